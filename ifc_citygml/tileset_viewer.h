#pragma once
// The page beside a batch's 3D Tiles (docs/exports.md, "3D Tiles"):
// DIR/view.html and its script DIR/lib/c3d-tiles.js (web/tileset_viewer.js
// with three.js and 3d-tiles-renderer, embedded in the program), so the
// tileset opens in a browser, served from its folder, with no other program.
#include <string>
#include <vector>

namespace c3d::tiles {

// Writes the page and its script into dir; returns their paths.
std::vector<std::string> write_viewer_page(const std::string& dir);

}  // namespace c3d::tiles
