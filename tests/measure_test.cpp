// Stage 7: element measures, volume, solid validity, OCC cross-check, sigma.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/geometry.h"
#include "core/reconstruct/measure/measure.h"
#include "core/check/occ_check.h"
#include "core/check/solid_check.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

// A 10 x 8 m box house, walls 3 m, gable roof with the ridge along x at y = 4,
// z = 5; the roof overhangs the walls by 0.5 m in plan on every side.
constexpr double kL = 10, kW = 8, kEave = 3, kRidge = 5, kOver = 0.5;

Face quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) { return {{a, b, c, d}, {}}; }

std::vector<Face> house_solid() {
  return {
      quad({0, 0, 0}, {0, kW, 0}, {kL, kW, 0}, {kL, 0, 0}),                 // ground
      quad({0, 0, 0}, {kL, 0, 0}, {kL, 0, kEave}, {0, 0, kEave}),          // south wall
      quad({kL, kW, 0}, {0, kW, 0}, {0, kW, kEave}, {kL, kW, kEave}),      // north wall
      {{{0, kW, 0}, {0, 0, 0}, {0, 0, kEave}, {0, kW / 2, kRidge}, {0, kW, kEave}}, {}},  // west gable
      {{{kL, 0, 0}, {kL, kW, 0}, {kL, kW, kEave}, {kL, kW / 2, kRidge}, {kL, 0, kEave}}, {}},  // east gable
      quad({0, 0, kEave}, {kL, 0, kEave}, {kL, kW / 2, kRidge}, {0, kW / 2, kRidge}),    // roof south
      quad({kL, kW, kEave}, {0, kW, kEave}, {0, kW / 2, kRidge}, {kL, kW / 2, kRidge}),  // roof north
  };
}

const double kRise = (kRidge - kEave) / (kW / 2);  // 0.5
const double kZo = kEave - kOver * kRise;         // overhang edge height 2.75

Building house() {
  Building b;
  b.id = "p1_b1";
  b.solid = house_solid();
  Element south{ElementType::Roof}, north{ElementType::Roof}, ceiling{ElementType::OuterCeiling};
  south.faces = {quad({-kOver, -kOver, kZo}, {kL + kOver, -kOver, kZo}, {kL + kOver, kW / 2, kRidge},
                      {-kOver, kW / 2, kRidge})};
  north.faces = {quad({kL + kOver, kW + kOver, kZo}, {-kOver, kW + kOver, kZo}, {-kOver, kW / 2, kRidge},
                      {kL + kOver, kW / 2, kRidge})};
  // Underside of the overhang, facing down, the footprint as a hole.
  ceiling.faces = {{{{-kOver, -kOver, kZo}, {-kOver, kW + kOver, kZo}, {kL + kOver, kW + kOver, kZo},
                     {kL + kOver, -kOver, kZo}},
                    {{{0, 0, kZo}, {kL, 0, kZo}, {kL, kW, kZo}, {0, kW, kZo}}}}};
  b.elements = {south, north, ceiling};
  for (int k = 0; k < 5; ++k) b.elements.push_back({k == 0 ? ElementType::Ground : ElementType::Wall, {b.solid[k]}});
  return b;
}

const double kSlopeLen = std::hypot(kW / 2, kRidge - kEave);  // sqrt(20)
const double kVolume = kL * kW * kEave + kL * kW * (kRidge - kEave) / 2;  // 240 + 80
const double kSolidArea = kL * kW + 2 * kL * kEave + 2 * (kW * kEave + kW * (kRidge - kEave) / 2) +
                          2 * kL * kSlopeLen;

// The shells of two 1 m cubes, with their lowest corners at a and b, as one face list.
std::vector<Face> two_cubes(const Vec3& a, const Vec3& b) {
  auto faces = test::box_shell(a, a + Vec3(1, 1, 1));
  const auto more = test::box_shell(b, b + Vec3(1, 1, 1));
  faces.insert(faces.end(), more.begin(), more.end());
  return faces;
}

Face flipped(Face f) {
  std::reverse(f.ring.begin(), f.ring.end());
  return f;
}

}  // namespace

