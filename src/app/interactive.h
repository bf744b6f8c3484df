// The interactive mode (--interactive, or the i key in --view; issue 28): one scene built
// once and rendered again whenever the camera or a setting changes. While the user moves,
// a preview (the path tracer, one sample per pixel, at a reduced resolution chosen to keep
// about 25 frames a second) follows each gesture; once still, the chosen tracer renders with
// the command line's --spp or --time, its progress shown as --view shows it. The window
// (view_window.cpp) changes the settings; this session renders them on a thread of its own.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "app/view_hub.h"
#include "scene/scene.h"
#include "wavemmlt/render.h"

namespace wmlt {

// What the user can change, and the values the render starts from.
struct ViewSettings {
    CameraDesc camera;
    TracerKind tracer = TracerKind::MMLT;
    int minPathLength = 1, maxPathLength = 10;
    float probLarge = 0.3f;  // MMLT, (0, 1]
    int chains = 0;          // MMLT, 0: auto
    float misBeta = 0;       // BPT, MMLT and PSSMLT, [0.5, 16]; 0: the tracer's own (misBetaOf)
    float exposure = 0;      // the display's and the PNG's, in stops
};

// The settings a render with these options and this camera has (what a session starts
// from), and those settings written back over options (what it renders).
ViewSettings viewSettingsOf(const CameraDesc& camera, const RenderOptions& o, float exposure = 0);
void applyViewSettings(const ViewSettings& s, RenderOptions& o);

// "" when the settings can be rendered, else what is wrong with them (one line, for the
// panel and stderr): ProbLarge outside (0, 1], MaxPathLength < MinPathLength, a negative
// aperture, a field of view outside [1, 170] degrees, ...
std::string checkViewSettings(const ViewSettings& s);

// The command line that renders `s` as the session does (the scene, the camera, the
// settings, the budget and the outputs), with 9 significant digits (the same floats).
std::string commandLineFor(const std::string& scenePath, const ViewSettings& s, const RenderOptions& base, int width, int height,
                           const std::vector<std::string>& outputs);

class InteractiveSession {
public:
    // base: the command line's render options (spp or time, seed, threads); the settings
    // replace its tracer, path lengths, ProbLarge, chains and MIS exponent.
    InteractiveSession(std::unique_ptr<Scene> scene, RenderOptions base, ViewSettings initial, ViewHub& hub);
    ~InteractiveSession();  // stop()

    ViewSettings settings() const;
    // Applies `next` and restarts the render: "" then; else the problem, and the settings
    // stay as they were. moving: part of a gesture (the preview runs until it is still).
    std::string change(const ViewSettings& next, bool moving);
    // The gesture is over (the mouse button released): the tracer starts now, without the
    // wait for stillness that a key held down needs.
    void endGesture();
    // The distance along the camera's view direction to the surface seen at film point
    // (fx, fy) in [0, 1)^2 (from the top left), the pinhole's ray; none when it meets nothing.
    std::optional<float> depthAt(float fx, float fy) const;
    // What the title shows: "preview 1/3 resolution, 31 fps" or "" while the tracer renders.
    std::string status() const;
    // The renders' thread ends (the render running is cancelled).
    void stop();

private:
    void loop();
    void renderPreview(const ViewSettings& s, uint64_t generation);
    void renderFull(const ViewSettings& s, uint64_t generation);
    void setStatus(std::string s);

    using Clock = std::chrono::steady_clock;
    std::unique_ptr<Scene> scene_;
    RenderOptions base_;
    ViewHub& hub_;
    int width_, height_;    // the full image's
    int previewScale_ = 4;  // the preview renders 1 / previewScale_ of the width and height

    mutable std::mutex mutex_;
    std::condition_variable changed_;
    ViewSettings settings_;
    uint64_t generation_ = 1;  // counts changes
    Clock::time_point lastMove_;
    std::string status_;
    std::atomic<bool> restart_{false}, stop_{false};
    std::thread thread_;
};

}  // namespace wmlt
