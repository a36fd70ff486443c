// The 3D Tiles page (tileset_viewer.h). Its legend is written here from the
// tiles' own element colours, so the page and the glTF cannot disagree.
#include "ifc_citygml/tileset_viewer.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/embed.h"
#include "ifc_citygml/tile_content.h"

#ifndef C3D_BUNDLE
#error "C3D_BUNDLE (the bundled tileset page script) is set by web/CMakeLists.txt"
#endif

namespace c3d::tiles {

// The symbol names the script: one name per embedded file in the program.
C3D_EMBED_FILE(tileset_viewer_script, C3D_BUNDLE)

namespace {

namespace fs = std::filesystem;

// The CSS colour a linear RGB vertex colour is drawn in (sRGB).
std::string css_colour(const std::array<float, 3>& linear) {
  char out[8];
  int c[3];
  for (size_t k = 0; k < 3; ++k) {
    const double v = linear[k];
    c[k] = int(std::lround(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055)));
  }
  std::snprintf(out, sizeof out, "#%02x%02x%02x", c[0], c[1], c[2]);
  return out;
}

std::string legend() {
  constexpr std::pair<ElementType, const char*> kTypes[] = {
      {ElementType::Roof, "Roof"}, {ElementType::Wall, "Exterior wall"}, {ElementType::PartyWall, "Party wall"},
      {ElementType::Ground, "Ground floor"}, {ElementType::OuterCeiling, "Outer ceiling"}};
  std::string html = "<div class=\"view3d-legend\">";
  for (const auto& [type, name] : kTypes)
    html += "<span class=\"entry\"><span class=\"swatch\" style=\"background:" + css_colour(element_colour(type)) +
            "\"></span>" + name + "</span>";
  return html + "</div>";
}

std::string page() {
  return "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Cadastre3D: 3D Tiles</title>\n"
         "<link rel=\"icon\" href=\"data:,\">\n<style>\n"
         "html,body{margin:0;height:100%;font-family:sans-serif}body{display:flex;flex-direction:column}\n"
         "#view{flex:1;display:flex;flex-direction:column;min-height:0;background:#f4f4ef}\n"
         ".view3d-canvas{flex:1 1 0;min-height:0;overflow:hidden}\n"
         ".view3d-pick,.view3d-legend,.view3d-note{font-size:13px;padding:4px 8px;margin:0}\n"
         ".view3d-legend .entry{margin-right:12px;white-space:nowrap}\n"
         ".swatch{display:inline-block;width:12px;height:12px;margin:0 4px;border:1px solid #555;vertical-align:middle}\n"
         "</style></head>\n<body><div id=\"view\">" +
         legend() +
         "</div>\n<script src=\"lib/c3d-tiles.js\"></script>\n"
         "<script>C3DTiles.open(document.getElementById('view'), 'tileset.json');</script>\n</body></html>\n";
}

void write_file(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error(path.string() + ": cannot be written");
}

}  // namespace

std::vector<std::string> write_viewer_page(const std::string& dir) {
  const fs::path html = fs::path(dir) / "view.html", script = fs::path(dir) / "lib" / "c3d-tiles.js";
  fs::create_directories(script.parent_path());
  write_file(script, tileset_viewer_script());
  write_file(html, page());
  return {html.string(), script.string()};
}

}  // namespace c3d::tiles