TEST(Measure, GableHouseElementAreasSlopeAzimuth) {
  Building b = house();
  measure_building(b, 3.0);
  const Element& south = b.elements[0];
  const double plan = (kL + 2 * kOver) * (kW / 2 + kOver);  // 49.5
  EXPECT_NEAR(south.plan_area, plan, 1e-9);
  EXPECT_NEAR(south.area, plan * kSlopeLen / (kW / 2), 1e-9);
  EXPECT_NEAR(south.slope_deg, std::atan(kRise) * 180 / M_PI, 1e-9);
  EXPECT_NEAR(south.azimuth_deg, 180, 1e-9);
  EXPECT_NEAR(b.elements[1].azimuth_deg, 0, 1e-9);
  const Element& ceiling = b.elements[2];
  const double ceiling_area = (kL + 2 * kOver) * (kW + 2 * kOver) - kL * kW;  // 99 - 80
  EXPECT_NEAR(ceiling.area, ceiling_area, 1e-9);
  EXPECT_NEAR(ceiling.plan_area, ceiling_area, 1e-9);
  EXPECT_NEAR(ceiling.slope_deg, 0, 1e-9);
  EXPECT_EQ(ceiling.azimuth_deg, 0);
  const Element& ground = b.elements[3];
  EXPECT_NEAR(ground.area, kL * kW, 1e-9);
  EXPECT_NEAR(ground.slope_deg, 0, 1e-9);
  const Element& east = b.elements[7];
  EXPECT_NEAR(east.area, kW * kEave + kW * (kRidge - kEave) / 2, 1e-9);
  EXPECT_NEAR(east.slope_deg, 90, 1e-9);
  EXPECT_NEAR(east.azimuth_deg, 90, 1e-9);
  EXPECT_NEAR(east.plan_area, 0, 1e-9);
}

TEST(Measure, GableHouseVolumeHeightsStoreys) {
  Building b = house();
  b.terrain_z = 0;
  measure_building(b, 3.0);
  EXPECT_NEAR(b.volume, kVolume, 1e-9);
  EXPECT_NEAR(b.ridge_height, kRidge, 1e-12);
  EXPECT_NEAR(b.eave_height, kZo, 1e-12);
  EXPECT_EQ(b.storeys, 1);
  EXPECT_TRUE(b.solid_valid) << b.solid_problem;
  EXPECT_TRUE(b.solid_problem.empty());

  b.terrain_z = -4;  // a higher building: eave 6.75 m above terrain
  measure_building(b, 3.0);
  EXPECT_NEAR(b.eave_height, kZo + 4, 1e-12);
  EXPECT_EQ(b.storeys, 2);
}

TEST(Measure, VolumeIsTranslationInvariantAndHandlesHoles) {
  auto s = house_solid();
  // Ground split into a ring with a hole plus the face filling the hole.
  Face ground = s[0];
  ground.holes = {{{2, 2, 0}, {6, 2, 0}, {6, 5, 0}, {2, 5, 0}}};
  s[0] = ground;
  s.push_back(quad({2, 2, 0}, {2, 5, 0}, {6, 5, 0}, {6, 2, 0}));
  for (auto& f : s)
    for (auto& p : f.ring) p += Vec3(500000, 9240000, 700);
  for (auto& f : s)
    for (auto& h : f.holes)
      for (auto& p : h) p += Vec3(500000, 9240000, 700);
  EXPECT_NEAR(closed_volume(s), kVolume, 1e-6);
  SolidCheck c = check_solid(s);
  EXPECT_TRUE(c.ok) << c.summary();
  EXPECT_NEAR(c.volume, kVolume, 1e-6);
  OccMeasures m = occ_measure(s);
  EXPECT_TRUE(m.ok) << m.problem;
  EXPECT_NEAR(m.volume, kVolume, 1e-6 * kVolume);
  EXPECT_NEAR(m.area, kSolidArea, 1e-6 * kSolidArea);
}

