// Trees and garden sheds on the parcels' open land, for the point classifier's
// training and tests. A tree: a crown of returns through an ellipsoid's outer
// shell and a few trunk points. A shed: a low box (what an airborne town has by
// every house, and what a classifier must not take for a bush). Each kind has
// its own random stream, drawn after every other point, so a town with them
// holds exactly the points of the same town without them, plus theirs.
#include <cmath>

#include "core/synthetic/sample_detail.h"

namespace c3d {

using namespace sample_detail;

namespace {

constexpr std::uint64_t kTreeStream = 0x7472656573ULL;  // "trees": a stream apart from the town's
constexpr std::uint8_t kVegetationClass = 5;             // ASPRS high vegetation
constexpr double kCrownReturnsPerRoofPoint = 0.8;        // a crown returns a little less than a roof
constexpr std::uint64_t kShedStream = 0x7368656473ULL;  // "sheds"
constexpr std::uint8_t kRoofClass = 6, kWallClass = 64;

bool on_any_roof(const SampleTown& town, size_t parcel, const Vec2& p) {
  for (const auto& tb : town.truth[parcel])
    for (const auto& e : tb.model.elements)
      if (e.type == ElementType::Roof)
        for (const auto& f : e.faces) {
          bool inside = true;
          for (size_t i = 0, n = f.ring.size(); i < n && inside; ++i) {
            Vec2 a = f.ring[i].head<2>(), b = f.ring[(i + 1) % n].head<2>();
            inside = (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x() >= 0;
          }
          if (inside) return true;
        }
  return false;
}

void add_point(SampleTown& town, Rng& rng, const Vec3& local, double sigma, std::uint8_t cls = kVegetationClass,
               PointTag tag = PointTag::Vegetation) {
  Vec3 n(rng.normal(), rng.normal(), rng.normal());
  town.cloud.points.push_back(town.frame.to_world(Vec3(local + n * sigma)));
  town.cloud.classes.push_back(cls);
  town.point_tags.push_back(tag);
}

// A shed of `size` (along, across the town's axes) turned by `angle`, centred
// at c on terrain z0: a flat or gently pitched roof `height` above it, and the
// few facade returns the survey's wall density gives its four sides.
void one_shed(SampleTown& town, const SampleOptions& opt, Rng& rng, const Vec2& c, double z0, const Vec2& size,
              double angle) {
  const double height = rng.uniform(2.0, 3.0), pitch = rng.chance(0.5) ? 0.0 : rng.uniform(0.05, 0.18);
  const Vec2 u(std::cos(angle), std::sin(angle)), v(-u.y(), u.x());
  auto at = [&](double a, double b) { return Vec2(c + a * u + b * v); };
  const long roof = rng.count(opt.roof_density * size.x() * size.y());
  for (long i = 0; i < roof; ++i) {
    const double a = rng.uniform(-0.5, 0.5) * size.x(), b = rng.uniform(-0.5, 0.5) * size.y();
    const Vec2 p = at(a, b);
    add_point(town, rng, Vec3(p.x(), p.y(), z0 + height - pitch * b), opt.roof_noise, kRoofClass, PointTag::Surface);
  }
  const double perimeter = 2 * (size.x() + size.y());
  const long walls = rng.count(opt.wall_density * perimeter * (height - 0.3));
  for (long i = 0; i < walls; ++i) {
    double t = rng.uniform(0, perimeter), a, b;  // round the sides
    if (t < size.x()) a = t - size.x() / 2, b = -size.y() / 2;
    else if ((t -= size.x()) < size.y()) a = size.x() / 2, b = t - size.y() / 2;
    else if ((t -= size.y()) < size.x()) a = size.x() / 2 - t, b = size.y() / 2;
    else a = -size.x() / 2, b = size.y() / 2 - (t - size.x());
    const Vec2 p = at(a, b);
    add_point(town, rng, Vec3(p.x(), p.y(), z0 + rng.uniform(0.3, height - pitch * b)), opt.wall_noise, kWallClass,
              PointTag::Surface);
  }
}

void one_tree(SampleTown& town, const SampleOptions& opt, Rng& rng, const Vec3& base) {
  const double radius = rng.uniform(1.5, 3.5), half_height = rng.uniform(1.2, 2.8);
  const double crown_z = base.z() + half_height + rng.uniform(1.5, 5.0);
  const long crown = rng.count(opt.roof_density * kCrownReturnsPerRoofPoint * kPi * radius * radius);
  for (long i = 0; i < crown; ++i) {
    Vec3 d(rng.normal(), rng.normal(), rng.normal());
    d.normalize();
    if (d.z() < 0 && rng.chance(0.6)) d.z() = -d.z();  // most returns come from the top
    const double depth = std::cbrt(rng.uniform(0.3, 1.0));  // through the outer shell of leaves
    add_point(town, rng, base + Vec3(d.x() * radius * depth, d.y() * radius * depth,
                                     crown_z - base.z() + d.z() * half_height * depth),
              opt.roof_noise);
  }
  const double trunk_top = crown_z - half_height - base.z();
  const long trunk = rng.count(trunk_top * opt.roof_density / 10);
  for (long i = 0; i < trunk; ++i) {
    const double a = rng.uniform(0, 2 * kPi);
    add_point(town, rng, base + Vec3(0.15 * std::cos(a), 0.15 * std::sin(a), rng.uniform(0, trunk_top)),
              opt.roof_noise);
  }
}

// Terrain height (local) under local plan point p.
double terrain_at(const SampleTown& town, const Vec2& p) {
  const Vec2 w = town.frame.to_world(p);
  return town.dtm.height_at(w.x(), w.y()) - town.frame.origin.z();
}

// Per parcel, about `per_parcel` objects on its open land: each from up to 50
// draws in all of `place(parcel, rect)`, which draws a spot and says whether
// it put an object there.
template <class Place>
void on_open_land(const SampleTown& town, const std::vector<TownParcel>& tp, Rng& rng, double per_parcel,
                  Place place) {
  for (size_t pi = 0; pi < town.parcels.size(); ++pi) {
    const long wanted = rng.count(per_parcel);
    for (long placed = 0, tries = 0; placed < wanted && tries < 50; ++tries) placed += place(pi, tp[pi].rect);
  }
}

}  // namespace

void sample_detail::sample_trees(SampleTown& town, const SampleOptions& opt,
                                 const std::vector<TownParcel>& tp, double town_angle) {
  Rng rng(opt.seed ^ kTreeStream);
  const Placement toloc{Vec2::Zero(), town_angle};
  on_open_land(town, tp, rng, opt.trees_per_parcel, [&](size_t pi, const Rect& r) {
    const Vec2 p = toloc.to_local(Vec2(rng.uniform(r.u0 + 1, r.u1 - 1), rng.uniform(r.v0 + 1, r.v1 - 1)));
    if (on_any_roof(town, pi, p)) return false;
    one_tree(town, opt, rng, Vec3(p.x(), p.y(), terrain_at(town, p)));
    return true;
  });
}

void sample_detail::sample_sheds(SampleTown& town, const SampleOptions& opt,
                                 const std::vector<TownParcel>& tp, double town_angle) {
  Rng rng(opt.seed ^ kShedStream);
  const Placement toloc{Vec2::Zero(), town_angle};
  on_open_land(town, tp, rng, opt.sheds_per_parcel, [&](size_t pi, const Rect& r) {
    const Vec2 size(rng.uniform(2.0, 4.0), rng.uniform(1.8, 3.0));
    const Vec2 c(rng.uniform(r.u0 + 2.5, r.u1 - 2.5), rng.uniform(r.v0 + 2.5, r.v1 - 2.5));
    for (double a : {-1.0, 0.0, 1.0})  // the whole shed on open land, a step clear of every roof
      for (double b : {-1.0, 0.0, 1.0})
        if (on_any_roof(town, pi, toloc.to_local(c + Vec2(a * (size.x() / 2 + 1), b * (size.y() / 2 + 1)))))
          return false;
    const Vec2 p = toloc.to_local(c);
    one_shed(town, opt, rng, p, terrain_at(town, p), size, town_angle);
    return true;
  });
}

}  // namespace c3d
