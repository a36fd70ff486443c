#pragma once
// Hand-built parcels for the store / valuation / report tests: a 10 x 8 m box
// house with a 26.57 degree gable roof (0.5 m eaves overhang), an empty parcel
// and a failed one, in a UTM-sized frame.
#include <cmath>
#include <string>

#include "core/geometry/geometry.h"
#include "core/types.h"

namespace c3d::test {

inline Face face(std::initializer_list<Vec3> pts, const Vec3& at) {
  Face f;
  for (const Vec3& p : pts) f.ring.push_back(p + at);
  return f;
}

inline Element element(ElementType t, std::vector<Face> faces, double slope, double azimuth) {
  Element e;
  e.type = t;
  e.faces = std::move(faces);
  for (const Face& f : e.faces) {
    e.plan_area += plan_area(f);
    e.area += t == ElementType::OuterCeiling ? plan_area(f) : area(f);
  }
  e.slope_deg = slope;
  e.azimuth_deg = azimuth;
  e.sigma_area = 0.02 * e.area;
  e.support_points = t == ElementType::Roof ? 800 : t == ElementType::Wall ? 300 : 0;
  e.rmse = t == ElementType::Roof ? 0.03 : t == ElementType::Wall ? 0.05 : 0;
  e.evidence = t == ElementType::Wall ? WallEvidence::Measured : WallEvidence::None;
  return e;
}

// Gable house; `at` is the local position of its south-west ground corner.
inline Building gable_house(const std::string& id, const Vec3& at) {
  const double slope = std::atan(0.5) * 180 / M_PI;
  Building b;
  b.id = id;
  auto roof_s = face({{0, -0.5, 2.75}, {10, -0.5, 2.75}, {10, 4, 5}, {0, 4, 5}}, at);
  auto roof_n = face({{10, 8.5, 2.75}, {0, 8.5, 2.75}, {0, 4, 5}, {10, 4, 5}}, at);
  auto wall_s = face({{0, 0, 0}, {10, 0, 0}, {10, 0, 3}, {0, 0, 3}}, at);
  auto wall_n = face({{10, 8, 0}, {0, 8, 0}, {0, 8, 3}, {10, 8, 3}}, at);
  auto gable_w = face({{0, 8, 0}, {0, 0, 0}, {0, 0, 3}, {0, 4, 5}, {0, 8, 3}}, at);
  auto gable_e = face({{10, 0, 0}, {10, 8, 0}, {10, 8, 3}, {10, 4, 5}, {10, 0, 3}}, at);
  auto ground = face({{0, 0, 0}, {0, 8, 0}, {10, 8, 0}, {10, 0, 0}}, at);
  // Underside of the overhang, on the roof plane, facing down.
  auto ceil_s = face({{0, -0.5, 2.75}, {0, 0, 3}, {10, 0, 3}, {10, -0.5, 2.75}}, at);
  auto ceil_n = face({{0, 8, 3}, {0, 8.5, 2.75}, {10, 8.5, 2.75}, {10, 8, 3}}, at);
  b.elements = {element(ElementType::Roof, {roof_s}, slope, 180),
                element(ElementType::Roof, {roof_n}, slope, 0),
                element(ElementType::Wall, {wall_s}, 90, 180),
                element(ElementType::Wall, {wall_n}, 90, 0),
                element(ElementType::Wall, {gable_w}, 90, 270),
                element(ElementType::PartyWall, {gable_e}, 90, 90),
                element(ElementType::Ground, {ground}, 180, 0),
                element(ElementType::OuterCeiling, {ceil_s, ceil_n}, 180, 0)};
  b.solid = {ground, wall_s, wall_n, gable_w, gable_e,
             face({{0, 0, 3}, {10, 0, 3}, {10, 4, 5}, {0, 4, 5}}, at),
             face({{10, 8, 3}, {0, 8, 3}, {0, 4, 5}, {10, 4, 5}}, at)};
  b.volume = 10 * 8 * 3 + 0.5 * 8 * 2 * 10;
  b.eave_height = 3;
  b.ridge_height = 5;
  b.terrain_z = at.z();
  b.storeys = 1;
  b.solid_valid = true;
  b.roof_deviation = {1600, 0.12, 0.0, 0.03, 0.03};
  b.wall_deviation = {600, 0.15, 0.0, 0.05, 0.05};
  return b;
}

inline Parcel square_parcel(int index, const std::string& id, const Vec2& sw_world, double size,
                            double official_area = kNaN) {
  Parcel p;
  p.index = index;
  p.id = id;
  p.right_type = index % 2 ? "Hak Guna Bangunan" : "Hak Milik";
  p.official_area = official_area;
  Ring2 r{sw_world, sw_world + Vec2(size, 0), sw_world + Vec2(size, size), sw_world + Vec2(0, size)};
  p.shape = {Polygon2{r, {}}};
  return p;
}

// Three parcels in a row: a house (ok), an empty lot, a failed parcel with a building-less result.
inline BatchModel sample_batch(int houses = 1) {
  BatchModel m;
  m.frame.origin = Vec3(781000, 9240000, 700);
  m.epsg = 32748;
  int n = houses + 2;
  for (int i = 0; i < n; ++i) {
    Vec2 sw = m.frame.origin.head<2>() + Vec2(20.0 * i, 0);
    std::string id = "32.73.0" + std::to_string(i + 1);
    m.parcels.push_back(square_parcel(i, id, sw, 16.0, i == 0 ? 250.0 : kNaN));
    ParcelResult r;
    r.parcel_index = i;
    r.parcel_id = id;
    if (i < houses) {
      r.status = ParcelStatus::Ok;
      r.buildings.push_back(gable_house(id + "_b0", Vec3(20.0 * i + 3, 4, 1.5)));
      r.roof_points = 1600;
      r.wall_points = 600;
      r.timings = {{"segment", 0.25}, {"envelope", 0.5}};
    } else if (i == houses) {
      r.status = ParcelStatus::Empty;
      r.reason = "no roof points";
    } else {
      r.status = ParcelStatus::Failed;
      r.reason = "roof segmentation found no planar component";
    }
    m.results.push_back(std::move(r));
  }
  return m;
}

}  // namespace c3d::test
