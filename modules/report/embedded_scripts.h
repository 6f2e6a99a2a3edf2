// The scripts report.html inlines, embedded into the library at build time
// (modules/report/CMakeLists.txt, embed_files.cmake): the page needs no network and no file
// beside it. None contains "</script" (the build checks), so each fits in a <script> element.
#pragma once

#include <string_view>

namespace pgba {

// three.min.js of the Debian package libjs-three: defines the global THREE.
std::string_view ThreeJsScript();
// examples/js/controls/OrbitControls.js of the same package: THREE.OrbitControls (drag to
// rotate, wheel to zoom, right-drag to pan).
std::string_view OrbitControlsScript();
// model_view_3d.js: draws the 3D view from its data (report/model_view_3d.h).
std::string_view ModelView3dScript();

}  // namespace pgba
