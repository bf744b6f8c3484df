#include "app/interactive.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/cli.h"
#include "kernels/camera.h"
#include "stages/core/trace.h"
#include "stages/render_scene.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kStill = std::chrono::milliseconds(150);  // a gesture has ended after this long without change
constexpr double kPreviewSeconds = 0.04;                 // the preview's aim: 25 frames a second
constexpr int kMaxPreviewScale = 8;

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}
std::string triple(Vec3 v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }
bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool same(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool sameCamera(const CameraDesc& a, const CameraDesc& b) {
    return same(a.position, b.position) && same(a.lookAt, b.lookAt) && same(a.up, b.up) && a.fovDegrees == b.fovDegrees && a.dof == b.dof &&
           a.focalLength == b.focalLength && a.fStop == b.fStop;  // (what the session changes)
}

// The image at `scale` times its size, each pixel repeated (the preview, shown in the window).
Image enlarged(const Image& small, int width, int height) {
    Image out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            out.set(x, y, small.at(std::min(small.width - 1, x * small.width / width), std::min(small.height - 1, y * small.height / height)));
    return out;
}

}  // namespace

ViewSettings viewSettingsOf(const CameraDesc& camera, const RenderOptions& o, float exposure) {
    ViewSettings s;
    s.camera = camera;
    s.tracer = o.tracer;
    s.minPathLength = o.minPathLength;
    s.maxPathLength = o.maxPathLength;
    s.probLarge = o.probLarge;
    s.chains = o.chains;
    s.misBeta = o.misBeta;
    s.exposure = exposure;
    return s;
}

void applyViewSettings(const ViewSettings& s, RenderOptions& o) {
    o.tracer = s.tracer;
    o.minPathLength = s.minPathLength;
    o.maxPathLength = s.maxPathLength;
    o.probLarge = s.probLarge;
    o.chains = s.chains;
    o.misBeta = s.misBeta;
}

std::string checkViewSettings(const ViewSettings& s) {
    const CameraDesc& c = s.camera;
    if (!finite(c.position) || !finite(c.lookAt) || !finite(c.up)) return "the camera's position, LookAt and Up must be finite";
    if (length(c.lookAt - c.position) <= 0) return "the camera's position and LookAt must differ";
    if (length(cross(c.lookAt - c.position, c.up)) <= 0) return "the camera's Up must not be parallel to its view";
    if (!(c.fovDegrees >= 1 && c.fovDegrees <= 170)) return "FOV must be in [1, 170] degrees";
    if (c.dof && !(c.fStop > 0 && c.focalLength > 0 && std::isfinite(c.focalLength / c.fStop)))
        return "the aperture must not be negative, and the focus distance must be positive";
    if (s.minPathLength < 1 || s.maxPathLength > kMaxPathLength) return "path lengths must be in [1, " + std::to_string(kMaxPathLength) + "]";
    if (s.maxPathLength < s.minPathLength)
        return "MaxPathLength " + std::to_string(s.maxPathLength) + " is less than MinPathLength " + std::to_string(s.minPathLength);
    if (!(s.probLarge > 0 && s.probLarge <= 1)) return "ProbLarge must be in (0, 1]";
    if (s.chains < 0) return "chains must be positive (0: auto)";
    if (!misBetaValid(s.misBeta)) return kMisBetaRange;
    if (!(s.exposure >= -64 && s.exposure <= 64)) return "exposure must be in [-64, 64] stops";
    return "";
}

