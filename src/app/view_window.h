// The --view window (SDL2): the newest snapshot of the render, tone-mapped as the PNG
// output is (toSrgb8), on a thread of its own. Keys: + / - exposure by half a stop, s
// writes the outputs now (the image shown), p pauses and resumes the render, q / Esc /
// closing the window stops the render as Ctrl-C does. The title shows the tracer, the
// progress, the time, Mrays/s and the value of the pixel under the mouse. i switches to the
// interactive mode (main() builds the session and attaches it; view_controls.h).
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "app/view_hub.h"

#if WAVEMMLT_HAVE_VIEW
#include "app/view_controls.h"
#else
#include "app/camera_control.h"
#include "app/interactive.h"
namespace wmlt {
struct ControlsOptions {
    std::function<std::string(const ViewSettings&)> keep, commandLine;
    float orbitRate = kOrbitRateDefault;
};
}  // namespace wmlt
#endif
#include "wavemmlt/image.h"

namespace wmlt {

struct ViewWindowOptions {
    std::string tracer;
    int width = 0, height = 0;  // the image's size
    float exposure = 0;         // the PNG's --exposure: the initial one
    // The s key: writes the outputs (PNG with this exposure: --exposure, or the interactive one).
    std::function<void(const Snapshot&, float exposure)> save;
    bool interactive = false;        // --interactive (its name in messages)
    bool interactiveAllowed = true;  // the i key may switch (not under mpirun)
};

// Throws InputError (exit status 2) when --view cannot work here: a build without SDL2,
// or neither DISPLAY nor WAYLAND_DISPLAY set. Cheap: called before the scene is loaded.
void checkViewPossible(const char* option = "--view");

class ViewWindow {
public:
    // Opens the window and returns once it is shown. Throws InputError (exit status 2)
    // when it cannot (checkViewPossible's reasons, or SDL's).
    ViewWindow(ViewHub& hub, ViewWindowOptions options);
    ~ViewWindow();  // waits for the window to close
    // Returns once the window is closed: by the user, or at once when the render was cancelled.
    void waitClosed();
    // As waitClosed, but returns true as soon as the user asked for the interactive mode (i).
    bool waitClosedOrInteractive();
    // The interactive mode from now on: the window shows the panel and drives the session
    // (which must outlive the window's thread: waitClosed() before it goes).
    void attach(InteractiveSession& session, ControlsOptions options);

private:
    struct Thread;
    std::unique_ptr<Thread> thread_;
};

}  // namespace wmlt
