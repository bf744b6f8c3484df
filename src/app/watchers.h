// The viewers of one render, set up before it and closed after it: the --view window and
// the --display-server sender, both fed by one ViewHub.
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "app/cli.h"
#include "app/tev_sender.h"
#include "app/view_hub.h"
#include "app/view_window.h"

namespace wmlt {

class Watchers {
public:
    // Opens the window (before the scene is built) and resolves the display server: throws
    // InputError (exit status 2) when either cannot be. `save` writes the outputs (the s key).
    // interactiveAllowed: the i key may switch to the interactive mode (one process).
    Watchers(const CommandLine& cl, const std::string& tracer, int width, int height, const std::string& imageName, std::atomic<bool>* cancel,
             std::function<void(const Snapshot&, float)> save, bool interactiveAllowed);
    // Without finish() (an error ended the render): closes the window without waiting.
    ~Watchers();

    RenderView* view() { return hub_.get(); }  // nullptr without --view and --display-server
    void progress(double fraction) {
        if (hub_) hub_->setProgress(fraction);
    }
    // After the outputs are written: shows the render's image, as written. Returns once tev
    // has it (or it is given up on) and the window is closed: by the user after a complete
    // render, at once after a cancelled one; or true as soon as the user asks for the
    // interactive mode (the i key).
    bool finish(const RenderResult& result);
    // The interactive mode's end: returns once tev has the final frame (or it is given up on).
    void waitFinalSent() {
        if (sender_) sender_->waitFinalSent();
    }
    bool interactiveRequested() const { return hub_ && hub_->interactiveRequested(); }
    ViewHub* hub() { return hub_.get(); }
    ViewWindow* window() { return window_.get(); }

private:
    std::unique_ptr<ViewHub> hub_;
    std::unique_ptr<ViewWindow> window_;
    std::unique_ptr<TevSender> sender_;
};

}  // namespace wmlt