std::string commandLineFor(const std::string& scenePath, const ViewSettings& s, const RenderOptions& base, int width, int height,
                           const std::vector<std::string>& outputs) {
    const CameraDesc& c = s.camera;
    std::string cmd = "wavemmlt";
    if (!scenePath.empty()) cmd += " '" + scenePath + "'";
    cmd += std::string(" --tracer ") + tracerName(s.tracer);
    cmd += " --eye " + triple(c.position) + " --look-at " + triple(c.lookAt) + " --up " + triple(c.up) + " --fov " + number(c.fovDegrees);
    cmd += " --focus-distance " + number(c.focalLength) + " --f-stop " + (c.dof ? number(c.fStop) : "0");
    cmd += " --min-length " + std::to_string(s.minPathLength) + " --max-length " + std::to_string(s.maxPathLength);
    const bool metropolis = s.tracer == TracerKind::MMLT || s.tracer == TracerKind::PSSMLT;
    if (metropolis) cmd += " --p-large " + number(s.probLarge) + " --chains " + (s.chains ? std::to_string(s.chains) : "auto");
    if ((metropolis || s.tracer == TracerKind::BPT) && s.misBeta != 0) cmd += " --mis-beta " + number(s.misBeta);
    cmd += " --width " + std::to_string(width) + " --height " + std::to_string(height);
    cmd += base.timeBudget > 0 ? " --time " + number(base.timeBudget) : " --spp " + std::to_string(base.spp);
    cmd += " --seed " + std::to_string(base.seed);
    if (s.exposure != 0) cmd += " --exposure " + number(s.exposure);
    for (const std::string& o : outputs) cmd += " -o '" + o + "'";
    return cmd;
}

InteractiveSession::InteractiveSession(std::unique_ptr<Scene> scene, RenderOptions base, ViewSettings initial, ViewHub& hub)
    : scene_(std::move(scene)), base_(std::move(base)), hub_(hub), settings_(std::move(initial)) {
    width_ = scene_->camera.width;
    height_ = scene_->camera.height;
    // A first guess of the preview's scale: about 160 x 120 pixels; each preview adjusts it.
    previewScale_ = std::clamp(int(std::sqrt(double(width_) * height_ / (160.0 * 120.0))), 1, kMaxPreviewScale);
    lastMove_ = Clock::now() - kStill;
    thread_ = std::thread([this] { loop(); });
}

InteractiveSession::~InteractiveSession() { stop(); }

void InteractiveSession::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        restart_ = true;
    }
    changed_.notify_all();
    hub_.setPaused(false);
    if (thread_.joinable()) thread_.join();
}

ViewSettings InteractiveSession::settings() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return settings_;
}

std::string InteractiveSession::status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
}

void InteractiveSession::setStatus(std::string s) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_ = std::move(s);
}

std::string InteractiveSession::change(const ViewSettings& next, bool moving) {
    std::string problem = checkViewSettings(next);
    if (problem.empty() && next.tracer == TracerKind::LT && scene_->features.emissiveMedia)
        problem = "the light tracer cannot render an emitting medium (docs/media.md)";
    std::unique_lock<std::mutex> lock(mutex_);
    if (problem.empty()) try {
            scene_->checkCameraAt(next.camera.position);
        } catch (const InputError& e) {
            problem = e.what();
        }
    if (!problem.empty()) return problem;
    ViewSettings shown = settings_;
    shown.exposure = next.exposure;
    const bool sameRender = sameCamera(shown.camera, next.camera) && shown.tracer == next.tracer && shown.minPathLength == next.minPathLength &&
                            shown.maxPathLength == next.maxPathLength && shown.probLarge == next.probLarge && shown.chains == next.chains &&
                            shown.misBeta == next.misBeta;
    settings_ = next;
    if (sameRender) return "";  // the exposure is the display's: no restart
    ++generation_;
    if (moving) lastMove_ = Clock::now();
    restart_ = true;
    lock.unlock();
    changed_.notify_all();
    hub_.setPaused(false);  // a paused render resumes with the change
    return "";
}

void InteractiveSession::endGesture() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        lastMove_ = Clock::now() - kStill;
    }
    changed_.notify_all();
}

