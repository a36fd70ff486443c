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
};

bool inside_convex(const Ring3& r, const Vec2& p) {
  for (size_t i = 0, n = r.size(); i < n; ++i) {
    Vec2 a = r[i].head<2>(), b = r[(i + 1) % n].head<2>();
    if ((b - a).x() * (p - a).y() - (b - a).y() * (p - a).x() < 0) return false;
  }
  return true;
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
      for (auto& e : m.elements) {
        if (e.type == ElementType::Roof) {
          e.support_points = s.element(e, opt.roof_density, true, opt.roof_noise, 6, opt.outlier_share);
          e.rmse = opt.roof_noise;
          for (const auto& f : e.faces)
            if (!biggest || area(f) > area(*biggest)) biggest = &f;
        } else if (e.type == ElementType::Wall) {
          if (rng.chance(opt.wall_occlusion)) continue;
          e.support_points = s.element(e, opt.wall_density, false, opt.wall_noise, 64, 0);
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
