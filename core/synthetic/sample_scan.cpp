// The simulated scan: UAV points on the roofs, handheld points on the walls
// (some walls occluded), clutter on some roofs, and open ground.
#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/synthetic/sample_detail.h"

namespace c3d {

using namespace sample_detail;

namespace {

// ---- Point sampling ----

class Sampler {
 public:
  Sampler(SampleTown& town, Rng& rng) : t_(town), r_(rng) {}

  // Uniform points on a convex planar ring: fan triangles picked by area.
  void fan(const Ring3& ring) {
    double total = 0;
    cum_.clear();
    for (size_t i = 1; i + 1 < ring.size(); ++i)
      cum_.push_back(total += 0.5 * (ring[i] - ring[0]).cross(ring[i + 1] - ring[0]).norm());
  }
  Vec3 on_fan(const Ring3& ring) {
    double u = r_.uniform() * cum_.back();
    size_t k = std::min(size_t(std::lower_bound(cum_.begin(), cum_.end(), u) - cum_.begin()),
                        cum_.size() - 1);
    double s = std::sqrt(r_.uniform()), v = r_.uniform();
    return ring[0] * (1 - s) + ring[k + 1] * (s * (1 - v)) + ring[k + 2] * (s * v);
  }
  Vec3 on_face(const Ring3& ring) {
    fan(ring);
    return on_fan(ring);
  }
  void add(const Vec3& local, double sigma, std::uint8_t cls, PointTag tag) {
    Vec3 n(r_.normal(), r_.normal(), r_.normal());
    t_.cloud.points.push_back(t_.frame.to_world(Vec3(local + n * sigma)));
    t_.cloud.classes.push_back(cls);
    t_.point_tags.push_back(tag);
  }
  // Points on every face of an element; returns how many.
  int element(const Element& e, double density_per_plan_or_area, bool per_plan, double sigma,
              std::uint8_t cls, double outlier_share) {
    int n = 0;
    for (const auto& f : e.faces) {
      if (per_plan && unit_normal(f).z() < 0) continue;  // the underside of a bulging roof: unseen from above
      long k = r_.count(density_per_plan_or_area * (per_plan ? plan_area(f) : area(f)));
      if (k > 0) fan(f.ring);
      for (long i = 0; i < k; ++i, ++n) {
        Vec3 p = on_fan(f.ring);
        if (r_.chance(outlier_share)) {
          p.z() += (r_.chance(0.5) ? 1 : -1) * r_.uniform(0.5, 4.0);
          add(p, sigma, cls, PointTag::Outlier);
        } else {
          add(p, sigma, cls, PointTag::Surface);
        }
      }
    }
    return n;
  }
  // A wall face with its openings: the wall's points outside them, and in
  // each its pane (`depth` behind the frame) and its four reveals.
  int wall_with_openings(const Face& f, const std::vector<Opening>& openings, double density, double sigma,
                         std::uint8_t cls) {
    int n = 0;
    long k = r_.count(density * area(f));
    if (k > 0) fan(f.ring);
    for (long i = 0; i < k; ++i) {
      const Vec3 p = on_fan(f.ring);
      if (std::none_of(openings.begin(), openings.end(), [&](const Opening& o) { return in_frame(o, p); }))
        add(p, sigma, cls, PointTag::Surface), ++n;
    }
    for (const Opening& o : openings) {
      const Vec3 back = o.inward * o.depth;
      Ring3 pane;
      for (const Vec3& c : o.frame) pane.push_back(c + back);
      n += on_ring(pane, density, sigma, cls);
      for (size_t i = 0; i < 4; ++i) {
        const Vec3 &a = o.frame[i], &b = o.frame[(i + 1) % 4];
        n += on_ring({a, b, b + back, a + back}, density, sigma, cls);
      }
    }
    return n;
  }
  // An antenna (vertical line) or a water tank (cylinder) standing on the roof.
  void clutter(const Face& roof, double density, double sigma) {
    Vec3 base = on_face(roof.ring);
    if (r_.chance(0.5)) {
      double h = r_.uniform(1.5, 3.0);
      for (int i = 0, n = int(h * 12); i < n; ++i)
        add(base + Vec3(0, 0, h * (i + 0.5) / n), sigma, 6, PointTag::Clutter);
      return;
    }
    double rad = r_.uniform(0.4, 0.7), h = r_.uniform(0.8, 1.4);
    long side = r_.count(density * 2 * kPi * rad * h), top = r_.count(density * kPi * rad * rad);
    for (long i = 0; i < side; ++i) {
      double a = r_.uniform(0, 2 * kPi);
      add(base + Vec3(rad * std::cos(a), rad * std::sin(a), r_.uniform(0, h)), sigma, 6, PointTag::Clutter);
    }
    for (long i = 0; i < top; ++i) {
      double a = r_.uniform(0, 2 * kPi), q = rad * std::sqrt(r_.uniform());
      add(base + Vec3(q * std::cos(a), q * std::sin(a), h), sigma, 6, PointTag::Clutter);
    }
  }

