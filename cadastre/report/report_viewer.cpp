// The report's 3D view script (web/report_viewer.js with three.js), bundled
// at build time by web/CMakeLists.txt and embedded here whole, so the
// program writes it into every report it makes.
#include "cadastre/report/report_3d.h"
#include "core/embed.h"

#ifndef C3D_BUNDLE
#error "C3D_BUNDLE (the bundled viewer script) is set by web/CMakeLists.txt"
#endif

namespace c3d {
C3D_EMBED_FILE(viewer_script, C3D_BUNDLE)
}  // namespace c3d
