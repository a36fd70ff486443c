#include "core/evaluate/evaluate.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "core/check/solid_check.h"

namespace c3d {

// Simple_cartesian: distance queries only construct points, and it is the
// fastest kernel for them; coordinates are local, so doubles are ample.
struct FaceIndex::Impl {
  using K = CGAL::Simple_cartesian<double>;
  using Tri = K::Triangle_3;
  using Iter = std::vector<Tri>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<K, Iter>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

  Vec3 origin = Vec3::Zero();
  std::vector<Tri> tris;
  std::vector<int> owner;  // per triangle
  Tree tree;

  K::Point_3 local(const Vec3& p) const {
    Vec3 q = p - origin;
    return {q.x(), q.y(), q.z()};
  }
  Vec3 world(const K::Point_3& p) const { return origin + Vec3(p.x(), p.y(), p.z()); }
};

FaceIndex::FaceIndex(const std::vector<Face>& faces, const std::vector<int>& owner)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  Vec3 lo = Vec3::Constant(INFINITY);
  for (const auto& f : faces)
    for (const auto& p : f.ring) lo = lo.cwiseMin(p);
  if (std::isfinite(lo.x())) m.origin = lo;
  for (size_t i = 0; i < faces.size(); ++i) {
    for (const auto& t : triangulate(faces[i])) {
      Impl::Tri tri(m.local(t.a), m.local(t.b), m.local(t.c));
      if (tri.is_degenerate() || tri.squared_area() < 1e-18) continue;
      m.tris.push_back(tri);
      m.owner.push_back(owner.empty() ? 0 : owner[i]);
    }
  }
  m.tree.insert(m.tris.begin(), m.tris.end());
  if (!m.tris.empty()) {
    m.tree.build();
    m.tree.accelerate_distance_queries();
  }
}

FaceIndex::~FaceIndex() = default;
FaceIndex::FaceIndex(FaceIndex&&) noexcept = default;
FaceIndex& FaceIndex::operator=(FaceIndex&&) noexcept = default;

bool FaceIndex::empty() const { return impl_->tris.empty(); }

SurfaceHit FaceIndex::nearest(const Vec3& p) const {
  const Impl& m = *impl_;
  SurfaceHit h;
  if (m.tris.empty()) return h;
  const auto q = m.local(p);
  const auto [cp, it] = m.tree.closest_point_and_primitive(q);
  h.distance = std::sqrt(CGAL::squared_distance(q, cp));
  h.owner = m.owner[size_t(it - m.tris.begin())];
  h.point = m.world(cp);
  return h;
}

SurfaceHit FaceIndex::vertical(const Vec3& p) const {
  const Impl& m = *impl_;
  SurfaceHit h;
  if (m.tris.empty()) return h;
  const auto q = m.local(p);
  std::vector<Impl::Iter> hits;
  m.tree.all_intersected_primitives(Impl::K::Line_3(q, Impl::K::Vector_3(0, 0, 1)),
                                    std::back_inserter(hits));
  for (auto it : hits) {
    const auto n = it->supporting_plane().orthogonal_vector();
    if (std::abs(n.z()) < 1e-12 * std::sqrt(n.squared_length())) continue;  // vertical face
    const auto& a = it->vertex(0);
    const double z = a.z() - (n.x() * (q.x() - a.x()) + n.y() * (q.y() - a.y())) / n.z();
    const double d = std::abs(q.z() - z);
    if (!(d >= h.distance)) {  // also true while h.distance is NaN
      h.distance = d;
      h.owner = m.owner[size_t(it - m.tris.begin())];
      h.point = m.world({q.x(), q.y(), z});
    }
  }
  return h;
}

