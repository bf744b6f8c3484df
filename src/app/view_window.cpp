// The --view window with SDL2 (built when CMake finds SDL2; view_window_none.cpp otherwise).
// Every SDL call is made on the window's own thread, which SDL allows on X11 and Wayland.
#include "app/view_window.h"

#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <thread>

#include "app/cli.h"
#include "app/sdl_leaks.h"
#include "app/view_controls.h"
#include "wavemmlt/error.h"

namespace wmlt {

namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kFrameInterval = std::chrono::milliseconds(250);  // frames asked of the render
constexpr auto kInteractiveFrameInterval = std::chrono::milliseconds(100);
constexpr int kEventWaitMs = 50;        // the loop's tick
constexpr int kInteractiveWaitMs = 10;  // (previews shown as they come)
constexpr float kExposureStep = 0.5f;   // stops per + or -

std::string format(const char* fmt, double a, double b = 0, double c = 0) {
    char buf[128];
    std::snprintf(buf, sizeof buf, fmt, a, b, c);
    return buf;
}

bool isSet(const char* name) {
    const char* v = std::getenv(name);
    return v && *v;
}

}  // namespace

void checkViewPossible(const char* option) {
    if (!isSet("DISPLAY") && !isSet("WAYLAND_DISPLAY"))
        throw InputError(std::string("wavemmlt: ") + option +
                         " needs a display, and neither DISPLAY nor WAYLAND_DISPLAY is set "
                         "(render without a window, or watch in tev with --display-server HOST:PORT)");
}

struct ViewWindow::Thread {
    ViewHub& hub;
    ViewWindowOptions opt;
    std::promise<std::string> opened;  // "" once the window is shown, else why it is not
    std::thread thread;

    SDL_Window* window = nullptr;
    SDL_Renderer* renderer = nullptr;
    SDL_Texture* texture = nullptr;
    std::shared_ptr<const Snapshot> shown;
    bool final = false;
    float exposure = 0, uploadedExposure = 0;
    int panelFrames = 0;           // frames still to draw after an event (the interactive panel)
    int mouseX = -1, mouseY = -1;  // image pixel under the mouse; -1: none
    Clock::time_point start = Clock::now();
    std::string title;
    // The interactive mode: attach() hands over the session; the window's thread makes the controls.
    std::mutex attachMutex;
    InteractiveSession* pending = nullptr;
    ControlsOptions pendingOptions;
    std::atomic<bool> attachPending{false}, closed{false};
    InteractiveSession* session = nullptr;
    std::unique_ptr<ViewControls> controls;

    Thread(ViewHub& h, ViewWindowOptions o) : hub(h), opt(std::move(o)), exposure(opt.exposure) {}

    bool open();
    void run();
    void takeSession();
    SDL_Rect imageRect() const;
    void close();
    void upload();
    void draw();
    std::string titleText() const;
    void updateTitle();
    void onKey(SDL_Keycode key);
    // ImGui 1.86 reads a key's state once a frame: a key pressed and released within one frame
    // (typing while a slow frame draws: Enter, Ctrl+A) would never be seen. So a frame takes
    // events up to a release whose press it took, or text after a click (the click first
    // activates the field); that event waits for the next frame.
    SDL_Event held;
    bool haveHeld = false, pressed = false, clicked = false;
    bool nextEvent(SDL_Event& e, bool wait) {
        NotLeakChecked notChecked;
        if (wait) pressed = clicked = false;  // a new frame
        if (wait && haveHeld) {
            e = held;
            haveHeld = false;
        } else if (!(wait ? SDL_WaitEventTimeout(&e, session ? kInteractiveWaitMs : kEventWaitMs) : SDL_PollEvent(&e))) return false;
        if (!controls) return true;
        const bool release = e.type == SDL_KEYUP || e.type == SDL_MOUSEBUTTONUP;
        if (((release && pressed) || (e.type == SDL_TEXTINPUT && clicked)) && !wait) {
            held = e;
            haveHeld = true;
            return false;
        }
        pressed |= e.type == SDL_KEYDOWN || e.type == SDL_MOUSEBUTTONDOWN;
        clicked |= e.type == SDL_MOUSEBUTTONDOWN || e.type == SDL_MOUSEBUTTONUP;
        return true;
    }
};

