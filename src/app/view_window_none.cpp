// The --view window in a build without SDL2 (CMake did not find it): --view is refused.
#include "app/view_window.h"
#include "wavemmlt/error.h"

namespace wmlt {

void checkViewPossible() {
    throw InputError("wavemmlt: --view is not available: this wavemmlt was built without SDL2 "
                     "(install libsdl2-dev and rebuild, or watch in tev with --display-server HOST:PORT)");
}

struct ViewWindow::Thread {};

ViewWindow::ViewWindow(ViewHub&, ViewWindowOptions) { checkViewPossible(); }
ViewWindow::~ViewWindow() = default;
void ViewWindow::waitClosed() {}

}  // namespace wmlt
