#include "core/reconstruct/envelope/roof_faces.h"

#include <algorithm>
#include <cmath>

#include "core/reconstruct/envelope/wall_faces.h"

namespace c3d::envelope {

// Heights at one vertex closer than this are one line numerically (welded).
constexpr double kHeightWeld = 0.002;  // m
// Pieces at a step fan meet at their mean where their heights there lie
// within this: farther apart they are real steps.
constexpr double kStepFanSpread = 0.01;  // m
// A vertex with this many vertical step-wall edges on it is a step fan: one
// step wall passing a vertex puts two there.
constexpr int kStepFanEdges = 4;

double Heights::get(const Vec2& v, double z) const {
  auto it = at_.find(key(v));
  if (it == at_.end()) return z;
  const bool all = at_mean_.count(key(v)) > 0;
  double sum = 0;
  int n = 0;
  for (double o : it->second)
    if (all || std::abs(o - z) < kHeightWeld) sum += o, ++n;
  return n ? sum / n : z;
}

void Heights::meet_at_mean(const Vec2& v) {
  auto it = at_.find(key(v));
  if (it == at_.end()) return;
  const auto [lo, hi] = std::minmax_element(it->second.begin(), it->second.end());
  if (*hi - *lo < kStepFanSpread) at_mean_.insert(key(v));
}

Ring3 lift(const Ring2& r, const Plane& plane, const Heights& h) {
  Ring3 out;
  for (const auto& v : r) out.emplace_back(v.x(), v.y(), h.get(v, plane.z_at(v.x(), v.y())));
  return out;
}

Face lift(const Piece& p, const Plane& plane, const Heights& h) {
  Face f{lift(p.plan.outer, plane, h), {}};
  for (const auto& hole : p.plan.holes) f.holes.push_back(lift(hole, plane, h));
  return f;
}

Ring3 flat(const Ring2& r, double z, bool downward) {
  Ring3 out;
  for (const auto& v : r) out.emplace_back(v.x(), v.y(), z);
  if (downward) std::reverse(out.begin(), out.end());
  return out;
}

// Planes that miss one junction by more than the 2 mm weld (a cross gable's
// wing ridge 3 mm above the main ridge it runs into, five faces round one
// vertex) leave a step wall between each high and low neighbour there, three
// or more on one vertical edge, which no solid can hold. The pieces at such a
// vertex meet at the mean of their heights, each a few millimetres off its
// plane at that one corner. (Four regions round one vertex are split into two
// three-plane points before, exactly: split_four_plane_vertices.)
void meet_at_step_fans(Heights& heights, const std::vector<Piece>& pieces, const std::vector<RoofRegion>& roof) {
  std::vector<Face> inside;
  for (const auto& p : pieces)
    if (p.inside) inside.push_back(lift(p, roof[p.region].plane, heights));
  std::map<std::pair<double, double>, int> vertical_edges;
  for (const auto& [above, faces] : step_walls(inside, std::vector<int>(inside.size(), 0)))
    for (const Face& f : faces)
      for (size_t i = 0; i < f.ring.size(); ++i) {
        const Vec3& a = f.ring[i];
        if (a.head<2>() == f.ring[(i + 1) % f.ring.size()].head<2>()) ++vertical_edges[{a.x(), a.y()}];
      }
  for (const auto& [xy, n] : vertical_edges)
    if (n >= kStepFanEdges) heights.meet_at_mean(Vec2(xy.first, xy.second));
}

RoofFaces lift_roof(const std::vector<Piece>& pieces, const std::vector<RoofRegion>& roof) {
  Heights heights;
  for (const auto& p : pieces) {
    const Plane& pl = roof[p.region].plane;
    for (const auto& v : p.plan.outer) heights.add(v, pl.z_at(v.x(), v.y()));
    for (const auto& h : p.plan.holes)
      for (const auto& v : h) heights.add(v, pl.z_at(v.x(), v.y()));
  }
  meet_at_step_fans(heights, pieces, roof);
  std::vector<std::vector<Face>> by_region(roof.size());
  std::vector<Face> inside, soffits;
  std::vector<int> inside_region;
  for (const auto& p : pieces) {
    const Face f = lift(p, roof[p.region].plane, heights);
    by_region[p.region].push_back(f);
    if (p.inside) {
      inside.push_back(f);
      inside_region.push_back(p.region);
    } else {
      double zmin = 1e18;
      for (const auto& v : f.ring) zmin = std::min(zmin, v.z());
      Face s{flat(p.plan.outer, zmin, true), {}};
      for (const auto& h : p.plan.holes) s.holes.push_back(flat(h, zmin, true));
      soffits.push_back(std::move(s));
    }
  }
  return {std::move(by_region), std::move(inside), std::move(inside_region), std::move(soffits)};
}

}  // namespace c3d::envelope
