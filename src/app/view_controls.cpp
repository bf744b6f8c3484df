// The interactive controls (view_controls.h). The panel is Dear ImGui from Debian's
// libimgui-dev with its SDL2 platform backend (events, keys, the mouse); Debian's library
// has no SDL_Renderer drawing backend, so drawPanel draws ImGui's triangle lists itself with
// SDL_RenderGeometryRaw (SDL 2.0.18), into the window's existing renderer.
#include "app/view_controls.h"

#include <backends/imgui_impl_sdl.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "app/camera_control.h"
#include "app/cli.h"
#include "app/sdl_leaks.h"

namespace wmlt {

namespace {

constexpr float kFlyStep = 0.05f;    // of the distance to LookAt, per key press
constexpr float kWheelDolly = 0.1f;  // per wheel notch

std::string number(double v, const char* fmt = "%.6g") {
    char buf[48];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

// A whole number or a number, all of `text`; false when it is not one.
bool parseNumber(const std::string& text, double& v) {
    char* end = nullptr;
    v = std::strtod(text.c_str(), &end);
    while (end && *end == ' ') ++end;
    return !text.empty() && end && *end == '\0' && std::isfinite(v);
}

float apertureOf(const CameraDesc& c) { return c.dof ? c.focalLength / (2 * c.fStop) : 0.0f; }

// The thin lens with aperture radius r at the camera's focus distance (r = 0: a pinhole).
CameraDesc withAperture(CameraDesc c, float r) {
    c.dof = r > 0;
    if (c.dof) c.fStop = c.focalLength / (2 * r);
    return c;
}

// The panel's status: the title's progress (its "wavemmlt interactive <tracer>: ", which the
// window's title and the tracer's button show, left off) wrapped to the panel's width in two
// lines, whatever it says, so that the widgets below stay where they are; a longer text (an
// error) ends in "..." and shows whole in a tooltip. Returns the text's rectangle.
SDL_Rect statusLines(std::string text) {
    if (text.compare(0, 9, "wavemmlt ") == 0 && text.find(": ") != std::string::npos) text.erase(0, text.find(": ") + 2);
    const float wrap = ImGui::GetContentRegionAvail().x, lines = 2 * ImGui::GetTextLineHeight();
    auto height = [&](const std::string& t) { return ImGui::CalcTextSize(t.c_str(), nullptr, false, wrap).y; };
    std::string shown = text;
    if (height(text) > lines + 0.5f) {
        do shown.pop_back();
        while (!shown.empty() && height(shown + "...") > lines + 0.5f);
        shown += "...";
    }
    ImGui::BeginChild("status", ImVec2(0, lines), false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    ImGui::TextWrapped("%s", shown.c_str());  // (at the child's right edge: the panel's content width)
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    if (shown != text && ImGui::IsWindowHovered()) {  // (wrapped too: a tooltip stays in the window)
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(wrap);
        ImGui::TextUnformatted(text.c_str());
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
    ImGui::EndChild();
    return SDL_Rect{int(a.x), int(a.y), int(b.x - a.x), int(b.y - a.y)};
}

// ImGui's triangle lists drawn with the SDL renderer: each command clipped to its rectangle.
void renderDrawData(SDL_Renderer* renderer, const ImDrawData* data) {
    for (int n = 0; n < data->CmdListsCount; ++n) {
        const ImDrawList* list = data->CmdLists[n];
        const ImDrawVert* v = list->VtxBuffer.Data;
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) continue;
            const ImVec2 o = data->DisplayPos;
            const SDL_Rect clip{int(cmd.ClipRect.x - o.x), int(cmd.ClipRect.y - o.y), int(cmd.ClipRect.z - cmd.ClipRect.x),
                                int(cmd.ClipRect.w - cmd.ClipRect.y)};
            if (clip.w <= 0 || clip.h <= 0) continue;
            SDL_RenderSetClipRect(renderer, &clip);
            const ImDrawVert* first = v + cmd.VtxOffset;
            // ImDrawVert's colour is 4 bytes R, G, B, A in memory: SDL_Color's layout.
            SDL_RenderGeometryRaw(renderer, static_cast<SDL_Texture*>(cmd.GetTexID()), &first->pos.x, sizeof(ImDrawVert),
                                  reinterpret_cast<const SDL_Color*>(&first->col), sizeof(ImDrawVert), &first->uv.x, sizeof(ImDrawVert),
                                  list->VtxBuffer.Size - int(cmd.VtxOffset), list->IdxBuffer.Data + cmd.IdxOffset, int(cmd.ElemCount),
                                  sizeof(ImDrawIdx));
        }
    }
    SDL_RenderSetClipRect(renderer, nullptr);
}

}  // namespace

ViewControls::ViewControls(SDL_Window* window, SDL_Renderer* renderer, InteractiveSession& session, ControlsOptions options)
    : window_(window), renderer_(renderer), session_(session), opt_(std::move(options)), orbitRate_(opt_.orbitRate) {
    NotLeakChecked notChecked;
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini written into the user's folder
    ImGui::StyleColorsDark();
    ImGui_ImplSDL2_InitForSDLRenderer(window_);
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    font_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC, w, h);
    if (font_) {
        SDL_UpdateTexture(font_, nullptr, pixels, 4 * w);
        SDL_SetTextureBlendMode(font_, SDL_BLENDMODE_BLEND);
    }
    io.Fonts->SetTexID(font_);
    if (const char* p = std::getenv("WAVEMMLT_PANEL_LAYOUT")) layoutPath_ = p;
}

ViewControls::~ViewControls() {
    NotLeakChecked notChecked;
    ImGui_ImplSDL2_Shutdown();
    ImGui::DestroyContext();
    if (font_) SDL_DestroyTexture(font_);
}

void ViewControls::say(const std::string& message, bool error) {
    message_ = message;
    messageIsError_ = error;
    std::fprintf(stderr, "%s%s\n", error ? "refused: " : "", message.c_str());
}

// The c key: printed on stdout and put on the clipboard.
void ViewControls::copyCommandLine(const ViewSettings& s) {
    const std::string cmd = opt_.commandLine(s);
    NotLeakChecked notChecked;
    SDL_SetClipboardText(cmd.c_str());
    say("printed the command line that renders this view, and copied it", false);
}

void ViewControls::apply(const ViewSettings& next, bool moving) {
    const std::string problem = session_.change(next, moving);
    if (!problem.empty()) say(problem, true);
    else if (!moving && messageIsError_) message_.clear();
}

void ViewControls::focusAt(int x, int y, const SDL_Rect& image) {
    const std::optional<float> d = session_.depthAt(float(x - image.x) / float(image.w), float(y - image.y) / float(image.h));
    if (!d || !(*d > 0)) return say("nothing under the mouse to focus on", true);
    ViewSettings s = session_.settings();
    const float r = apertureOf(s.camera);
    s.camera.focalLength = *d;
    s.camera = withAperture(s.camera, r);
    apply(s, false);
    if (!messageIsError_) say("focus distance " + number(*d), false);
}

// The orbit's pivot, from the eye along the view: the surface under the image's centre;
// none there, the thin lens' focus distance; else LookAt's distance.
float ViewControls::pivotDistance(const CameraDesc& c) const {
    const std::optional<float> d = session_.depthAt(0.5f, 0.5f);
    if (d && *d > 0) return *d;
    return c.dof ? c.focalLength : cameraFrame(c).distance;
}

bool ViewControls::key(SDL_Keycode k, Uint16 mod, const SDL_Rect& image) {
    ViewSettings s = session_.settings();
    const float step = kFlyStep * cameraFrame(s.camera).distance;
    switch (k) {
        case SDLK_LEFT: s.camera = fly(s.camera, {-step, 0, 0}); break;
        case SDLK_RIGHT: s.camera = fly(s.camera, {step, 0, 0}); break;
        case SDLK_UP: s.camera = fly(s.camera, {0, 0, step}); break;
        case SDLK_DOWN: s.camera = fly(s.camera, {0, 0, -step}); break;
        case SDLK_PAGEUP: s.camera = fly(s.camera, {0, step, 0}); break;
        case SDLK_PAGEDOWN: s.camera = fly(s.camera, {0, -step, 0}); break;
        case SDLK_t: s.tracer = TracerKind((int(s.tracer) + ((mod & KMOD_SHIFT) ? 4 : 1)) % 5); break;
        case SDLK_RIGHTBRACKET: ++s.maxPathLength; break;
        case SDLK_LEFTBRACKET: --s.maxPathLength; break;
        case SDLK_PERIOD: ++s.minPathLength; break;
        case SDLK_COMMA: --s.minPathLength; break;
        case SDLK_PLUS:
        case SDLK_EQUALS:
        case SDLK_KP_PLUS: s.exposure += 0.5f; break;
        case SDLK_MINUS:
        case SDLK_KP_MINUS: s.exposure -= 0.5f; break;
        case SDLK_f:
            if (mouseX_ >= 0) focusAt(mouseX_, mouseY_, image);
            return true;
        case SDLK_w: say(opt_.keep(s), false); return true;
        case SDLK_c: copyCommandLine(s); return true;
        case SDLK_TAB: shown_ = !shown_; return true;
        default: return false;  // the window's keys (s, p, q, Esc)
    }
    const bool moving = k == SDLK_LEFT || k == SDLK_RIGHT || k == SDLK_UP || k == SDLK_DOWN || k == SDLK_PAGEUP || k == SDLK_PAGEDOWN;
    apply(s, moving);
    return true;
}

bool ViewControls::event(const SDL_Event& e, const SDL_Rect& image) {
    {
        NotLeakChecked notChecked;
        ImGui_ImplSDL2_ProcessEvent(&e);
    }
    const ImGuiIO& io = ImGui::GetIO();
    auto inImage = [&](int x, int y) { return x >= image.x && y >= image.y && x < image.x + image.w && y < image.y + image.h; };
    switch (e.type) {
        // (The image and the panel do not overlap: a mouse event on the image is the camera's.)
        case SDL_MOUSEBUTTONDOWN: {
            if (!inImage(e.button.x, e.button.y)) return true;
            const Uint16 mod = SDL_GetModState();
            focusClick_ = e.button.button == SDL_BUTTON_LEFT && (mod & KMOD_CTRL);
            drag_ = e.button.button == SDL_BUTTON_RIGHT || (e.button.button == SDL_BUTTON_LEFT && (mod & KMOD_SHIFT)) ? Drag::Pan
                    : e.button.button == SDL_BUTTON_MIDDLE                                                            ? Drag::Dolly
                    : e.button.button == SDL_BUTTON_LEFT && !focusClick_                                              ? Drag::Orbit
                                                                                                                      : Drag::None;
            pressX_ = e.button.x;
            pressY_ = e.button.y;
            moved_ = false;
            pressCamera_ = session_.settings().camera;
            if (drag_ == Drag::Orbit) pressCamera_ = recentre(pressCamera_, pivotDistance(pressCamera_));
            return true;
        }
        case SDL_MOUSEMOTION: {
            mouseX_ = inImage(e.motion.x, e.motion.y) ? e.motion.x : -1;
            mouseY_ = e.motion.y;
            if (drag_ == Drag::None) return false;
            // The gesture from where the button went down (no drift from summed steps).
            const float dx = float(e.motion.x - pressX_) / float(image.h), dy = float(e.motion.y - pressY_) / float(image.h);
            moved_ = moved_ || dx != 0 || dy != 0;
            int W = 0, H = 0;
            SDL_GetWindowSize(window_, &W, &H);
            const float perPixel = orbitRate_ * kPi / 180.0f / float(std::max(W, 1));  // radians
            ViewSettings s = session_.settings();
            if (drag_ == Drag::Orbit) s.camera = orbit(pressCamera_, -perPixel * float(e.motion.x - pressX_), perPixel * float(e.motion.y - pressY_));
            else if (drag_ == Drag::Pan) s.camera = pan(pressCamera_, -dx, dy);
            else s.camera = dolly(pressCamera_, 2 * dy);
            apply(s, true);
            return true;
        }
        case SDL_MOUSEBUTTONUP: {
            if (focusClick_ && inImage(e.button.x, e.button.y)) focusAt(e.button.x, e.button.y, image);
            const bool was = drag_ != Drag::None || focusClick_;
            if (drag_ != Drag::None && moved_) session_.endGesture();
            drag_ = Drag::None;
            focusClick_ = false;
            return was;
        }
        case SDL_MOUSEWHEEL: {
            if (mouseX_ < 0 || e.wheel.y == 0) return true;
            ViewSettings s = session_.settings();
            s.camera =
                (SDL_GetModState() & KMOD_SHIFT) ? zoom(s.camera, kWheelDolly * float(e.wheel.y)) : dolly(s.camera, kWheelDolly * float(e.wheel.y));
            apply(s, true);
            return true;
        }
        case SDL_KEYDOWN:
            if (io.WantTextInput) return true;
            return key(e.key.keysym.sym, e.key.keysym.mod, image);
        default: return io.WantCaptureKeyboard && (e.type == SDL_KEYUP || e.type == SDL_TEXTINPUT);
    }
}

void ViewControls::note(const char* label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    layout_[label] = SDL_Rect{int(a.x), int(a.y), int(b.x - a.x), int(b.y - a.y)};
}

// A text field showing `current`; Enter applies what was typed (true, `edit` holding it).
bool ViewControls::field(const char* label, const std::string& current, std::string& edit) {
    std::string& text = edits_[label];
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s", text.c_str());
    const bool entered = ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    note(label);
    layout_[label].w = int(ImGui::CalcItemWidth());  // the text box, not its label beside it
    text = ImGui::IsItemActive() || entered ? std::string(buf) : current;
    if (!entered) return false;
    edit = buf;
    text = current;
    return true;
}

void ViewControls::drawPanel(const std::string& progress) {
    NotLeakChecked notChecked;
    ImGui_ImplSDL2_NewFrame();
    ImGui::NewFrame();
    layout_.clear();
    int W = 0, H = 0;
    SDL_GetWindowSize(window_, &W, &H);
    if (shown_) {
        ImGui::SetNextWindowPos(ImVec2(float(W - kPanelWidth), 0));
        ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(H)));
        ImGui::Begin("settings", nullptr,
                     ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings);
        ImGui::PushItemWidth(120);
        layout_["status"] = statusLines(progress.substr(0, progress.find(" | ")));
        ImGui::Separator();
        ViewSettings s = session_.settings();
        for (int t : {3, 2, 1, 0, 4}) {  // pt, lt, bpt, mmlt, pssmlt
            if (ImGui::RadioButton(tracerName(TracerKind(t)), int(s.tracer) == t) && int(s.tracer) != t) {
                s.tracer = TracerKind(t);
                apply(s, false);
            }
            note(tracerName(TracerKind(t)));
            ImGui::SameLine();
        }
        ImGui::Text("(t)");
        std::string typed;
        double v = 0;
        // Each field: typed text, parsed; a refused value leaves the setting as it was.
        auto edit = [&](const char* label, const std::string& current, auto set) {
            if (!field(label, current, typed)) return;
            if (!parseNumber(typed, v)) return say(std::string(label) + ": '" + typed + "' is not a number", true);
            ViewSettings next = session_.settings();
            const std::string problem = set(next, v);
            if (!problem.empty()) return say(std::string(label) + ": " + problem, true);
            apply(next, false);
        };
        // The plain fields: a whole number or a number, range-checked by the session.
        auto wholeField = [&](const char* label, int ViewSettings::*member) {
            edit(label, std::to_string(s.*member), [member](ViewSettings& n, double x) {
                if (!(x == std::floor(x) && std::fabs(x) < 1e9)) return std::string("not a whole number");
                n.*member = int(x);
                return std::string();
            });
        };
        auto realField = [&](const char* label, auto target) {  // target(settings): the float it sets
            edit(label, number(target(s)), [target](ViewSettings& n, double x) {
                target(n) = float(x);
                return std::string();
            });
        };
        wholeField("MaxPathLength ([ ])", &ViewSettings::maxPathLength);
        wholeField("MinPathLength (, .)", &ViewSettings::minPathLength);
        realField("ProbLarge", [](ViewSettings& n) -> float& { return n.probLarge; });
        wholeField("chains (0: auto)", &ViewSettings::chains);
        realField("MIS beta (0: auto)", [](ViewSettings& n) -> float& { return n.misBeta; });
        realField("exposure (+ -)", [](ViewSettings& n) -> float& { return n.exposure; });
        ImGui::Separator();
        realField("FOV (degrees)", [](ViewSettings& n) -> float& { return n.camera.fovDegrees; });
        // The orbit's rate: the window's, no render setting (--orbit-rate).
        if (field("orbit (deg/width)", number(orbitRate_), typed)) {
            if (parseNumber(typed, v) && v > 0 && v < 1e30)
                orbitRate_ = float(v), say("orbit rate " + number(v) + " degrees per window width", false);
            else say("orbit (deg/width): '" + typed + "' is not a positive number", true);
        }
        edit("focus distance (f)", number(s.camera.focalLength), [](ViewSettings& n, double x) {
            if (!(x > 0)) return std::string("must be positive");
            const float r = apertureOf(n.camera);
            n.camera.focalLength = float(x);
            n.camera = withAperture(n.camera, r);
            return std::string();
        });
        edit("aperture radius", number(apertureOf(s.camera)), [](ViewSettings& n, double x) {
            if (x < 0) return std::string("must not be negative");
            n.camera = withAperture(n.camera, float(x));
            return std::string();
        });
        ImGui::Text("eye %.4g %.4g %.4g", s.camera.position.x, s.camera.position.y, s.camera.position.z);
        ImGui::Text("look at %.4g %.4g %.4g", s.camera.lookAt.x, s.camera.lookAt.y, s.camera.lookAt.z);
        ImGui::Separator();
        if (ImGui::Button("write scene (w)")) say(opt_.keep(s), false);
        note("write scene");
        ImGui::SameLine();
        if (ImGui::Button("command line (c)")) copyCommandLine(s);
        note("command line");
        if (!message_.empty()) {
            if (messageIsError_) ImGui::PushStyleColor(ImGuiCol_Text, IM_COL32(255, 110, 110, 255));
            ImGui::TextWrapped("%s", message_.c_str());
            if (messageIsError_) ImGui::PopStyleColor();
        }
        ImGui::TextWrapped(
            "drag: orbit about the point at the centre; right or shift drag: pan; middle drag or wheel: dolly; shift wheel: zoom; "
            "ctrl click or f: focus; arrows, PgUp, PgDn: fly; Tab hides this panel");
        ImGui::PopItemWidth();
        ImGui::End();
    }
    ImGui::Render();
    renderDrawData(renderer_, ImGui::GetDrawData());
    if (!layoutPath_.empty()) {  // for the tests: where each widget is (written when it moves)
        std::string text;
        for (const auto& [label, r] : layout_)
            text += label + "\t" + std::to_string(r.x) + " " + std::to_string(r.y) + " " + std::to_string(r.w) + " " + std::to_string(r.h) + "\n";
        if (text != layoutWritten_) {
            const std::string tmp = layoutPath_ + ".tmp";
            std::ofstream(tmp) << text;
            std::rename(tmp.c_str(), layoutPath_.c_str());
            layoutWritten_ = text;
        }
    }
}

}  // namespace wmlt
