#include "stages/pssmlt/pssmlt.h"

#include "stages/mmlt/mmlt_render.h"

namespace wmlt {

RenderResult renderPssmlt(const Scene& scene, const RenderOptions& opt) { return mmlt_detail::MmltRender(scene, opt, true).run(); }

}  // namespace wmlt