std::optional<float> InteractiveSession::depthAt(float fx, float fy) const {
    const ViewSettings s = settings();
    CameraDesc pinhole = s.camera;
    pinhole.dof = false;
    const Camera cam = makeCamera(pinhole, width_, height_);
    Vec3 o, d;
    generateCameraRay(cam, fx * float(width_), fy * float(height_), 0.5f, 0.5f, o, d);
    RTCRayHit rh;
    setRayHit(rh, o, d);
    traceClosest(scene_->rtc, &rh, 1, false);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    return rh.ray.tfar * dot(d, cam.forward);
}

void InteractiveSession::loop() {
    uint64_t previewed = 0, rendered = 0;
    while (true) {
        ViewSettings s;
        uint64_t generation = 0;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            auto still = [&] { return Clock::now() - lastMove_ >= kStill; };
            changed_.wait_for(lock, std::chrono::milliseconds(20),
                              [&] { return stop_ || generation_ != previewed || (generation_ != rendered && still()); });
            if (stop_) return;
            if (generation_ == previewed && !(generation_ != rendered && still())) continue;
            s = settings_;
            generation = generation_;
            restart_ = false;
        }
        if (generation != previewed) {  // every change is shown at once
            renderPreview(s, generation);
            previewed = generation;
        } else {
            renderFull(s, generation);
            rendered = generation;
        }
    }
}

void InteractiveSession::renderPreview(const ViewSettings& s, uint64_t generation) {
    const int w = std::max(1, width_ / previewScale_), h = std::max(1, height_ / previewScale_);
    RenderOptions opt = base_;
    opt.tracer = TracerKind::PT;
    opt.spp = 1;
    opt.strataPerAxis = 1;
    opt.timeBudget = 0;
    opt.seed = base_.seed + generation;
    opt.minPathLength = s.minPathLength;
    opt.maxPathLength = s.maxPathLength;
    // Not stopped by the next change: a preview a step behind the mouse is shown, where
    // restarting each one as the next step comes would show none while the mouse moves.
    opt.cancel = &stop_;
    opt.view = nullptr;
    opt.progress = nullptr;
    opt.notice = nullptr;
    opt.ranks = nullptr;
    const auto start = Clock::now();
    try {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            scene_->setView(s.camera, w, h);
        }
        const RenderResult r = renderScene(*scene_, opt);
        if (r.stats.cancelled) return;
        Snapshot shot{enlarged(r.image, width_, height_), 0, r.stats.seconds, 1, r.stats.raysIntersect + r.stats.raysOccluded};
        hub_.show(std::move(shot));
    } catch (const std::exception& e) {
        setStatus(std::string("error: ") + e.what());
        return;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    char text[96];
    std::snprintf(text, sizeof text, "preview at 1/%d size, %.0f fps", previewScale_, 1 / std::max(seconds, 1e-3));
    setStatus(text);
    // The next preview's scale: its time goes with its pixel count.
    if (seconds > 1.5 * kPreviewSeconds && previewScale_ < kMaxPreviewScale) ++previewScale_;
    else if (seconds < 0.4 * kPreviewSeconds && previewScale_ > 1) --previewScale_;
}

void InteractiveSession::renderFull(const ViewSettings& s, uint64_t generation) {
    RenderOptions opt = base_;
    applyViewSettings(s, opt);
    opt.cancel = &restart_;
    opt.view = &hub_;
    opt.progress = [this](double f) { hub_.setProgress(f); };
    opt.notice = nullptr;
    opt.ranks = nullptr;
    setStatus("");
    hub_.setProgress(0);
    try {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            scene_->setView(s.camera, width_, height_);
        }
        const RenderResult r = renderScene(*scene_, opt);
        if (r.stats.cancelled) return;
        std::lock_guard<std::mutex> lock(mutex_);  // (a change since: not shown)
        if (generation_ != generation) return;
        hub_.setProgress(1);
        hub_.finish(Snapshot{r.image, 1, r.stats.seconds, r.stats.spp, r.stats.raysIntersect + r.stats.raysOccluded});
    } catch (const std::exception& e) {
        setStatus(std::string("error: ") + e.what());
        std::fprintf(stderr, "error: %s\n", e.what());
    }
}

}  // namespace wmlt
