#include "core/reconstruct/envelope/area_sigma.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/common.h"
#include "core/reconstruct/outline/outline.h"

namespace c3d::envelope {

// The outline stage places each roof edge by maximum likelihood on a density
// rho * Phi((e - s) / noise) across it, the noise fitted to all of a roof's
// edges together (outline.cpp). Its Fisher information per metre of edge, in
// units of rho / noise, with z = (e - s) / noise:
//   edge  x edge:  kEdgeInfo  = int phi^2 / Phi       dz = 0.903
//   edge  x noise: kCrossInfo = int z phi^2 / Phi     dz = -0.596
//   noise x noise: kNoiseInfo = int z^2 phi^2 / Phi   dz = 1.103
// Inverting it (Schur complement), an edge's own variance is noise / (0.903
// rho L), and the noise fitted over perimeter P has variance noise / (rho P
// (kNoiseInfo - kCrossInfo^2 / kEdgeInfo)) and moves every edge by
// kCrossInfo / kEdgeInfo = -0.66 m per m: a shift the roof's edges share.
constexpr double kEdgeInfo = 0.903;
constexpr double kCrossInfo = -0.596;
constexpr double kNoiseInfo = 1.103;
// A wall face's vertices within this of a footprint corner are its end there.
constexpr double kEndTol = 0.01;  // m
// The roof's slope across a wall is read this far inside its middle.
constexpr double kProbeInside = 0.05;  // m

double RoofEdgeNoise::edge(double length) const {
  const double sampled = sampled_edge_length(length);  // the points near its ends are not read
  if (noise <= 0 || density <= 0 || sampled <= 0) return 0;
  return std::sqrt(noise / (kEdgeInfo * density * sampled));
}

double RoofEdgeNoise::common(double sampled) const {
  if (noise <= 0 || density <= 0 || sampled <= 0) return 0;
  const double noise_info = density * sampled / noise * (kNoiseInfo - kCrossInfo * kCrossInfo / kEdgeInfo);
  return std::abs(kCrossInfo / kEdgeInfo) / std::sqrt(noise_info);
}

RoofEdgeNoise roof_edge_noise(const EnvelopeInput& in) {
  double n = 0, ss = 0, plan = 0;
  for (size_t r = 0; r < in.roof.size() && r < in.fits.size(); ++r) {
    const PlaneFit& f = in.fits[r];
    n += f.inliers;
    ss += f.inliers * f.rmse * f.rmse;
    plan += area(in.roof[r].plan);
  }
  RoofEdgeNoise out;
  if (n > 0 && plan > 0) out.noise = std::sqrt(ss / n), out.density = n / plan;
  if (n > 0) out.plane_z = out.noise / std::sqrt(n / double(in.fits.size()));
  return out;
}

double sampled_perimeter(const std::vector<OutlineEdge>& edges) {
  double p = 0;
  for (const auto& e : edges)
    if (!e.party) p += std::max(0.0, sampled_edge_length((e.b - e.a).norm()));
  return p;
}

WallPositionError wall_position_error(const OutlineEdge& e, const RoofEdgeNoise& noise, double sampled) {
  WallPositionError w;
  if (e.party) {  // on the parcel boundary; the roof ends on the same line
    w.wall = e.sigma;
    return w;
  }
  const double roof_edge = noise.edge((e.b - e.a).norm()), common = noise.common(sampled);
  if (e.evidence == WallEvidence::Measured || e.support > 0) {
    // Placed from its own points (or the neighbours' facade): the roof edge
    // beyond it errs on its own.
    w.wall = e.sigma;
    w.eave = std::hypot(roof_edge, e.sigma);
    w.eave_shared = common;
    return w;
  }
  // Set back from its roof edge by an overhang: the wall moves with the edge,
  // the hanging roof's depth errs by the overhang's error alone. An overhang
  // taken from the seen walls errs as much as theirs scatter about it (their
  // own roof edges' noise included), at least as much as its own roof edge.
  w.wall = std::max(e.sigma, roof_edge);
  w.wall_shared = std::hypot(e.sigma_shared, common);
  w.eave = e.sigma;
  w.eave_shared = e.sigma_shared;
  return w;
}

namespace {

// Height of wall face f above ground_z at its end p (its highest vertex there).
double end_height(const Face& f, const Vec2& p, double ground_z) {
  double top = ground_z;
  for (const auto& v : f.ring)
    if ((v.head<2>() - p).norm() < kEndTol) top = std::max(top, v.z());
  return top - ground_z;
}

// Rise of the roof underside per metre outward across edge a -> b, from the
// inside piece just inside its middle (0 where none is found).
double rise_outward(const Vec2& a, const Vec2& b, const std::vector<Face>& inside) {
  const Vec2 n = outward((b - a).normalized()), p = 0.5 * (a + b) - kProbeInside * n;
  for (const auto& f : inside) {
    if (f.ring.size() < 3 || !in_ring_plan(f.ring, p)) continue;
    const Vec3 u = unit_normal(f);
    if (std::abs(u.z()) < 1e-6) return 0;
    return -(u.x() * n.x() + u.y() * n.y()) / u.z();
  }
  return 0;
}

}  // namespace

WallSensitivity wall_area_sensitivity(const Ring2& fp, size_t i, const Face& wall, double ground_z,
                                      const std::vector<Face>& inside) {
  const size_t m = fp.size();
  const Vec2 &prev = fp[(i + m - 1) % m], &a = fp[i], &b = fp[(i + 1) % m], &next = fp[(i + 2) % m];
  auto turn = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // +1 convex (left turn), -1 concave
    const Vec2 u = q - p, v = r - q;
    return u.x() * v.y() - u.y() * v.x() >= 0 ? 1.0 : -1.0;
  };
  return {turn(prev, a, b) * end_height(wall, a, ground_z), turn(a, b, next) * end_height(wall, b, ground_z),
          (b - a).norm() * rise_outward(a, b, inside)};
}

}  // namespace c3d::envelope
