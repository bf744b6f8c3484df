// Where a render meets its viewers (the --view window, the --display-server sender). The
// render publishes a snapshot at a pass or round boundary when a viewer has asked for a
// frame; viewers ask about four times a second and read the newest snapshot. The render
// never waits on a viewer: it takes the lock only to swap a pointer, and only the newest
// snapshot is kept (a viewer that falls behind skips frames). Making a snapshot costs the
// render time (it runs on the render's thread), so frames are asked for at most as often as
// keeps that cost under 5% of the render's time (a large image is shown less often).
// After the render, main() publishes the final image as written (finish()), so the last
// frame equals the file.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>

#include "wavemmlt/render.h"

namespace wmlt {

class ViewHub : public RenderView {
public:
    struct Frame {
        uint64_t version = 0;  // 0: nothing published yet
        std::shared_ptr<const Snapshot> snapshot;
        bool final = false;  // the render's result, as written
    };

    // `cancel` is the render's cancel flag (also set by Ctrl-C).
    explicit ViewHub(std::atomic<bool>* cancel) : cancel_(cancel) {}

    // RenderView: the render's thread.
    bool wantsFrame() const override;
    void publish(Snapshot snapshot) override;
    double waitWhilePaused() override;

    // The viewers' side.
    void requestFrame() { frameWanted_ = true; }
    Frame latest() const;
    // The newest frame once it is newer than `version`, or after `timeout` whatever is newest.
    Frame waitNewer(uint64_t version, std::chrono::milliseconds timeout) const;
    void setPaused(bool paused);
    bool paused() const { return paused_; }
    // Stops the render as Ctrl-C does (a paused render resumes to stop).
    void cancel() { *cancel_ = true; }
    bool cancelled() const { return cancel_->load(); }
    // The i key of --view: the render stops (as cancel()) and main() goes on to the
    // interactive mode in the same window.
    void requestInteractive() {
        interactive_ = true;
        *cancel_ = true;
    }
    bool interactiveRequested() const { return interactive_; }
    // An interactive session renders into this hub: a final frame is not the last one (the
    // tev sender goes on streaming after it).
    void setSessionRunning(bool running) { session_ = running; }
    bool sessionRunning() const { return session_; }
    // The fraction done, as the progress callback last reported it.
    void setProgress(double fraction) { progress_ = fraction; }
    double progress() const { return progress_; }

    // The interactive mode's preview (not the render's; no frame asked for).
    void show(Snapshot snapshot) { store(std::move(snapshot), false); }

    // main(), after the outputs are written: the final frame.
    void finish(Snapshot snapshot) { store(std::move(snapshot), true); }

private:
    void store(Snapshot snapshot, bool final);

    using Clock = std::chrono::steady_clock;
    std::atomic<bool>* cancel_;
    // wantsFrame() said yes at askedAt_; no frame is made before notBefore_.
    mutable Clock::time_point askedAt_;
    Clock::time_point notBefore_;
    std::atomic<bool> frameWanted_{false}, paused_{false}, interactive_{false}, session_{false};
    std::atomic<double> progress_{0};
    mutable std::mutex mutex_;
    mutable std::condition_variable changed_;
    Frame frame_;
};

}  // namespace wmlt
