#include <filesystem>
#include <stdexcept>

#include "ifc_citygml/export.h"

namespace c3d {

std::vector<std::string> export_formats(const BatchModel& model, const std::string& dir,
                                        const std::vector<std::string>& formats,
                                        std::vector<std::string>* skipped) {
  namespace fs = std::filesystem;
  for (const auto& f : formats)
    if (f != "gml" && f != "cityjson" && f != "ifc" && f != "obj" && f != "step")
      throw std::invalid_argument("unknown export format '" + f +
                                  "' (use gml, cityjson, ifc, obj, step)");
  fs::create_directories(dir);
  std::vector<std::string> out;
  auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
  for (const auto& f : formats) {
    if (f == "gml") { write_citygml(model, path("buildings.gml")); out.push_back(path("buildings.gml")); }
    if (f == "cityjson") { write_cityjson(model, path("buildings.city.json")); out.push_back(path("buildings.city.json")); }
    if (f == "ifc") { write_ifc(model, path("buildings.ifc")); out.push_back(path("buildings.ifc")); }
    if (f == "obj") for (auto& p : write_obj_per_parcel(model, path("obj"))) out.push_back(p);
    if (f == "step") for (auto& p : write_step_per_building(model, path("step"), skipped)) out.push_back(p);
  }
  return out;
}

}  // namespace c3d