namespace {

// Runs f(i) for i in [0, n) on all hardware threads.
template <class F>
void parallel_for(size_t n, F f) {
  const size_t threads = std::max(1u, std::min(std::thread::hardware_concurrency(), 16u));
  if (n < 4096 || threads == 1) {
    for (size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::vector<std::thread> pool;
  const size_t chunk = (n + threads - 1) / threads;
  for (size_t t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (size_t i = t * chunk; i < std::min(n, (t + 1) * chunk); ++i) f(i);
    });
  for (auto& th : pool) th.join();
}

}  // namespace

std::vector<SurfaceHit> FaceIndex::nearest(const std::vector<Vec3>& pts) const {
  std::vector<SurfaceHit> out(pts.size());
  if (!pts.empty()) out[0] = nearest(pts[0]);  // builds the search tree before threads start
  parallel_for(pts.size(), [&](size_t i) { out[i] = nearest(pts[i]); });
  return out;
}

std::vector<SurfaceHit> FaceIndex::vertical(const std::vector<Vec3>& pts) const {
  std::vector<SurfaceHit> out(pts.size());
  parallel_for(pts.size(), [&](size_t i) { out[i] = vertical(pts[i]); });
  return out;
}

// ---- statistics -------------------------------------------------------------

Deviation deviation(const std::vector<double>& distances) {
  Deviation d;
  double sum = 0, sum2 = 0;
  for (double v : distances) {
    if (!std::isfinite(v)) continue;
    v = std::abs(v);
    ++d.n;
    sum += v;
    sum2 += v * v;
    d.max = std::max(d.max, v);
  }
  if (d.n == 0) return d;
  d.mean = sum / double(d.n);
  double ss = 0;  // second pass: no cancellation in the variance
  for (double v : distances)
    if (std::isfinite(v)) ss += (std::abs(v) - d.mean) * (std::abs(v) - d.mean);
  d.std = std::sqrt(ss / double(d.n));
  d.rmse = std::sqrt(sum2 / double(d.n));
  return d;
}

Deviation pool(const std::vector<Deviation>& parts) {
  Deviation d;
  double sum = 0, sum2 = 0;
  for (const auto& p : parts) {
    if (p.n <= 0) continue;
    d.n += p.n;
    sum += p.n * p.mean;
    sum2 += p.n * p.rmse * p.rmse;
    d.max = std::max(d.max, p.max);
  }
  if (d.n == 0) return d;
  d.mean = sum / double(d.n);
  d.rmse = std::sqrt(sum2 / double(d.n));
  // Between-part spread plus within-part spread (exact for population std).
  double ss = 0;
  for (const auto& p : parts)
    if (p.n > 0) ss += p.n * (p.std * p.std + (p.mean - d.mean) * (p.mean - d.mean));
  d.std = std::sqrt(ss / double(d.n));
  return d;
}

int roof_cover_part(double vertical, double near) {
  return !std::isfinite(vertical) ? 2 : vertical <= near ? 0 : 1;
}

RoofCover split_by_cover(const std::vector<double>& distance, const std::vector<double>& vertical, double near) {
  std::vector<double> parts[3];
  for (size_t i = 0; i < distance.size(); ++i)
    parts[roof_cover_part(i < vertical.size() ? vertical[i] : kNaN, near)].push_back(distance[i]);
  return {deviation(parts[0]), deviation(parts[1]), deviation(parts[2])};
}

int wall_cover_part(double distance, double own_roof, double other_roof, double near) {
  return distance <= near ? 0 : std::isfinite(own_roof) ? 1 : std::isfinite(other_roof) ? 2 : 3;
}

WallCover split_wall_cover(const std::vector<double>& distance, const std::vector<double>& own_roof,
                           const std::vector<double>& other_roof, double near) {
  auto at = [](const std::vector<double>& v, size_t i) { return i < v.size() ? v[i] : kNaN; };
  std::vector<double> parts[4];
  for (size_t i = 0; i < distance.size(); ++i)
    parts[wall_cover_part(distance[i], at(own_roof, i), at(other_roof, i), near)].push_back(distance[i]);
  return {deviation(parts[0]), deviation(parts[1]), deviation(parts[2]), deviation(parts[3])};
}

Deviation deviation_to_faces(const std::vector<Vec3>& points, const std::vector<Face>& faces,
                             bool vertical) {
  FaceIndex index(faces);
  if (index.empty()) return {};
  const auto hits = vertical ? index.vertical(points) : index.nearest(points);
  std::vector<double> d(hits.size());
  for (size_t i = 0; i < hits.size(); ++i) d[i] = hits[i].distance;
  return deviation(d);
}

std::vector<Face> faces_of(const Building& b, const std::vector<ElementType>& types) {
  std::vector<Face> out;
  for (const auto& e : b.elements)
    if (std::find(types.begin(), types.end(), e.type) != types.end())
      out.insert(out.end(), e.faces.begin(), e.faces.end());
  return out;
}

namespace {

// Per building: deviation of the points nearest to that building's faces.
std::vector<Deviation> per_building(const std::vector<Building>& buildings,
                                    const std::vector<Vec3>& points,
                                    const std::vector<ElementType>& types) {
  std::vector<Face> faces;
  std::vector<int> owner;
  for (size_t b = 0; b < buildings.size(); ++b)
    for (const auto& f : faces_of(buildings[b], types)) {
      faces.push_back(f);
      owner.push_back(int(b));
    }
  std::vector<std::vector<double>> d(buildings.size());
  FaceIndex index(faces, owner);
  if (!index.empty())
    for (const auto& h : index.nearest(points)) d[h.owner].push_back(h.distance);
  std::vector<Deviation> out;
  for (const auto& v : d) out.push_back(deviation(v));
  return out;
}

}  // namespace

void evaluate_buildings(std::vector<Building>& buildings, const std::vector<Vec3>& roof_points,
                        const std::vector<Vec3>& wall_points) {
  const auto roof = per_building(buildings, roof_points, {ElementType::Roof});
  const auto wall = per_building(buildings, wall_points, {ElementType::Wall, ElementType::PartyWall});
  for (size_t b = 0; b < buildings.size(); ++b) {
    buildings[b].roof_deviation = roof[b];
    buildings[b].wall_deviation = wall[b];
  }
}

}  // namespace c3d
