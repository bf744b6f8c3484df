// The --view window in a build without SDL2 and Dear ImGui (CMake did not find them):
// --view and --interactive are refused.
#include "app/view_window.h"
#include "wavemmlt/error.h"

namespace wmlt {

void checkViewPossible(const char* option) {
    throw InputError(std::string("wavemmlt: ") + option +
                     " is not available: this wavemmlt was built without SDL2 and Dear ImGui "
                     "(install libsdl2-dev and libimgui-dev and rebuild, or watch in tev with --display-server HOST:PORT)");
}

struct ViewWindow::Thread {};

ViewWindow::ViewWindow(ViewHub&, ViewWindowOptions options) { checkViewPossible(options.interactive ? "--interactive" : "--view"); }
ViewWindow::~ViewWindow() = default;
void ViewWindow::waitClosed() {}
bool ViewWindow::waitClosedOrInteractive() { return false; }
void ViewWindow::attach(InteractiveSession&, ControlsOptions) {}

}  // namespace wmlt
