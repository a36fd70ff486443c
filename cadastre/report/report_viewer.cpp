// The report's 3D view script (cadastre/report/viewer/viewer.js with
// three.js), bundled at build time by cadastre/CMakeLists.txt and embedded
// here whole, so the program writes it into every report it makes.
#include "cadastre/report/report_3d.h"

#ifndef C3D_VIEWER_BUNDLE
#error "C3D_VIEWER_BUNDLE (the bundled viewer script) is set by cadastre/CMakeLists.txt"
#endif

__asm__(".pushsection .rodata\n"
        ".global c3d_viewer_js\n.hidden c3d_viewer_js\n"
        "c3d_viewer_js:\n"
        ".incbin \"" C3D_VIEWER_BUNDLE "\"\n"
        ".global c3d_viewer_js_end\n.hidden c3d_viewer_js_end\n"
        "c3d_viewer_js_end:\n"
        ".popsection\n");
extern "C" const char c3d_viewer_js[], c3d_viewer_js_end[];

std::string_view c3d::viewer_script() { return {c3d_viewer_js, size_t(c3d_viewer_js_end - c3d_viewer_js)}; }
