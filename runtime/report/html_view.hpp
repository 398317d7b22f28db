// The `mechgen view` page: one self-contained HTML file (the template view_page/view.html, embedded
// in mechgen at build time) with the scene as JSON and three.js inlined, so it opens from file://
// with no network and no file beside it.
#pragma once

#include <string>

#include "report/view_scene.hpp"

namespace mechgen::report {

// The scene as the page reads it (numbers in shortest round-trip form: the page holds exactly the
// table's doubles).
std::string scene_json(const ViewScene& scene);

// Where three.js (three.min.js) and its OrbitControls.js are read from: $MECHGEN_THREE_DIR, else
// Debian libjs-three's /usr/share/javascript/three. Throws std::runtime_error naming the package
// when a file is missing.
std::string three_js_dir();

// The page. Reads three.js from three_js_dir().
std::string render_html_view(const ViewScene& scene);

}  // namespace mechgen::report