 private:
  SampleTown& t_;
  Rng& r_;
  std::vector<double> cum_;

  int on_ring(const Ring3& ring, double density, double sigma, std::uint8_t cls) {
    const long k = r_.count(density * area(ring));
    if (k > 0) fan(ring);
    for (long i = 0; i < k; ++i) add(on_fan(ring), sigma, cls, PointTag::Surface);
    return int(std::max(0L, k));
  }
  // Whether a point of the wall plane lies inside the opening's frame.
  static bool in_frame(const Opening& o, const Vec3& p) {
    const Vec3 along = (o.frame[1] - o.frame[0]).normalized();
    const double s = (p - o.frame[0]).dot(along), z = p.z();
    return s > 0 && s < (o.frame[1] - o.frame[0]).norm() && z > o.frame[0].z() && z < o.frame[2].z();
  }
};

// Whether p lies in the convex counter-clockwise ring (its plan, for a Ring3).
template <typename Ring>
bool inside_convex(const Ring& r, const Vec2& p) {
  for (size_t i = 0, n = r.size(); i < n; ++i) {
    const Vec2 a = r[i].template head<2>(), b = r[(i + 1) % n].template head<2>();
    if ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x() < 0) return false;
  }
  return true;
}

// Recessed openings of one exterior wall face: windows 1.2 m wide and 1.3 m
// high every 3 m along it, on each 3 m storey (sills 0.9 m above the
// storey), 0.15 m deep; the building's first face with room gets a door
// (1.0 x 2.1 m, 0.3 m above the floor) in its first ground-floor slot. An opening keeps 0.3 m of
// wall around it inside the face, so gables and low walls get fewer.
std::vector<Opening> openings_of(const Face& f, bool& door_left) {
  std::vector<Opening> out;
  const Ring3& r = f.ring;
  if (r.size() < 3) return out;
  Vec3 n = unit_normal(f);  // outward: the truth's solid is oriented
  n.z() = 0;
  if (n.norm() < 0.99) return out;  // not a vertical face
  n.normalize();
  Vec3 lo = r[0], hi = r[0];
  for (const Vec3& p : r) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 mid = (lo + hi) / 2;
  const Vec3 along(-n.y(), n.x(), 0);
  const Vec3 plane = mid - n * (mid - r[0]).dot(n);  // a point on the face's plane
  const auto corner = [&](double s, double z) { return Vec3(plane + along * s + Vec3(0, 0, z - plane.z())); };
  // The face in its own plane (along, up), counter-clockwise: a convex ring.
  Ring2 flat;
  for (const Vec3& p : r) flat.emplace_back((p - mid).dot(along), p.z());
  if (signed_area(flat) < 0) std::reverse(flat.begin(), flat.end());
  double s0 = 1e300, s1 = -1e300;
  for (const Vec2& q : flat) s0 = std::min(s0, q.x()), s1 = std::max(s1, q.x());
  const auto fits = [&](double a, double b, double z0, double z1) {
    for (double s : {a - 0.3, b + 0.3})
      for (double z : {z0 - 0.3, z1 + 0.3})
        if (!inside_convex(flat, Vec2(s, z))) return false;
    return true;
  };
  const int slots = int(std::floor((s1 - s0) / 3.0));
  for (int storey = 0; storey < 10; ++storey) {
    const double floor_z = lo.z() + 3.0 * storey;
    if (floor_z > hi.z()) break;
    for (int k = 0; k < slots; ++k) {
      const double c = s0 + (s1 - s0 - 3.0 * slots) / 2 + 3.0 * (k + 0.5);
      const bool door = door_left && storey == 0 && k == 0;
      const double w = door ? 1.0 : 1.2, z0 = door ? floor_z + 0.3 : floor_z + 0.9, z1 = z0 + (door ? 2.1 : 1.3);
      if (!fits(c - w / 2, c + w / 2, z0, z1)) continue;
      door_left = door_left && !door;
      out.push_back({door ? "door" : "window",
                     {corner(c - w / 2, z0), corner(c + w / 2, z0), corner(c + w / 2, z1), corner(c - w / 2, z1)},
                     -n, 0.15});
    }
  }
  return out;
}


}  // namespace