TEST(SolidCheck, GableHouseIsValidAndAgreesWithOcc) {
  const auto s = house_solid();
  SolidCheck c = check_solid(s);
  EXPECT_TRUE(c.ok) << c.summary();
  EXPECT_EQ(c.summary(), "ok");
  EXPECT_NEAR(c.volume, kVolume, 1e-9);
  EXPECT_NEAR(c.area, kSolidArea, 1e-9);
  OccMeasures m = occ_measure(s);
  ASSERT_TRUE(m.ok) << m.problem;
  EXPECT_EQ(m.free_edges, 0);
  EXPECT_NEAR(m.volume / kVolume, 1, 1e-6);
  EXPECT_NEAR(m.area / kSolidArea, 1, 1e-6);
  EXPECT_NEAR(closed_volume(s) / m.volume, 1, 1e-6);
}

TEST(SolidCheck, MissingFaceIsNotClosed) {
  auto s = house_solid();
  s.erase(s.begin() + 2);
  SolidCheck c = check_solid(s);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("not_closed")) << c.summary();
  EXPECT_FALSE(occ_measure(s).ok);
}

TEST(SolidCheck, FlippedFaceAndInsideOutShell) {
  auto s = house_solid();
  s[1] = flipped(s[1]);
  SolidCheck c = check_solid(s);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("inconsistent_orientation")) << c.summary();

  auto all = house_solid();
  for (auto& f : all) f = flipped(f);
  SolidCheck d = check_solid(all);
  EXPECT_FALSE(d.ok);
  EXPECT_TRUE(d.has("inward_orientation")) << d.summary();
  EXPECT_LT(occ_measure(all).volume, 0);
}

TEST(SolidCheck, NonPlanarFace) {
  auto s = house_solid();
  // Move the east ridge end 5 cm east: both roof faces stay planar, the east
  // gable does not.
  for (auto& f : s)
    for (auto& p : f.ring)
      if (p.isApprox(Vec3(kL, kW / 2, kRidge))) p.x() += 0.05;
  SolidCheck c = check_solid(s);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("non_planar")) << c.summary();
  EXPECT_NE(c.summary().find("face 4"), std::string::npos) << c.summary();
  EXPECT_FALSE(c.has("not_closed"));
  EXPECT_TRUE(check_solid(s, 0.1).ok);
}

TEST(SolidCheck, SelfIntersectingShell) {
  auto s = house_solid();
  // The ridge pushed below the ground: the roof planes cut through the floor.
  for (auto& f : s)
    for (auto& p : f.ring)
      if (p.z() == kRidge) p.z() = -2;
  SolidCheck c = check_solid(s);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("self_intersection")) << c.summary();
}

TEST(SolidCheck, DegenerateAndDuplicateVertices) {
  auto s = house_solid();
  s[0].ring.insert(s[0].ring.begin() + 1, s[0].ring[0]);  // repeated vertex: warning only
  SolidCheck c = check_solid(s);
  EXPECT_TRUE(c.has("duplicate_vertex"));
  EXPECT_TRUE(c.ok) << c.summary();
  s.push_back(quad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}));  // zero area
  EXPECT_TRUE(check_solid(s).has("zero_area_face"));
  EXPECT_TRUE(check_solid({}).has("empty"));
}

TEST(SolidCheck, TJunctionIsClosed) {
  auto s = house_solid();
  // Split the south wall into two halves: the ground edge now meets two walls.
  s[1] = quad({0, 0, 0}, {5, 0, 0}, {5, 0, kEave}, {0, 0, kEave});
  s.push_back(quad({5, 0, 0}, {kL, 0, 0}, {kL, 0, kEave}, {5, 0, kEave}));
  SolidCheck c = check_solid(s);
  EXPECT_TRUE(c.ok) << c.summary();
  EXPECT_NEAR(c.volume, kVolume, 1e-9);
  EXPECT_NEAR(occ_measure(s).volume, kVolume, 1e-6 * kVolume);
}

