#include "core/reconstruct/planar_account.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"

namespace c3d {

RoofPlanes roof_planes(const Building& b) {
  std::vector<Face> faces;
  std::vector<int> owner;
  std::map<int, std::pair<Vec3, double>> plane;
  for (size_t k = 0; k < b.elements.size(); ++k) {
    const Element& e = b.elements[k];
    if (e.type != ElementType::Roof || e.faces.empty()) continue;
    Vec3 normal = Vec3::Zero(), centre = Vec3::Zero();
    size_t n = 0;
    for (const Face& f : e.faces) {
      faces.push_back(f), owner.push_back(int(k));
      normal += newell_normal(f.ring);
      for (const Vec3& v : f.ring) centre += v, ++n;
    }
    if (normal.norm() > 0) plane[int(k)] = {normal.normalized(), normal.normalized().dot(centre / double(n))};
  }
  return {FaceIndex(faces, owner), std::move(plane)};
}

PlanarAccount planar_account(const RoofPlanes& roof, const std::vector<Vec3>& pts) {
  PlanarAccount a;
  if (roof.faces.empty() || pts.empty()) return a;
  std::map<int, size_t> taken;
  double rss = 0;
  for (const Vec3& q : pts) {
    const SurfaceHit hit = roof.faces.nearest(q);
    double d = hit.distance;
    const auto plane = roof.plane.find(hit.owner);
    if (plane != roof.plane.end() && std::isnan(roof.faces.vertical(q).distance))
      d = std::min(d, std::abs(plane->second.first.dot(q) - plane->second.second));
    rss += d * d;
    ++taken[hit.owner];
  }
  a.rmse = std::sqrt(rss / double(pts.size()));
  for (const auto& [plane, n] : taken) a.planes += n * 50 >= pts.size();
  return a;
}

}  // namespace c3d
