// One parcel from points to buildings: bad input, roof levels, points no plane takes.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <random>

#include "core/config/config.h"
#include "core/reconstruct/building_plan.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/outline/outline.h"
#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/reconstruct.h"
#include "core/reconstruct/roof/roof.h"
#include "core/synthetic/sample_town.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/segment/segmentation.h"
#include "core/check/solid_check.h"
#include "ifc_citygml/validate.h"
#include "tests/test_support.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::test;

TEST(ReconstructBadInput, ThreeRoofPointsGiveEmptyWithReason) {
  ParcelScene s = square_parcel_scene();
  s.roof_points = {{1, 1, 103}, {2, 1, 103}, {1, 2, 103}};
  ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Empty);
  EXPECT_NE(r.reason.find("too few roof points"), std::string::npos) << r.reason;
}

TEST(ReconstructBadInput, OnlyWallPointsGiveEmpty) {
  ParcelScene s = square_parcel_scene();
  for (int i = 0; i < 500; ++i) s.wall_points.emplace_back(5 + 0.02 * i, 6, 100 + 0.005 * i);
  ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Empty);
  EXPECT_EQ(r.reason, "no roof points in the parcel");
}

TEST(ReconstructBadInput, NoisyBlobIsNotAModelOfPlanes) {
  // A tree-like blob: 3000 points in a 2 m ball, no plane in it.
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n(0, 0.8);
  ParcelScene s = square_parcel_scene();
  for (int i = 0; i < 3000; ++i) s.roof_points.emplace_back(10 + n(rng), 10 + n(rng), 104 + n(rng));
  ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_NE(r.status, ParcelStatus::Ok) << "a blob became " << r.buildings.size() << " buildings";
  EXPECT_FALSE(r.reason.empty());
}

TEST(ReconstructBadInput, TerrainMissingUnderTheBuildingFailsWithReason) {
  std::mt19937_64 rng(10);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  s.terrain = [](double, double) { return kNaN; };
  ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_EQ(r.status, ParcelStatus::Failed);
  EXPECT_NE(r.reason.find("terrain"), std::string::npos) << r.reason;
}

TEST(ReconstructBadInput, TwoTouchingRoofLevelsMakeOneClosedBuilding) {
  // A gable house with a flat annex roof 1.5 m lower against its east gable.
  ParcelScene s = house_and_flat_roof(11, 15.5, 19.0, 7, 13);
  ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 1u);
  const Building& b = r.buildings[0];
  EXPECT_EQ(totals(b).roof_planes, 3);
  EXPECT_TRUE(b.solid_valid) << b.solid_problem;
  EXPECT_GT(b.volume, 0.0);
}

TEST(ReconstructBadInput, RoofsTouchingAtACornerAreTwoBuildings) {
  // The gable house and a flat shed roof 1.5 m lower that meets it only at the
  // house's south-east overhang corner: two buildings, each with its own walls,
  // not one building whose shed hangs in the air beside it.
  ParcelScene s = house_and_flat_roof(12, 15.6, 19.5, 1.0, 5.4);
  ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 2u);
  for (const auto& b : r.buildings) {
    EXPECT_TRUE(b.solid_valid) << b.id << " " << b.solid_problem;
    BuildingTotals t = totals(b);
    EXPECT_GT(t.ground, 0.5 * t.roof_plan) << b.id << ": most of the roof over walls";
  }
}


// ---- the work list: a plan whose footprint comes apart --------------------

// Two 8 x 8 m roofs (x 1..9 and x 11..19, y 6..14) joined by a walkway roof
// (x 9..11, y 9.5..10.5), whose footprint came apart in two: the plan is
// replaced by one per house, the walkway's roof going to one of them, and
// neither house may grow onto its sibling.
TEST(Reconstruct, PlanWhoseFootprintComesApartIsOnePlanPerHouse) {
  const MultiPolygon2 roof = poly::unite_all({{Polygon2{{{1, 6}, {9, 6}, {9, 14}, {1, 14}}, {}}},
                                              {Polygon2{{{11, 6}, {19, 6}, {19, 14}, {11, 14}}, {}}},
                                              {Polygon2{{{9, 9.5}, {11, 9.5}, {11, 10.5}, {9, 10.5}}, {}}}});
  ASSERT_EQ(roof.size(), 1u);
  const BuildingPlan bp{roof[0], {0, 1}, poly::buffer(roof, 3.0)};
  FootprintApart apart;
  apart.parts = {Polygon2{{{1.5, 6.5}, {8.5, 6.5}, {8.5, 13.5}, {1.5, 13.5}}, {}},
                 Polygon2{{{11.5, 6.5}, {18.5, 6.5}, {18.5, 13.5}, {11.5, 13.5}}, {}}};
  apart.overhang = 0.5;
  const std::vector<BuildingPlan> houses = houses_under(bp, apart);
  ASSERT_EQ(houses.size(), 2u);
  EXPECT_NEAR(area(houses[0].outline) + area(houses[1].outline), 130, 0.1);
  for (size_t h = 0; h < 2; ++h) {
    EXPECT_GE(area(houses[h].outline), 64 - 0.1);
    EXPECT_EQ(houses[h].components, bp.components);
    EXPECT_TRUE(poly::covers(houses[h].room, h == 0 ? Vec2(5, 10) : Vec2(15, 10)));
    EXPECT_FALSE(poly::covers(houses[h].room, h == 0 ? Vec2(15, 10) : Vec2(5, 10)));  // the sibling's
  }
  apart.parts.pop_back();  // in one piece: the plan stands
  EXPECT_TRUE(houses_under(bp, apart).empty());
}