TEST(Triangulate, FaceWithHoleKeepsAreaAndOrientation) {
  Face f{{{0, 0, 1}, {4, 0, 1}, {4, 4, 3}, {0, 4, 3}}, {{{1, 1, 1.5}, {1, 3, 2.5}, {3, 3, 2.5}, {3, 1, 1.5}}}};
  const Vec3 n = unit_normal(f);
  double a = 0;
  for (const auto& t : triangulate(f)) {
    Vec3 tn = (t.b - t.a).cross(t.c - t.a);
    EXPECT_GT(tn.dot(n), 0);
    a += 0.5 * tn.norm();
  }
  EXPECT_NEAR(a, area(f), 1e-12);
  // Non-convex L shape.
  Face l{{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}}, {}};
  double al = 0;
  for (const auto& t : triangulate(l)) al += 0.5 * (t.b - t.a).cross(t.c - t.a).z();
  EXPECT_NEAR(al, 3, 1e-12);
}

TEST(Sigma, BoundaryOnlyWithoutPlaneFit) {
  Face sq{{{0, 0, 0}, {10, 0, 0}, {10, 5, 0}, {0, 5, 0}}, {}};
  EXPECT_NEAR(sigma_area_from_plane(sq, 0, 0, 0.05), 30 * 0.05, 1e-12);
  EXPECT_EQ(sigma_area_from_plane(sq, 0, 100, 0), 0);
}

TEST(Sigma, TiltedRectangleClosedForm) {
  // 10 m along x, 5 m of slope length rising to the north at 30 deg.
  const double th = 30 * M_PI / 180, L = 5;
  Face f{{{0, 0, 0}, {10, 0, 0}, {10, L * std::cos(th), L * std::sin(th)}, {0, L * std::cos(th), L * std::sin(th)}}, {}};
  const double rmse = 0.05;
  const int n = 500;
  const double st = rmse / std::sqrt(n * L * L / 12);  // variance along the slope: L^2/12
  const double expect = 50 * (std::tan(th) * st + 0.5 * st * st);
  EXPECT_NEAR(sigma_area_from_plane(f, rmse, n, 0), expect, 1e-9);
  // More points or a better fit shrink it; a flat face still gets a second-order part.
  EXPECT_LT(sigma_area_from_plane(f, rmse, 4 * n, 0), expect);
  Face flat{{{0, 0, 0}, {10, 0, 0}, {10, 5, 0}, {0, 5, 0}}, {}};
  EXPECT_GT(sigma_area_from_plane(flat, rmse, n, 0), 0);
  EXPECT_LT(sigma_area_from_plane(flat, rmse, n, 0), expect);
  // measure_element fills sigma_area only when given a boundary sigma.
  Element e{ElementType::Roof, {f}};
  e.rmse = rmse;
  e.support_points = n;
  e.sigma_area = -1;
  measure_element(e);
  EXPECT_EQ(e.sigma_area, -1);
  measure_element(e, 0.02);
  EXPECT_NEAR(e.sigma_area, std::hypot(expect, 30 * 0.02), 1e-9);
}

TEST(SolidCheck, BoxesTouchingAtAVertexOrAnEdgeAreNonManifold) {
  const auto vertex = two_cubes({0, 0, 0}, {1, 1, 1});
  SolidCheck c = check_solid(vertex);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("non_manifold")) << c.summary();
  const auto edge = two_cubes({0, 0, 0}, {1, 1, 0});
  SolidCheck d = check_solid(edge);
  EXPECT_FALSE(d.ok);
  EXPECT_TRUE(d.has("non_manifold")) << d.summary();
}

TEST(SolidCheck, CornerAHairFromAnotherFaceTouchesIt) {
  // A box standing 0.5 mm above another: no face crosses another, but
  // `validate` snaps vertices to 1 mm, and there the boxes' faces meet inside
  // (as a step wall's foot met the wall beside it on a Cimahi house).
  const auto near = two_cubes({0, 0, 0}, {0.25, 0.25, 1.0005});
  SolidCheck c = check_solid(near);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(c.has("self_intersection")) << c.summary();
  const auto apart = two_cubes({0, 0, 0}, {0.25, 0.25, 1.01});  // 1 cm: two solids, no contact
  const SolidCheck d = check_solid(apart);
  EXPECT_FALSE(d.has("self_intersection")) << d.summary();
}
