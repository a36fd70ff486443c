#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "ifc_citygml/export.h"

namespace c3d {

const std::vector<std::string>& export_format_names() {
  static const std::vector<std::string> names{"gml", "gml3", "cityjson", "cityjsonseq",
                                                "ifc", "obj", "step"};
  return names;
}

std::vector<std::string> export_formats(const BatchModel& model, const std::string& dir,
                                        const std::vector<std::string>& formats,
                                        std::vector<std::string>* skipped) {
  namespace fs = std::filesystem;
  const auto& names = export_format_names();
  for (const auto& f : formats)
    if (std::find(names.begin(), names.end(), f) == names.end())
      throw std::invalid_argument("unknown export format '" + f +
                                  "' (use gml, gml3, cityjson, cityjsonseq, ifc, obj, step)");
  fs::create_directories(dir);
  std::vector<std::string> out;
  auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
  for (const auto& f : formats) {
    if (f == "gml") { write_citygml(model, path("buildings.gml")); out.push_back(path("buildings.gml")); }
    if (f == "gml3") {
      write_citygml(model, path("buildings.citygml3.gml"), 3);
      out.push_back(path("buildings.citygml3.gml"));
    }
    if (f == "cityjson") { write_cityjson(model, path("buildings.city.json")); out.push_back(path("buildings.city.json")); }
    if (f == "cityjsonseq") {
      write_cityjson_seq(model, path("buildings.city.jsonl"));
      out.push_back(path("buildings.city.jsonl"));
    }
    if (f == "ifc") { write_ifc(model, path("buildings.ifc")); out.push_back(path("buildings.ifc")); }
    if (f == "obj") for (auto& p : write_obj_per_parcel(model, path("obj"))) out.push_back(p);
    if (f == "step") for (auto& p : write_step_per_building(model, path("step"), skipped)) out.push_back(p);
  }
  return out;
}

}  // namespace c3d
