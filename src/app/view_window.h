// The --view window (SDL2): the newest snapshot of the render, tone-mapped as the PNG
// output is (toSrgb8), on a thread of its own. Keys: + / - exposure by half a stop, s
// writes the outputs now (the image shown), p pauses and resumes the render, q / Esc /
// closing the window stops the render as Ctrl-C does. The title shows the tracer, the
// progress, the time, Mrays/s and the value of the pixel under the mouse.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "app/view_hub.h"
#include "wavemmlt/image.h"

namespace wmlt {

struct ViewWindowOptions {
    std::string tracer;
    int width = 0, height = 0;                     // the image's size
    float exposure = 0;                            // the PNG's --exposure: the initial one
    std::function<void(const Snapshot&)> save;     // the s key: writes the outputs
};

// Throws InputError (exit status 2) when --view cannot work here: a build without SDL2,
// or neither DISPLAY nor WAYLAND_DISPLAY set. Cheap: called before the scene is loaded.
void checkViewPossible();

class ViewWindow {
public:
    // Opens the window and returns once it is shown. Throws InputError (exit status 2)
    // when it cannot (checkViewPossible's reasons, or SDL's).
    ViewWindow(ViewHub& hub, ViewWindowOptions options);
    ~ViewWindow();  // waits for the window to close
    // Returns once the window is closed: by the user, or at once when the render was cancelled.
    void waitClosed();

private:
    struct Thread;
    std::unique_ptr<Thread> thread_;
};

}  // namespace wmlt