void sample_detail::sample_points(SampleTown& town, const SampleOptions& opt, Rng& rng,
                   const std::vector<TownParcel>& tp, double town_angle) {
  Sampler s(town, rng);
  double roof = 0, wall = 0, ground = 0;  // expected counts, to reserve once
  for (const auto& p : town.truth)
    for (const auto& tb : p) {
      BuildingTotals t = totals(tb.model);
      roof += t.roof_plan;
      wall += t.wall;
    }
  for (const auto& p : town.parcels) ground += area(p.shape);
  size_t expect = size_t(roof * opt.roof_density * 1.02 + wall * opt.wall_density +
                         ground * opt.ground_density) + 1000;
  town.cloud.points.reserve(expect);
  town.cloud.classes.reserve(expect);
  town.point_tags.reserve(expect);
  Placement toloc{Vec2::Zero(), town_angle};
  for (size_t pi = 0; pi < town.parcels.size(); ++pi) {
    for (auto& tb : town.truth[pi]) {
      Building& m = tb.model;
      const Face* biggest = nullptr;
      bool door_left = true;  // one door a building
      for (auto& e : m.elements) {
        if (e.type == ElementType::Roof) {
          e.support_points = s.element(e, opt.roof_density, true, opt.roof_noise, 6, opt.outlier_share);
          e.rmse = opt.roof_noise;
          for (const auto& f : e.faces)
            if (!biggest || area(f) > area(*biggest)) biggest = &f;
        } else if (e.type == ElementType::Wall) {
          if (rng.chance(opt.wall_occlusion)) continue;
          if (opt.openings) {
            e.support_points = 0;
            for (const Face& f : e.faces) {
              const std::vector<Opening> here = openings_of(f, door_left);
              e.support_points += s.wall_with_openings(f, here, opt.wall_density, opt.wall_noise, 64);
              tb.openings.insert(tb.openings.end(), here.begin(), here.end());
            }
          } else {
            e.support_points = s.element(e, opt.wall_density, false, opt.wall_noise, 64, 0);
          }
          e.rmse = opt.wall_noise;
          e.evidence = WallEvidence::Measured;
        }
      }
      if (biggest && rng.chance(opt.clutter_share)) s.clutter(*biggest, opt.roof_density, opt.roof_noise);
    }
    // Open ground of the parcel, outside every roof over it.
    const Rect& r = tp[pi].rect;
    long k = rng.count(opt.ground_density * (r.u1 - r.u0) * (r.v1 - r.v0));
    for (long i = 0; i < k; ++i) {
      Vec2 p = toloc.to_local(Vec2(rng.uniform(r.u0, r.u1), rng.uniform(r.v0, r.v1)));
      bool covered = false;
      for (const auto& tb : town.truth[pi])
        for (const auto& e : tb.model.elements)
          if (e.type == ElementType::Roof)
            for (const auto& f : e.faces) covered = covered || inside_convex(f.ring, p);
      if (covered) continue;
      Vec2 w = town.frame.to_world(p);
      s.add(Vec3(p.x(), p.y(), town.dtm.height_at(w.x(), w.y()) - town.frame.origin.z()),
            opt.roof_noise, 2, PointTag::Surface);
    }
    if (opt.progress && (pi % 100 == 99 || pi + 1 == town.parcels.size()))
      opt.progress("points", int(pi + 1), int(town.parcels.size()));
  }
}

}  // namespace c3d
