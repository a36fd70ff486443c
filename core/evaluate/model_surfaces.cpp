#include "core/evaluate/model_surfaces.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/geometry/unique_points.h"

namespace c3d {
namespace {

// |nz| at or below this: a wall (within 10 deg of vertical); above it and
// facing up: a roof (slopes below 80 deg).
constexpr double kVerticalNz = 0.17;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

SurfaceKind surface_kind(const MeshGroup& group, const Face& face) {
  const std::string label = lower(group.name + " " + group.material);
  if (label.find("roof") != std::string::npos) return SurfaceKind::Roof;
  if (label.find("wall") != std::string::npos) return SurfaceKind::Wall;
  if (label.find("ground") != std::string::npos || label.find("floor") != std::string::npos ||
      label.find("ceiling") != std::string::npos)
    return SurfaceKind::Other;
  const double nz = unit_normal(face).z();
  if (nz > kVerticalNz) return SurfaceKind::Roof;
  return std::abs(nz) <= kVerticalNz ? SurfaceKind::Wall : SurfaceKind::Other;
}

std::vector<MeshGroup> element_groups(const BatchModel& model) {
  std::vector<MeshGroup> groups;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings)
      for (const auto& e : b.elements) {
        MeshGroup g;
        g.name = (r.parcel_id.empty() ? "" : r.parcel_id + "_") + b.id + "_" + to_string(e.type);
        for (Face f : e.faces) {
          for (auto& p : f.ring) p += model.frame.origin;
          for (auto& h : f.holes)
            for (auto& p : h) p += model.frame.origin;
          g.faces.push_back(std::move(f));
        }
        groups.push_back(std::move(g));
      }
  return groups;
}

ClassMapping parse_class_codes(const std::string& text, const std::string& where) {
  ClassMapping m;
  m.roof.clear();
  m.wall.clear();
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    auto eq = item.find('=');
    if (eq == std::string::npos) throw InputError(where, "expected kind=code, got '" + item + "'");
    const std::string kind = item.substr(0, eq);
    const int code = std::stoi(item.substr(eq + 1));
    if (kind == "roof") m.roof.push_back(code);
    else if (kind == "wall") m.wall.push_back(code);
    else throw InputError(where, "unknown kind '" + kind + "' (roof or wall)");
  }
  return m;
}

RoofWallPoints roof_and_wall_points(const PointCloud& cloud, const ClassMapping& classes) {
  RoofWallPoints out;
  out.unclassified = cloud.classes.empty();
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const int c = out.unclassified ? classes.roof.front() : cloud.classes[i];
    if (classes.is_roof(c)) out.roof.push_back(cloud.points[i]);
    else if (classes.is_wall(c)) out.wall.push_back(cloud.points[i]);
  }
  out.roof = one_per_place(out.roof);  // as the batch measures them
  out.wall = one_per_place(out.wall);
  return out;
}

}  // namespace c3d
