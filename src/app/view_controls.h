// The interactive mode's controls in the view window (issue 28; docs/interactive.md): mouse
// gestures on the image move the camera (app/camera_control.h), keys fly it and change
// settings, and a Dear ImGui panel (Debian's libimgui-dev) at the window's right shows and
// edits every setting. Everything here runs on the window's thread; a change goes to the
// InteractiveSession, which checks it (a refused value keeps the old one, and the panel
// and stderr say why) and restarts the render.
// The orbit (left drag) turns about the point under the view's centre: at the press, one
// ray through the image's centre (InteractiveSession::depthAt, as the focus click's); where
// it meets nothing, the thin lens' focus distance, else LookAt's. LookAt moves there along
// the view (recentre: the image does not change), then the drag turns the eye about it at
// orbitRate degrees per window width (the panel included), as much up and down.
#pragma once
#include <SDL.h>

#include <functional>
#include <map>
#include <string>

#include "app/camera_control.h"
#include "app/interactive.h"

namespace wmlt {

constexpr int kPanelWidth = 300;  // pixels, at the window's right

struct ControlsOptions {
    // The w key and the panel's button: writes the scene file and prints the command line;
    // returns what to show ("wrote x.xml", or why not).
    std::function<std::string(const ViewSettings&)> keep;
    // The c key: the command line that renders the current settings.
    std::function<std::string(const ViewSettings&)> commandLine;
    float orbitRate = kOrbitRateDefault;  // --orbit-rate: degrees per window width
};

class ViewControls {
public:
    ViewControls(SDL_Window* window, SDL_Renderer* renderer, InteractiveSession& session, ControlsOptions options);
    ~ViewControls();
    ViewControls(const ViewControls&) = delete;
    ViewControls& operator=(const ViewControls&) = delete;

    // An event of the window; `image`: where the image is drawn. True when it was used (the
    // window does not handle it as --view would).
    bool event(const SDL_Event& e, const SDL_Rect& image);
    // The panel, drawn over the window's right column (after the image).
    void drawPanel(const std::string& progress);
    bool panelShown() const { return shown_; }
    float exposure() const { return session_.settings().exposure; }

private:
    enum class Drag { None, Orbit, Pan, Dolly };
    void apply(const ViewSettings& next, bool moving);
    void focusAt(int x, int y, const SDL_Rect& image);
    float pivotDistance(const CameraDesc& c) const;
    bool key(SDL_Keycode k, Uint16 mod, const SDL_Rect& image);
    void say(const std::string& message, bool error);
    void copyCommandLine(const ViewSettings& s);
    void note(const char* label);  // the last widget's rectangle (WAVEMMLT_PANEL_LAYOUT)
    bool field(const char* label, const std::string& current, std::string& edit);

    SDL_Window* window_;
    SDL_Renderer* renderer_;
    SDL_Texture* font_ = nullptr;
    InteractiveSession& session_;
    ControlsOptions opt_;
    bool shown_ = true;
    Drag drag_ = Drag::None;
    int pressX_ = 0, pressY_ = 0;
    bool moved_ = false, focusClick_ = false;
    CameraDesc pressCamera_;  // at the press (an orbit's: recentred on its pivot)
    float orbitRate_;         // degrees per window width
    int mouseX_ = -1, mouseY_ = -1;
    std::string message_;
    bool messageIsError_ = false;
    std::map<std::string, std::string> edits_;  // each text field's text while it is edited
    std::map<std::string, SDL_Rect> layout_;    // each widget's rectangle, this frame
    std::string layoutPath_, layoutWritten_;
};

}  // namespace wmlt