// The same two houses and a shed apart from them (x 3..9, y 16..19): three
// buildings, numbered in the order modelled, with nothing left out.
TEST(Reconstruct, HousesOfARoofThatCameApartAreModelledInTurn) {
  std::mt19937_64 rng(41);
  const Plane flat = plane_through({0, 0, 103}, {0, 0.02, 1});
  ParcelScene s = square_parcel_scene();
  s.roof_points = sample_plane(flat, 1, 9, 6, 14, 40, 0.02, rng);
  for (auto part : {sample_plane(flat, 11, 19, 6, 14, 40, 0.02, rng),
                    sample_plane(flat, 9, 11, 9.5, 10.5, 40, 0.02, rng),
                    sample_plane(plane_through({0, 0, 102}, {0.1, 0, 1}), 3, 9, 16, 19, 40, 0.02, rng)})
    s.roof_points.insert(s.roof_points.end(), part.begin(), part.end());
  const ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 3u);
  std::set<std::string> ids;
  for (const auto& b : r.buildings) {
    ids.insert(b.id);
    EXPECT_TRUE(b.solid_valid) << b.id << " " << b.solid_problem;
  }
  EXPECT_EQ(ids, (std::set<std::string>{"P_b1", "P_b2", "P_b3"}));
  EXPECT_EQ(r.reason, "");
}

// ---- roof points no plane takes -------------------------------------------

namespace {

// The gable house with a strip along its south eave that no plane takes:
// sheet laid in a zigzag (teeth 0.6 m wide tilted 20 degrees either way, each
// too small for a roof plane) 0.25 m above the south plane, 1.2 m wide
// (y 4.3 .. 5.5), like the eave strips of the Cimahi roofs.
ParcelScene house_with_zigzag_eave_strip(unsigned seed) {
  std::mt19937_64 rng(seed);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  const Plane south = plane_through({0, 10, 106}, {0, -0.75, 1});
  std::uniform_real_distribution<double> ux(4.5, 15.5), uy(4.3, 5.5);
  std::normal_distribution<double> noise(0, 0.02);
  const double tooth = 0.6, rise = tooth * std::tan(20 * M_PI / 180);
  for (int i = 0; i < int(11 * 1.2 * 60); ++i) {
    double x = ux(rng), y = uy(rng);
    double t = std::fmod(x, 2 * tooth);
    double zig = rise * (t < tooth ? t / tooth : 2 - t / tooth);
    s.roof_points.emplace_back(x, y, south.z_at(x, y) + 0.25 + zig + noise(rng));
  }
  return s;
}

}  // namespace

TEST(Reconstruct, ZigzagEaveStripNoPlaneTakesIsStillInsideTheRoof) {
  ParcelScene s = house_with_zigzag_eave_strip(21);
  ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 1u);
  EXPECT_TRUE(r.buildings[0].solid_valid) << r.buildings[0].solid_problem;
  // The roof reaches y = 4.3, not the south plane's own edge at 5.5 (99 m^2).
  EXPECT_NEAR(totals(r.buildings[0]).roof_plan, 11.0 * 10.2, 11.0 * 10.2 * 0.03);
  EXPECT_LT(r.buildings[0].roof_deviation.mean, 0.3) << "the strip's points have a roof under them";
}

TEST(Reconstruct, BoxStandingOverTheEaveDoesNotWidenTheRoof) {
  // A 3 m water-tank box stands on the south eave and reaches 0.8 m past it.
  // Its sides are steep and its lid stands 1.2 m above the roof: neither is
  // roof surface, so the outline keeps to the eave.
  std::mt19937_64 rng(22);
  ParcelScene s = square_parcel_scene();
  s.roof_points = gable_points(rng);
  const Plane south = plane_through({0, 10, 106}, {0, -0.75, 1});
  std::uniform_real_distribution<double> u(0, 1);
  const double base = south.z_at(10, 5.5), top = base + 1.2;
  auto side = [&](Vec2 a, Vec2 b) {
    for (int i = 0; i < int((b - a).norm() * 1.2 * 60); ++i) {
      Vec2 p = a + u(rng) * (b - a);
      s.roof_points.emplace_back(p.x(), p.y(), base + u(rng) * (top - base));
    }
  };
  side({8.5, 4.7}, {11.5, 4.7});
  side({8.5, 4.7}, {8.5, 6.2});
  side({11.5, 4.7}, {11.5, 6.2});
  for (int i = 0; i < int(3 * 1.5 * 40); ++i) s.roof_points.emplace_back(8.5 + 3 * u(rng), 4.7 + 1.5 * u(rng), top);
  ParcelResult r = reconstruct_parcel(s, params());
  ASSERT_EQ(r.status, ParcelStatus::Ok) << r.reason;
  ASSERT_EQ(r.buildings.size(), 1u);
  EXPECT_NEAR(totals(r.buildings[0]).roof_plan, 11.0 * 9.0, 11.0 * 9.0 * 0.01);
}

TEST(ReconstructBadInput, RoofOnTheTerrainIsNoBuildingAndTheParcelSaysSo) {
  // A ground patch in the building class (AHN3 09088): a flat "roof" 6 x 5 m
  // lying on the terrain. No solid of any LoD can stand on it, and no invalid
  // solid is ever reported as modelled: the parcel fails and says why.
  std::mt19937_64 rng(3);
  ParcelScene s = square_parcel_scene();  // terrain at 100 m
  s.roof_points = sample_plane(plane_through({0, 0, 100}, {0, 0, 1}), 7, 13, 7, 12, 40, 0.01, rng);
  const ParcelResult r = reconstruct_parcel(s, params());
  EXPECT_TRUE(r.buildings.empty());
  EXPECT_EQ(r.status, ParcelStatus::Failed) << r.reason;
  EXPECT_NE(r.reason.find("no valid model"), std::string::npos) << r.reason;
}
