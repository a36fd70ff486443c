#pragma once
// Scenes, point samplers and envelope inputs shared by the reconstruction
// stage tests (planes, outline, roof, envelope, ownership, reconstruct).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/reconstruct.h"
#include "core/reconstruct/segment/segmentation.h"

namespace c3d::test {


// Uniform points on a plane patch [x0,x1]x[y0,y1] with Gaussian noise.
std::vector<Vec3> sample_plane(const Plane& pl, double x0, double x1, double y0, double y1,
                               double density, double noise, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::normal_distribution<double> n(0, noise);
  int count = int((x1 - x0) * (y1 - y0) * density);
  std::vector<Vec3> pts;
  for (int i = 0; i < count; ++i) {
    double x = ux(rng), y = uy(rng);
    pts.emplace_back(x + n(rng), y + n(rng), pl.z_at(x, y) + n(rng));
  }
  return pts;
}

inline Plane plane_through(const Vec3& p, Vec3 n) {
  n.normalize();
  if (n.z() < 0) n = -n;
  return Plane{n, n.dot(p)};
}

// A flat roof at z = 3 over `outline` on flat terrain at z = 0; wall points to add.
inline EnvelopeInput flat_roof_input(const std::string& id, const Polygon2& outline) {
  EnvelopeInput in;
  in.building_id = id;
  in.outline = outline;
  Plane roof = plane_through({0, 0, 3}, {0, 0, 1});
  in.roof = {RoofRegion{0, roof, {in.outline}}};
  PlaneFit fit;
  fit.plane = roof;
  fit.rmse = 0.02;
  fit.inliers = 3000;
  in.fits = {fit};
  in.terrain = [](double, double) { return 0.0; };
  in.default_overhang = 0.3;
  return in;
}

// `in` with a roof of two planes: `island` over `hole`, `around` over the rest of `whole`.
inline EnvelopeInput with_island_roof(EnvelopeInput in, const MultiPolygon2& whole, const MultiPolygon2& hole,
                               const Plane& around, const Plane& island) {
  in.roof = {RoofRegion{0, around, poly::subtract(whole, hole)}, RoofRegion{1, island, hole}};
  in.fits = {in.fits[0], in.fits[0]};
  in.fits[0].plane = around;
  in.fits[1].plane = island;
  return in;
}



// `count` wall points (2 cm noise, z0 to z1 high) along the segment a-b.
inline void see_wall(EnvelopeInput& in, const Vec2& a, const Vec2& b, unsigned seed, int count = 1500,
              double z0 = 0.3, double z1 = 3.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, 0.02);
  std::uniform_real_distribution<double> u(0, 1), z(z0, z1);
  const Vec2 normal = Vec2((b - a).y(), -(b - a).x()).normalized();
  for (int i = 0; i < count; ++i) {
    const Vec2 p = a + u(rng) * (b - a) + n(rng) * normal;
    in.wall_points.emplace_back(p.x(), p.y(), z(rng));
  }
}

// How many of the building's elements rest on evidence `ev`.
inline int elements_with(const Building& b, WallEvidence ev) {
  return int(std::count_if(b.elements.begin(), b.elements.end(), [&](const auto& e) { return e.evidence == ev; }));
}

// 2000 wall points each on the south wall y = 0 and the west wall x = 0 of a
// 10 x 8 m house with its south-west corner at the origin.
inline void see_south_and_west_walls(EnvelopeInput& in, unsigned seed) {
  see_wall(in, {0, 0}, {10, 0}, seed, 2000);
  see_wall(in, {0, 8}, {0, 0}, seed + 1000, 2000);
}



inline ParcelScene square_parcel_scene() {
  ParcelScene s;
  s.parcel_id = "P";
  s.parcel = {Polygon2{{{0, 0}, {20, 0}, {20, 20}, {0, 20}}, {}}};
  s.terrain = [](double, double) { return 100.0; };
  return s;
}

