#include "core/reconstruct/lower_lods.h"

#include <algorithm>
#include <cstdio>

#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/log.h"
#include "core/reconstruct/lod12/lod12.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

std::vector<Vec3> over_footprint(const std::vector<Vec3>& points, const Polygon2& footprint) {
  if (footprint.outer.size() < 3) return points;
  std::vector<Vec3> out;
  for (const auto& p : points)
    if (in_polygon_plan(footprint, p.head<2>())) out.push_back(p);
  return out;
}

Polygon2 ground_footprint(const Building& b) {
  std::vector<MultiPolygon2> parts;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Ground)
      for (const auto& f : e.faces) {
        Polygon2 p{to_2d(f.ring), {}};
        for (const auto& h : f.holes) p.holes.push_back(to_2d(h));
        parts.push_back(poly::make_valid({p}));  // facing down: clockwise in plan, made valid either way
      }
  return parts.empty() ? Polygon2{} : poly::largest(poly::unite_all(parts));
}

std::string roof_type_of(const std::vector<PlaneFit>& planes, long roof_points) {
  if (roof_points <= 0) return "no points";
  if (planes.empty()) return "could not detect";
  std::vector<double> levels;  // heights of the horizontal planes
  for (const auto& f : planes) {
    if (f.plane.slope_deg() >= kHorizontalSlopeDeg) return "slanted";
    levels.push_back(f.centroid.z());
  }
  std::sort(levels.begin(), levels.end());
  for (size_t i = 1; i < levels.size(); ++i)
    if (levels[i] - levels[i - 1] > kSameLevelM) return "multiple horizontal";
  return "horizontal";
}

double min_good_density(double min_component_area_m2) {
  return double(kMinPlanePoints) / std::max(min_component_area_m2, 1e-3);
}

std::string data_quality_of(const Building& b, const BuildingAttributes& a, double min_density) {
  std::vector<std::string> why;
  if (a.roof_points <= 0) {
    why.push_back("no roof points");
  } else if (!(a.point_density >= min_density)) {
    char s[96];
    std::snprintf(s, sizeof s, "insufficient points (%.1f per m2, LoD 2.2 needs %.1f)", a.point_density, min_density);
    why.push_back(s);
  }
  if (b.lod != Lod::Lod22) why.push_back(std::string("lod fallback (") + to_string(b.lod) + ")");
  std::string out;
  for (const auto& w : why) out += (out.empty() ? "" : "; ") + w;
  return out.empty() ? "good" : out;
}

BuildingAttributes roof_attributes(const Building& b, const std::vector<Vec3>& own_roof_points,
                                   const std::vector<PlaneFit>& planes, double plan_area, double min_density) {
  BuildingAttributes a;
  a.roof_points = long(own_roof_points.size());
  a.roof_type = roof_type_of(planes, a.roof_points);
  std::vector<double> z;
  for (const auto& p : own_roof_points) z.push_back(p.z());
  std::sort(z.begin(), z.end());
  if (!z.empty()) {
    a.roof_z_min = z.front();
    a.roof_z_50p = quantile_of_sorted(z, 0.5);
    a.roof_z_70p = quantile_of_sorted(z, kLod12RoofPercentile);
    a.roof_z_max = z.back();
  }
  if (plan_area > 0) a.point_density = double(a.roof_points) / plan_area;
  std::vector<Face> roof;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Roof) roof.insert(roof.end(), e.faces.begin(), e.faces.end());
  a.roof_rmse = roof_rmse(roof, own_roof_points);
  a.data_quality = data_quality_of(b, a, min_density);
  return a;
}

double roof_rmse(const std::vector<Face>& roof_faces, const std::vector<Vec3>& points) {
  if (roof_faces.empty() || points.empty()) return kNaN;
  const Deviation d = deviation_to_faces(points, roof_faces, false);
  return d.n > 0 ? d.rmse : kNaN;
}

LodShell lod_shell_of(const Building& lower, const std::vector<Vec3>& own_roof_points) {
  LodShell s;
  s.lod = lower.lod;
  s.volume = lower.volume;
  std::vector<Face> roof;
  for (const auto& e : lower.elements)
    for (const auto& f : e.faces) {
      s.faces.push_back(f);
      s.face_types.push_back(e.type);
      if (e.type == ElementType::Roof) roof.push_back(f);
    }
  if (s.faces.size() != lower.solid.size())  // lod12 / lod13 make every shell face an element's
    log::warn(lower.id + ": LoD " + to_string(lower.lod) + " elements hold " + std::to_string(s.faces.size()) +
              " faces, its solid " + std::to_string(lower.solid.size()));
  s.roof_rmse = roof_rmse(roof, own_roof_points);
  return s;
}

}  // namespace c3d