bool ViewWindow::Thread::open() {
    NotLeakChecked notChecked;
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");  // Ctrl-C stays wavemmlt's
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "nearest");
    SDL_SetHint(SDL_HINT_VIDEO_X11_NET_WM_BYPASS_COMPOSITOR, "0");
    SDL_SetHint(SDL_HINT_VIDEO_ALLOW_SCREENSAVER, "1");  // a long render need not keep the screen on
    // Only the display named by the environment: SDL would otherwise fall back to drivers
    // that show nothing (KMSDRM, offscreen) and the render would run in an unseen window.
    if (!isSet("SDL_VIDEODRIVER"))
        SDL_SetHint(SDL_HINT_VIDEODRIVER, isSet("DISPLAY") && isSet("WAYLAND_DISPLAY") ? "x11,wayland" : isSet("DISPLAY") ? "x11" : "wayland");
    if (SDL_Init(SDL_INIT_VIDEO) != 0) return false;
    // The image's size, enlarged by a whole factor when tiny, shrunk to fit the display.
    const int zoom = std::max(1, int(std::ceil(64.0 / std::max(opt.width, opt.height))));
    int w = opt.width * zoom, h = opt.height * zoom;
    SDL_Rect usable;
    if (SDL_GetDisplayUsableBounds(0, &usable) == 0 && usable.w > 0 && usable.h > 0) {
        const double s = std::min({1.0, 0.95 * usable.w / w, 0.95 * usable.h / h});
        w = std::max(1, int(w * s));
        h = std::max(1, int(h * s));
    }
    // Hidden and untitled until the renderer exists: SDL may replace the X window then (for
    // OpenGL), and whoever looks for the window by its title must find the one that stays.
    window = SDL_CreateWindow("", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, w, h, SDL_WINDOW_RESIZABLE | SDL_WINDOW_HIDDEN);
    if (!window) return false;
    renderer = SDL_CreateRenderer(window, -1, 0);
    if (!renderer) return false;
    updateTitle();
    SDL_ShowWindow(window);
    SDL_RenderSetLogicalSize(renderer, opt.width, opt.height);
    texture = SDL_CreateTexture(renderer, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, opt.width, opt.height);
    if (!texture) return false;
    draw();
    return true;
}

void ViewWindow::Thread::close() {
    NotLeakChecked notChecked;
    controls.reset();
    if (texture) SDL_DestroyTexture(texture);
    if (renderer) SDL_DestroyRenderer(renderer);
    if (window) SDL_DestroyWindow(window);
    SDL_Quit();
}

// The shown snapshot, tone-mapped as the PNG output is, into the texture.
void ViewWindow::Thread::upload() {
    if (!shown) return;
    uploadedExposure = controls ? controls->exposure() : exposure;
    const std::vector<unsigned char> bytes = toSrgb8(shown->image, uploadedExposure);
    NotLeakChecked notChecked;
    SDL_UpdateTexture(texture, nullptr, bytes.data(), opt.width * 3);
}

// Interactive: the image at the window's top left, as large as fits beside the panel (a
// whole factor when enlarged), its aspect ratio kept: the resolution gate.
SDL_Rect ViewWindow::Thread::imageRect() const {
    int W = 0, H = 0;
    SDL_GetWindowSize(window, &W, &H);
    const int areaW = std::max(1, W - (controls && controls->panelShown() ? kPanelWidth : 0));
    double scale = std::min(double(areaW) / opt.width, double(std::max(1, H)) / opt.height);
    if (scale >= 1) scale = std::floor(scale);
    return SDL_Rect{0, 0, std::max(1, int(opt.width * scale)), std::max(1, int(opt.height * scale))};
}

void ViewWindow::Thread::draw() {
    NotLeakChecked notChecked;
    SDL_SetRenderDrawColor(renderer, 40, 40, 40, 255);
    SDL_RenderClear(renderer);
    if (!controls) {
        if (shown) SDL_RenderCopy(renderer, texture, nullptr, nullptr);
        SDL_RenderPresent(renderer);
        return;
    }
    const SDL_Rect r = imageRect();
    if (shown) SDL_RenderCopy(renderer, texture, nullptr, &r);
    SDL_SetRenderDrawColor(renderer, 230, 200, 60, 255);  // the gate's edges
    SDL_RenderDrawLine(renderer, r.w, 0, r.w, r.h);
    SDL_RenderDrawLine(renderer, 0, r.h, r.w, r.h);
    controls->drawPanel(titleText());
    SDL_RenderPresent(renderer);
}