// Gable house 10 x 8 m at (5..15, 6..14), eaves at 103, ridge at 106, 0.5 m overhang.
std::vector<Vec3> gable_points(std::mt19937_64& rng, double x0 = 5, double z0 = 103) {
  Plane north = plane_through({0, 10, z0 + 3}, {0, 0.75, 1});
  Plane south = plane_through({0, 10, z0 + 3}, {0, -0.75, 1});
  auto a = sample_plane(north, x0 - 0.5, x0 + 10.5, 10, 14.5, 40, 0.02, rng);
  auto b = sample_plane(south, x0 - 0.5, x0 + 10.5, 5.5, 10, 40, 0.02, rng);
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

inline ReconstructionParams params() { return default_config().reconstruction; }

// The gable house and a second roof on `plane` over [x0,x1] x [y0,y1].
inline ParcelScene house_and_roof(unsigned seed, const Plane& plane, double x0, double x1, double y0, double y1) {
  std::mt19937_64 rng(seed);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  auto a = sample_plane(plane, x0, x1, y0, y1, 40, 0.02, rng);
  s.roof_points.insert(s.roof_points.end(), a.begin(), a.end());
  return s;
}

// The gable house and a flat roof 1.5 m lower over [x0,x1] x [y0,y1].
inline ParcelScene house_and_flat_roof(unsigned seed, double x0, double x1, double y0, double y1) {
  return house_and_roof(seed, plane_through({0, 0, 102}, {0, 0, 1}), x0, x1, y0, y1);
}

// One parcel of two sharing a roof: `own` with `other` as its only neighbour.
inline ParcelResult reconstruct_beside(const Polygon2& own, const Polygon2& other, const std::vector<Vec3>& roof) {
  ParcelScene s = square_parcel_scene();
  s.parcel = {own};
  s.neighbours = {{other}};
  s.roof_points = roof;
  ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  for (const auto& b : r.buildings) EXPECT_TRUE(b.solid_valid) << b.id << " " << b.solid_problem;
  return r;
}


// This parcel's flat roof (x 3..17, y 2..10 at 103 m) reaching its boundary
// y = 10, the neighbour's parcel beyond it, and a flat roof at height z over
// [x0,x1] x [y0,y1] there.
inline ParcelScene flat_roof_at_the_line(std::mt19937_64& rng, double z, double x0, double x1, double y0, double y1) {
  ParcelScene s = square_parcel_scene();
  s.parcel = {Polygon2{{{0, 0}, {20, 0}, {20, 10}, {0, 10}}, {}}};
  s.neighbours = {{Polygon2{{{0, 10}, {20, 10}, {20, 24}, {0, 24}}, {}}}};
  s.roof_points = sample_plane(plane_through({0, 0, 103}, {0, 0, 1}), 3, 17, 2, 10, 40, 0.02, rng);
  const auto across = sample_plane(plane_through({0, 0, z}, {0, 0, 1}), x0, x1, y0, y1, 40, 0.02, rng);
  s.roof_points.insert(s.roof_points.end(), across.begin(), across.end());
  return s;
}

// The parcel's one building's totals, its solid checked.
inline BuildingTotals one_building(const ParcelScene& s) {
  const ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  EXPECT_EQ(r.buildings.size(), 1u);
  for (const auto& b : r.buildings) EXPECT_TRUE(b.solid_valid) << b.id << " " << b.solid_problem;
  return r.buildings.empty() ? BuildingTotals{} : totals(r.buildings[0]);
}

// A segmentation of the scene's roof points that found no roof: every point
// belongs to no component and no roof (all another's, to the ownership queries).
inline Segmentation no_roofs(const ParcelScene& s) {
  Segmentation seg;
  seg.label.assign(s.roof_points.size(), -1);
  seg.roof_of.assign(s.roof_points.size(), -1);
  return seg;
}

// This parcel's shed roof (x 3..17, y 2..9.7 at 104 m, falling north) stops
// 0.3 m short of the boundary y = 10, where the neighbour's roof 5 m higher
// (x 1..19, y 9.7..18) hangs over it; with north_wall_seen, 1500 points of the
// house's north wall 0.5 m inside its edge; without neighbour_beyond, no
// parcel beyond the boundary (a street).
inline ParcelScene roof_under_a_neighbours_eave(bool north_wall_seen, bool neighbour_beyond = true) {
  std::mt19937_64 rng(17);
  ParcelScene s = square_parcel_scene();
  s.parcel = {Polygon2{{{0, 0}, {20, 0}, {20, 10}, {0, 10}}, {}}};
  if (neighbour_beyond) s.neighbours = {{Polygon2{{{0, 10}, {20, 10}, {20, 24}, {0, 24}}, {}}}};
  s.roof_points = sample_plane(plane_through({0, 2, 104}, {0, 0.2, 1}), 3, 17, 2, 9.7, 40, 0.02, rng);
  const auto eave = sample_plane(plane_through({0, 0, 108}, {0, 0, 1}), 1, 19, 9.7, 18, 40, 0.02, rng);
  s.roof_points.insert(s.roof_points.end(), eave.begin(), eave.end());
  if (north_wall_seen) {
    EnvelopeInput walls;
    see_wall(walls, {16, 9.2}, {4, 9.2}, 5, 1500, 100.3, 102.3);
    s.wall_points = walls.wall_points;
  }
  return s;
}

}  // namespace c3d::test
