#include "app/view_hub.h"

namespace wmlt {

namespace {
constexpr double kMaxShareOfRenderTime = 0.05;  // making snapshots
}

bool ViewHub::wantsFrame() const {
    if (!frameWanted_.load(std::memory_order_relaxed)) return false;
    const Clock::time_point now = Clock::now();
    if (now < notBefore_) return false;
    askedAt_ = now;
    return true;
}

void ViewHub::publish(Snapshot snapshot) {
    // What this snapshot cost the render, and the wait that keeps that a small share.
    const Clock::time_point now = Clock::now();
    notBefore_ = now + (now - askedAt_) * int(1 / kMaxShareOfRenderTime - 1);
    store(std::move(snapshot), false);
}

void ViewHub::store(Snapshot snapshot, bool final) {
    auto shared = std::make_shared<const Snapshot>(std::move(snapshot));
    {
        std::lock_guard<std::mutex> lock(mutex_);
        frame_.snapshot = std::move(shared);
        frame_.final = final;
        ++frame_.version;
        frameWanted_ = false;
    }
    changed_.notify_all();
}

ViewHub::Frame ViewHub::latest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return frame_;
}

ViewHub::Frame ViewHub::waitNewer(uint64_t version, std::chrono::milliseconds timeout) const {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait_for(lock, timeout, [&] { return frame_.version > version; });
    return frame_;
}

void ViewHub::setPaused(bool paused) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        paused_ = paused;
    }
    changed_.notify_all();
}

double ViewHub::waitWhilePaused() {
    if (!paused_) return 0;
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_);
    // Ctrl-C sets the cancel flag from a signal handler, which cannot notify: look every 50 ms.
    while (paused_ && !cancel_->load()) changed_.wait_for(lock, std::chrono::milliseconds(50));
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace wmlt
