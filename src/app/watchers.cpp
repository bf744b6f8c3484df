#include "app/watchers.h"

namespace wmlt {

Watchers::Watchers(const CommandLine& cl, const std::string& tracer, int width, int height, const std::string& imageName, std::atomic<bool>* cancel,
                   std::function<void(const Snapshot&, float)> save, bool interactiveAllowed) {
    if (!cl.view && !cl.interactive && cl.displayHost.empty()) return;
    hub_ = std::make_unique<ViewHub>(cancel);
    if (!cl.displayHost.empty()) sender_ = std::make_unique<TevSender>(*hub_, cl.displayHost, cl.displayPort, imageName, cl.quiet);
    if (cl.view || cl.interactive)
        window_ =
            std::make_unique<ViewWindow>(*hub_, ViewWindowOptions{tracer, width, height, cl.exposure, save, cl.interactive, interactiveAllowed});
}

Watchers::~Watchers() {
    if (hub_ && window_) hub_->cancel();  // the window closes at once
}

bool Watchers::finish(const RenderResult& r) {
    if (!hub_) return false;
    const double fraction = r.stats.cancelled ? hub_->progress() : 1.0;
    hub_->finish(Snapshot{r.image, fraction, r.stats.seconds, r.stats.spp, r.stats.raysIntersect + r.stats.raysOccluded});
    if (sender_) sender_->waitFinalSent();
    return window_ && window_->waitClosedOrInteractive();
}

}  // namespace wmlt