// The session main() attached (the window's thread): the panel's column added to the
// window, the image placed by imageRect from now on.
void ViewWindow::Thread::takeSession() {
    std::lock_guard<std::mutex> lock(attachMutex);
    attachPending = false;
    NotLeakChecked notChecked;
    session = pending;
    controls = std::make_unique<ViewControls>(window, renderer, *session, pendingOptions);
    SDL_RenderSetLogicalSize(renderer, 0, 0);
    int W = 0, H = 0, x = 0, y = 0;
    SDL_GetWindowSize(window, &W, &H);
    W += kPanelWidth, H = std::max(H, 480);
    SDL_SetWindowSize(window, W, H);
    // Moved back onto the display where the larger window would leave it (a small image's
    // window, centred, would put the panel's lower part below the screen).
    SDL_Rect usable;
    SDL_GetWindowPosition(window, &x, &y);
    if (SDL_GetDisplayUsableBounds(std::max(0, SDL_GetWindowDisplayIndex(window)), &usable) == 0)
        SDL_SetWindowPosition(window, std::max(usable.x, std::min(x, usable.x + usable.w - W)),
                              std::max(usable.y, std::min(y, usable.y + usable.h - H)));
    mouseX = mouseY = -1;
    upload();
}

std::string ViewWindow::Thread::titleText() const {
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    std::string t = "wavemmlt " + opt.tracer + ": ";
    if (session) {  // the tracer now, and the preview's figures while it runs
        t = std::string("wavemmlt interactive ") + tracerName(session->settings().tracer) + ": ";
        const std::string status = session->status();
        if (!status.empty()) return t + status;
    } else if (hub.interactiveRequested()) {
        return t + "switching to the interactive mode";
    }
    const double mrays = shown && shown->seconds > 0 ? double(shown->rays) / shown->seconds * 1e-6 : 0;
    if (final) t += format("done, %.0f spp in %.1f s, %.2f Mrays/s", double(shown->spp), shown->seconds, mrays);
    else
        t += format("%.0f%%, %.1f s", std::floor(hub.progress() * 100), session ? (shown ? shown->seconds : 0.0) : wall) +
             (shown ? format(", %.2f Mrays/s", mrays) : std::string(", preparing")) + (hub.paused() ? ", paused" : "");
    const float ev = controls ? controls->exposure() : exposure;
    if (ev != 0) t += format(", exposure %+.1f", ev);
    if (shown && mouseX >= 0 && mouseY >= 0 && mouseX < opt.width && mouseY < opt.height) {
        const Vec3 v = shown->image.at(mouseX, mouseY);
        t += format(" | (%.0f, %.0f)", mouseX, mouseY) + format(" %.4g %.4g %.4g", v.x, v.y, v.z);
    }
    return t;
}

void ViewWindow::Thread::updateTitle() {
    const std::string t = titleText();
    if (t != title) {
        title = t;
        NotLeakChecked notChecked;
        SDL_SetWindowTitle(window, title.c_str());
    }
}

void ViewWindow::Thread::onKey(SDL_Keycode key) {
    switch (key) {
        case SDLK_PLUS:
        case SDLK_EQUALS:
        case SDLK_KP_PLUS:  // '+' is shift + '=' on many layouts
            exposure += kExposureStep;
            break;
        case SDLK_MINUS:
        case SDLK_KP_MINUS: exposure -= kExposureStep; break;
        case SDLK_p:
            if (!final) hub.setPaused(!hub.paused());
            return;
        case SDLK_s:
            if (shown) opt.save(*shown, controls ? controls->exposure() : opt.exposure);
            return;
        case SDLK_q:
        case SDLK_ESCAPE: hub.cancel(); return;
        case SDLK_i:  // --view: on to the interactive mode (main() takes it from here)
            if (session || hub.interactiveRequested()) return;
            if (!opt.interactiveAllowed) {
                std::fprintf(stderr, "\nthe interactive mode needs one process (run without mpirun)\n");
                return;
            }
            hub.requestInteractive();
            return;
        default: return;
    }
    upload();
    draw();
}

