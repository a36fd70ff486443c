#include "core/reconstruct/curved_roofs.h"

#include <cmath>
#include <map>

#include "core/evaluate/evaluate.h"
#include "core/log.h"
#include "core/primitives/curved_building.h"
#include "core/reconstruct/measure/measure.h"

namespace c3d {

namespace {

// The building's roof faces, each tagged with its roof element (a plane).
FaceIndex roof_plane_index(const Building& b) {
  std::vector<Face> faces;
  std::vector<int> plane;
  for (size_t k = 0; k < b.elements.size(); ++k)
    if (b.elements[k].type == ElementType::Roof)
      for (const Face& f : b.elements[k].faces) faces.push_back(f), plane.push_back(int(k));
  return FaceIndex(faces, plane);
}

// How the modelled roof planes explain some points: their RMS distance to the
// nearest roof face, and how many planes take at least 2 % of them.
PlanarAccount planar_account(const FaceIndex& roof, const std::vector<Vec3>& pts) {
  PlanarAccount a;
  if (roof.empty() || pts.empty()) return a;
  std::map<int, size_t> taken;
  double rss = 0;
  for (const Vec3& q : pts) {
    const SurfaceHit hit = roof.nearest(q);
    rss += hit.distance * hit.distance;
    ++taken[hit.owner];
  }
  a.rmse = std::sqrt(rss / double(pts.size()));
  for (const auto& [plane, n] : taken) a.planes += n * 50 >= pts.size();
  return a;
}

PrimitiveFit curved_surfaces(const Building& b, const std::vector<Vec3>& own) {
  PrimitiveSearch search;
  const FaceIndex roof = roof_plane_index(b);
  search.planar_model = [&](const std::vector<Vec3>& pts) { return planar_account(roof, pts); };
  PrimitiveFit fit = find_curved_surfaces(own, search);
  log::debug(b.id + ": " + std::to_string(fit.curved.size() + fit.rejected.size()) + " curved candidates among " +
             std::to_string(own.size()) + " roof points");
  for (size_t j = 0; j < fit.rejected.size(); ++j)
    log::debug(b.id + ": not a curved roof: " + fit.rejected[j].describe() + ": " + fit.why_rejected[j]);
  return fit;
}

// The points on surface p: those of `nearby` within `tol` of it and within
// kReachM in plan of the box of its inliers among `own`. The search saw the
// building's planar segments only, which may leave out a vault's steep flanks.
std::vector<Vec3> on_surface(const Primitive& p, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                             double tol) {
  constexpr double kReachM = 2.0;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (int i : p.inliers) lo = lo.cwiseMin(own[size_t(i)].head<2>()), hi = hi.cwiseMax(own[size_t(i)].head<2>());
  lo -= Vec2(kReachM, kReachM), hi += Vec2(kReachM, kReachM);
  std::vector<Vec3> out;
  for (const Vec3& q : nearby)
    if (std::abs(p.distance(q)) <= tol && (q.head<2>().array() >= lo.array()).all() &&
        (q.head<2>().array() <= hi.array()).all())
      out.push_back(q);
  return out;
}

// b modelled on surface p, if valid.
bool remodel_on(Building& b, const Primitive& p, std::vector<Vec3> points, const std::vector<Vec3>& walls,
                double spacing, double storey_height) {
  CurvedBuildingInput in;
  in.building_id = b.id;
  in.roof = p;
  in.roof_points = std::move(points);
  in.wall_points = walls;
  in.ground_z = b.terrain_z;
  in.spacing = spacing;
  std::optional<Building> curved = curved_building(in);
  if (!curved) return false;
  measure_building(*curved, storey_height);
  if (!curved->solid_valid) {
    log::info(b.id + ": its roof is a " + p.describe() + " but the model on it fails (" + curved->solid_problem + ")");
    return false;
  }
  curved->lod_note = "roof modelled on its " + p.describe();
  b = std::move(*curved);
  return true;
}

}  // namespace

std::string model_curved_roof(Building& b, const std::vector<Vec3>& own, const std::vector<Vec3>& nearby,
                              const std::vector<Vec3>& walls, double spacing, double storey_height) {
  const PrimitiveFit fit = curved_surfaces(b, own);
  if (fit.curved.empty()) return "";
  const Primitive& p = fit.curved.front();
  if (fit.curved.size() == 1 && p.share >= kWholeRoofShare &&
      remodel_on(b, p, on_surface(p, own, nearby, 2.5 * fit.noise), walls, spacing, storey_height))
    return "";
  std::string note;
  for (const Primitive& q : fit.curved)
    note += (note.empty() ? "" : ", ") + b.id + " " + q.describe() + " (" + std::to_string(q.share) +
            " % of its roof points)";
  return note;
}

}  // namespace c3d