void ViewWindow::Thread::run() {
    if (!open()) {
        const char* display = std::getenv(isSet("DISPLAY") ? "DISPLAY" : "WAYLAND_DISPLAY");
        opened.set_value(std::string("cannot open a window on display '") + (display ? display : "") + "': " + SDL_GetError());
        close();
        return;
    }
    opened.set_value("");
    uint64_t version = 0;
    auto lastRequest = Clock::now() - kFrameInterval;
    // Ends when the user closes the window or the render is cancelled (q, Ctrl-C); not while
    // main() switches to the interactive mode (it cancelled the render to).
    while (!hub.cancelled() || (hub.interactiveRequested() && !session)) {
        if (attachPending) takeSession();
        if (!final && Clock::now() - lastRequest >= (session ? kInteractiveFrameInterval : kFrameInterval)) {
            hub.requestFrame();
            lastRequest = Clock::now();
        }
        const ViewHub::Frame f = hub.latest();
        bool redraw = false;
        if (f.version != version && f.snapshot) {
            version = f.version;
            shown = f.snapshot;
            final = f.final;
            upload();
            redraw = true;
        }
        SDL_Event e;
        for (bool got = nextEvent(e, true); got; got = nextEvent(e, false)) {
            if (controls) {
                // The panel answers an event at ImGui's next frames (a click's release: the one after).
                panelFrames = 3;
                const SDL_Rect r = imageRect();
                if (e.type == SDL_MOUSEMOTION) {
                    mouseX = e.motion.x < r.w ? e.motion.x * opt.width / r.w : -1;
                    mouseY = e.motion.y < r.h ? e.motion.y * opt.height / r.h : -1;
                }
                if (controls->event(e, r)) {
                    if (e.type == SDL_KEYDOWN) upload();  // (exposure)
                    continue;
                }
                if (e.type == SDL_MOUSEMOTION) continue;
            }
            if (e.type == SDL_QUIT) hub.cancel();
            else if (e.type == SDL_KEYDOWN) onKey(e.key.keysym.sym);
            else if (e.type == SDL_MOUSEMOTION) mouseX = e.motion.x, mouseY = e.motion.y;
            else if (e.type == SDL_WINDOWEVENT && e.window.event == SDL_WINDOWEVENT_LEAVE) mouseX = mouseY = -1;
            else if (e.type == SDL_WINDOWEVENT) redraw = true;  // exposed, resized
        }
        if (controls && shown && controls->exposure() != uploadedExposure) {  // (set in the panel)
            upload();
            redraw = true;
        }
        if (panelFrames > 0) --panelFrames, redraw = true;
        if (redraw) draw();
        updateTitle();
    }
    close();
    closed = true;
}

ViewWindow::ViewWindow(ViewHub& hub, ViewWindowOptions options) {
    checkViewPossible(options.interactive ? "--interactive" : "--view");
    thread_ = std::make_unique<Thread>(hub, std::move(options));
    std::future<std::string> opened = thread_->opened.get_future();
    thread_->thread = std::thread([t = thread_.get()] { t->run(); });
    const std::string error = opened.get();
    if (!error.empty()) {
        thread_->thread.join();
        throw InputError(std::string("wavemmlt: ") + (thread_->opt.interactive ? "--interactive" : "--view") + ": " + error);
    }
}

ViewWindow::~ViewWindow() { waitClosed(); }

void ViewWindow::waitClosed() {
    if (thread_ && thread_->thread.joinable()) thread_->thread.join();
}

bool ViewWindow::waitClosedOrInteractive() {
    while (thread_ && !thread_->closed) {
        if (thread_->hub.interactiveRequested() && !thread_->session) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    waitClosed();
    return false;
}

void ViewWindow::attach(InteractiveSession& session, ControlsOptions options) {
    std::lock_guard<std::mutex> lock(thread_->attachMutex);
    thread_->pending = &session;
    thread_->pendingOptions = std::move(options);
    thread_->attachPending = true;
}

}  // namespace wmlt
