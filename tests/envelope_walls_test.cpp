// Stage "envelope": wall evidence, the footprint and where walls stand.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <random>

#include "core/config/config.h"
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

TEST(Envelope, WallPointsSetTheFootprintAndTheSolidCloses) {
  // Flat roof 10 x 8 m at z = 3 with 0.5 m overhang; walls seen on two sides.
  EnvelopeInput in = flat_roof_input("t", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_south_and_west_walls(in, 7);
  Building b = build_building(in);
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 80.0, 0.8);  // unseen walls take the measured overhang
  EXPECT_NEAR(t.roof, 99.0, 1e-6);
  EXPECT_NEAR(t.outer_ceiling, 19.0, 0.8);
  EXPECT_NEAR(t.wall, 2 * (10 + 8) * 3.0, 1.0);
  EXPECT_EQ(elements_with(b, WallEvidence::Measured), 2);
  EXPECT_EQ(elements_with(b, WallEvidence::Propagated), 2);
  EXPECT_GT(b.solid.size(), 5u);
}

TEST(Envelope, FlushGableWallIsBelievedNotTakenForAMisread) {
  // Flat roof over 10 x 8 m walls: 0.8 m overhang on three sides, none on the
  // east gable (x = 10). Each wall is seen. The east wall lies much nearer the
  // edge than the median overhang, yet it is where the points are: a wall
  // right under the roof edge is no misread (those lie further inside).
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n(0, 0.02);
  std::uniform_real_distribution<double> u(0, 1);
  EnvelopeInput in = flat_roof_input("flush", Polygon2{{{-0.8, -0.8}, {10.0, -0.8}, {10.0, 8.8}, {-0.8, 8.8}}, {}});
  for (int i = 0; i < 1500; ++i) {
    in.wall_points.emplace_back(10 * u(rng), 0 + n(rng), 3 * u(rng));   // south
    in.wall_points.emplace_back(10 * u(rng), 8 + n(rng), 3 * u(rng));   // north
    in.wall_points.emplace_back(0 + n(rng), 8 * u(rng), 3 * u(rng));    // west
    in.wall_points.emplace_back(10 + n(rng), 8 * u(rng), 3 * u(rng));   // east, flush
  }
  Building b = build_building(in);
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 80.0, 0.3);
  EXPECT_NEAR(t.outer_ceiling, 10.8 * 9.6 - 80.0, 0.3);
  EXPECT_EQ(elements_with(b, WallEvidence::Measured), 4);
}

TEST(Envelope, UnseenWallTakesTheOverhangOfTheFacadeParallelToIt) {
  // A row house 8 m along the street, 10 m deep: eaves of 0.8 m over the
  // street (south) and the yard (north), gable walls flush with the verges.
  // Seen: the street wall and the west gable, the longer one. The unseen yard
  // wall is an eave like the street's, the unseen east gable flush like the
  // west; pooled, the flush gable's length would outvote the eave and the
  // street wall's 0.8 m would be thrown out as a misread: 92.8 m^2 of floor.
  EnvelopeInput in = flat_roof_input("row", Polygon2{{{0, -0.8}, {8, -0.8}, {8, 10.8}, {0, 10.8}}, {}});
  see_wall(in, {0, 0}, {8, 0}, 21, 1500);
  see_wall(in, {0, 10.8}, {0, -0.8}, 22, 1500);
  Building b = build_building(in);
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 80.0, 0.5);
  EXPECT_NEAR(t.outer_ceiling, 8 * 11.6 - 80.0, 0.5);
  EXPECT_EQ(elements_with(b, WallEvidence::Measured), 2);
  EXPECT_EQ(elements_with(b, WallEvidence::Propagated), 2);
}

TEST(Envelope, UnseenWallsTakeTheOverhangOfMostEaveLength) {
  // 10 x 8 m walls under a roof with 0.5 m overhang and a 2 m wide porch bump
  // on the north whose sides are flush with their walls. Seen: the 11 m south
  // eave (0.5 m) and the two 1.2 m porch sides (0 m). By count the typical
  // overhang would be 0 and every unseen wall would move out to the roof edge
  // (ground 101.4 m2); by eave length it is 0.5 m.
  std::mt19937_64 rng(12);
  std::normal_distribution<double> n(0, 0.02);
  std::uniform_real_distribution<double> u(0, 1);
  EnvelopeInput in = flat_roof_input(
      "porch", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {6, 8.5}, {6, 9.7}, {4, 9.7}, {4, 8.5}, {-0.5, 8.5}},
                        {}});
  for (int i = 0; i < 1500; ++i) {
    in.wall_points.emplace_back(10 * u(rng), 0 + n(rng), 3 * u(rng));          // south eave
    in.wall_points.emplace_back(6 + n(rng), 8.6 + 0.6 * u(rng), 3 * u(rng));   // porch sides, flush
    in.wall_points.emplace_back(4 + n(rng), 8.6 + 0.6 * u(rng), 3 * u(rng));
  }
  Building b = build_building(in);
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 10 * 8 + 2 * 1.2, 0.3);
  EXPECT_NEAR(t.outer_ceiling, 11 * 9 - 10 * 8, 0.3);
}

TEST(Envelope, UnseenWallsTakeTheLengthWeightedMeanOfTheSeenEaves) {
  // 10 x 8 m walls; the roof hangs 0.46 m over the 11 m south eave and 0.54 m
  // over the 9 m west eave, both seen, as two reads of one 0.5 m overhang that
  // are each a few centimetres off would be. Every seen eave counts, by its
  // length (its position is known to within σ² ∝ 1/length): the unseen north
  // and east walls take (0.46·11.0 + 0.54·9.0) / 20.0 = 0.496 m, not the
  // median's 0.46 m (ground 0.65 m² larger).
  EnvelopeInput in = flat_roof_input("two-eaves", Polygon2{{{-0.54, -0.46}, {10.5, -0.46}, {10.5, 8.5}, {-0.54, 8.5}}, {}});
  see_south_and_west_walls(in, 14);
  Building b = build_building(in);
  const double typical = (0.46 * 11.04 + 0.54 * 8.96) / 20.0;
  EXPECT_NEAR(totals(b).ground, (10.5 - typical) * (8.5 - typical), 0.2);
}

TEST(Envelope, WallSeenJustOutsideTheRoofOutlineStandsUnderThatEave) {
  // 10 x 8 m walls; the roof hangs 0.5 m over the west and north walls (both
  // seen) and is flush with the south wall, whose eave points are missing:
  // the outline stops 0.45 m short of it. The south wall is that edge's wall,
  // flush; taking the building's 0.5 m overhang there instead would put it
  // 0.95 m inside the points (ground 70.5 m2, not 75.5). The envelope alone
  // keeps the wall at the outline; a batch first grows the outline onto the
  // wall (OutlineGrowsOntoAWallSeenOutsideIt).
  EnvelopeInput in = flat_roof_input("short-eave", Polygon2{{{-0.5, 0.45}, {10.5, 0.45}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_wall(in, {0, 0}, {10, 0}, 31);  // south, 0.45 m outside the outline
  see_wall(in, {0, 8}, {0, 0}, 32);   // west
  see_wall(in, {10, 8}, {0, 8}, 33);  // north
  Building b = build_building(in);
  EXPECT_NEAR(totals(b).ground, 10.0 * (8.0 - 0.45), 0.3);
  int measured = 0;
  for (const auto& e : b.elements) {
    measured += e.evidence == WallEvidence::Measured;
    // The floor stops 0.45 m short of the south wall's points along its 10 m:
    // its σ says so (without that it would be about 0.5 m²).
    if (e.type == ElementType::Ground) EXPECT_GT(e.sigma_area, 10 * 0.4);
  }
  EXPECT_EQ(measured, 3);
}

TEST(Envelope, OutlineGrowsOntoAWallSeenOutsideIt) {
  // The case above, the way a batch models it: the outline is grown onto the
  // south wall, the roof (re-partitioned) reaches it, and the floor is the
  // 10 x 8 m inside the walls. A fence 1 m beyond the east edge (farther out
  // than kMaxOutside) moves nothing, nor does a wall on land the building
  // may not take.
  const Polygon2 outline{{{-0.5, 0.45}, {10.5, 0.45}, {10.5, 8.5}, {-0.5, 8.5}}, {}};
  EnvelopeInput in = flat_roof_input("grow", outline);
  see_wall(in, {0, 0}, {10, 0}, 31);      // south, 0.45 m outside the outline
  see_wall(in, {0, 8}, {0, 0}, 32);       // west, under the 0.5 m eave
  see_wall(in, {10, 8}, {0, 8}, 33);      // north, likewise
  see_wall(in, {11.5, 1}, {11.5, 8}, 38); // a fence 1 m east of the outline
  EXPECT_TRUE(grow_to_walls_outside(in, poly::box({-5, 0.45}, {15, 15})).walls.empty());
  const GrownOutline g = grow_to_walls_outside(in, poly::box({-5, -5}, {15, 15}));
  ASSERT_EQ(g.walls.size(), 1u);
  EXPECT_NEAR(area(g.outline), 11.0 * 8.5, 0.05);  // -0.5..10.5 x 0..8.5
  EXPECT_NEAR(g.walls[0].a.y(), 0.0, 0.01);
  EXPECT_NEAR(g.walls[0].b.y(), 0.0, 0.01);

  in.outline = g.outline;
  in.roof = {RoofRegion{0, in.roof[0].plane, {g.outline}}};
  in.walls_on_outline = g.walls;
  const Building b = build_building(in);
  const BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 80.0, 0.3);  // was 75.5 with the wall kept at the outline
  EXPECT_NEAR(t.roof, 11.0 * 8.5, 0.05);
  EXPECT_NEAR(t.outer_ceiling, 11.0 * 8.5 - 80.0, 0.3);
  EXPECT_EQ(elements_with(b, WallEvidence::Measured), 3);
  for (const auto& e : b.elements)  // the floor no longer stops short of the south wall
    if (e.type == ElementType::Ground) EXPECT_LT(e.sigma_area, 10 * 0.2);
  const SolidCheck check = check_solid(b.solid);
  EXPECT_TRUE(check.ok) << check.summary();
}

// A party wall running on in one line as a free wall (05797: 12 m of its
// south-west side meet the neighbour's roof, the last 9 m face a yard): the
// footprint steps where the overhang changes along the line instead of
// taking one of the two for the whole side.
TEST(Envelope, FootprintStepsWhereAPartyWallRunsOnAsAFreeWall) {
  // 10 x 8 m flat roof; its north side is two edges in one line, the east
  // half on the parcel line with the neighbour (party), the west half free.
  EnvelopeInput in = flat_roof_input("step", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {5, 8}, {0, 8}}, {}});
  in.party_edge = {false, false, true, false, false};
  const Building b = build_building(in);
  const SolidCheck check = check_solid(b.solid);
  EXPECT_TRUE(check.ok) << check.summary();
  const double o = in.default_overhang;
  const BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, (10 - 2 * o) * (8 - 2 * o) + (5 - o) * o, 1e-6);
  EXPECT_NEAR(t.party_wall, (5 - o) * 3, 1e-6);
  EXPECT_NEAR(t.wall, (10 - 2 * o) * 3 + 2 * (8 - 2 * o) * 3 + 5 * 3 + o * 3, 1e-6);  // the step's 0.3 m included
  EXPECT_NEAR(t.outer_ceiling, 80 - t.ground, 1e-6);
}

// Two outline edges almost in one line (1.5 degrees apart) with the same
// overhang are no step between two kinds of wall: the footprint is
// regularised as any other (here: the bend straightened, four corners). A
// step of millimetres between their moved lines kept a footprint on a 12 m
// grid over Cimahi from being regularised and broke a roof face.
TEST(Envelope, SameOverhangAlmostInLineIsNoStep) {
  EnvelopeInput in = flat_roof_input("bend", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {5, 8.065}, {0, 8}}, {}});
  const Building b = build_building(in);
  EXPECT_TRUE(check_solid(b.solid).ok);
  size_t grounds = 0;
  for (const Element& e : b.elements) {
    if (e.type != ElementType::Ground) continue;
    EXPECT_EQ(e.faces.at(0).ring.size(), 4u);
    ++grounds;
  }
  EXPECT_EQ(grounds, 1u);
}

TEST(Envelope, NoWallOutsideLeavesTheOutlineAsItIs) {
  EnvelopeInput in = flat_roof_input("keep", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_south_and_west_walls(in, 39);  // both 0.5 m inside their edges
  const GrownOutline g = grow_to_walls_outside(in, poly::box({-5, -5}, {15, 15}));
  EXPECT_TRUE(g.walls.empty());
  EXPECT_EQ(g.outline.outer, in.outline.outer);
}

TEST(Envelope, TallerWallBehindTheEdgeIsNotThisEdgesWall) {
  // 10 x 8 m walls under a flat roof at 3 m with 0.5 m overhang, south and west
  // seen. Behind the east edge, 0.8 m inside it, stands the wall of a taller
  // neighbour, seen only above this roof (3.6 to 7 m). It is not the east wall:
  // that wall takes the building's overhang (ground 80 m2); believing the
  // taller wall would cut the footprint to 9.7 x 8 m.
  EnvelopeInput in = flat_roof_input("taller-behind", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_south_and_west_walls(in, 34);
  see_wall(in, {9.7, 0}, {9.7, 8}, 35, 1500, 3.6, 7.0);
  Building b = build_building(in);
  EXPECT_NEAR(totals(b).ground, 80.0, 0.5);
}

TEST(Envelope, ShortBrightPatchDoesNotHideTheWallBehindIt) {
  // A gate post 0.2 m outside the south edge gives more points than the south
  // wall 0.5 m inside it, but covers only 0.6 m of the 11 m edge: the wall is
  // the next peak of the offsets, and it is the one that covers the edge.
  EnvelopeInput in = flat_roof_input("post", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_wall(in, {0, 0}, {10, 0}, 36);
  see_wall(in, {4.0, -0.7}, {4.6, -0.7}, 37, 3000);
  const WallFit fit = fit_wall(in.wall_points, {-0.5, -0.5}, {10.5, -0.5}, 0.3, 3.5);
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.offset, -0.5, 0.03);
}

TEST(Envelope, UnseenWallBesideALowerAnnexContinuesTheStepWall) {
  // A 10 x 8 m house (flat roof at 6 m, 0.5 m overhang, none on its east
  // gable) with a 4 x 4 m annex (roof at 3 m) against the middle of that gable.
  // No wall is seen. The two short outline edges beside the annex lie on the
  // step between the levels: the wall under them is the step wall carried
  // down, not set back by the overhang (which would notch 2 m2 out).
  EnvelopeInput in = flat_roof_input(
      "annex", Polygon2{{{-0.5, -0.5}, {10, -0.5}, {10, 1.5}, {14.5, 1.5}, {14.5, 6.5}, {10, 6.5}, {10, 8.5}, {-0.5, 8.5}},
                        {}});
  in.default_overhang = 0.5;
  Plane high = plane_through({0, 0, 6}, {0, 0, 1}), low = plane_through({0, 0, 3}, {0, 0, 1});
  in.roof = {RoofRegion{0, high, poly::box({-0.5, -0.5}, {10, 8.5})},
             RoofRegion{1, low, poly::box({10, 1.5}, {14.5, 6.5})}};
  in.fits = {in.fits[0], in.fits[0]};
  in.fits[0].plane = high;
  in.fits[1].plane = low;
  Building b = build_building(in);
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.ground, 10 * 8 + 4 * 4, 0.01);
  const SolidCheck check = check_solid(b.solid);
  EXPECT_TRUE(check.ok) << check.summary();
}

TEST(Envelope, IslandRoofCrossingTheRoofAroundItStaysClosed) {
  // A 2 x 2 m roof piece inside a larger one (a hole in it), their planes
  // tilted by 1 % in opposite directions along y, so they cross at y = 4 on
  // the island's west and east edges: there each roof walls the part where it
  // is the higher (two triangles per edge, 1 m long, 2 cm high at their ends);
  // along y = 3 the island is 2 cm higher, along y = 5 the roof around it.
  const EnvelopeInput in = with_island_roof(
      flat_roof_input("island", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}}),
      poly::box({-0.5, -0.5}, {10.5, 8.5}), poly::box({4, 3}, {6, 5}), plane_through({0, 4, 3}, {0, -0.01, 1}),
      plane_through({0, 4, 3}, {0, 0.01, 1}));
  Building b = build_building(in);
  const SolidCheck check = check_solid(b.solid);
  EXPECT_TRUE(check.ok) << check.summary();
  double step = 0;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Wall)
      for (const auto& f : e.faces) {
        bool on_island = true;
        for (const auto& v : f.ring)  // within the weld tolerance of the island
          on_island = on_island && v.x() > 4 - 1e-3 && v.x() < 6 + 1e-3 && v.y() > 3 - 1e-3 && v.y() < 5 + 1e-3;
        if (on_island) step += area(f);
      }
  EXPECT_NEAR(step, 4 * 0.5 * 1 * 0.02 + 2 * 2 * 0.02, 1e-6);
  // Each step is a wall element of its own, placed by the roof planes.
  for (const auto& e : b.elements)
    if (e.type == ElementType::Wall && e.area < 0.2) EXPECT_EQ(e.evidence, WallEvidence::RoofStep);
}

TEST(Envelope, SliverStepBetweenRoofPlanesJoinsTheNearestWall) {
  // A 1 x 1 m flat roof piece standing 2.2 mm above the flat roof around it
  // (just over the 2 mm at which heights are welded as one): its step wall
  // (4 m x 2.2 mm, under 0.01 m^2) stays in the shell, but as part of the
  // nearest wall element, not as a wall of its own that no one could point
  // at. A 5 mm step (0.02 m^2) stays a roof-step wall.
  for (double rise : {0.0022, 0.005}) {
    EnvelopeInput in = with_island_roof(flat_roof_input("sliver", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}}),
                                        poly::box({0, 0}, {10, 8}), poly::box({4.5, 3.5}, {5.5, 4.5}),
                                        plane_through({0, 0, 3}, {0, 0, 1}), plane_through({0, 0, 3 + rise}, {0, 0, 1}));
    in.default_overhang = 0.0;
    Building b = build_building(in);
    const SolidCheck check = check_solid(b.solid);
    EXPECT_TRUE(check.ok) << check.summary();
    double walls = 0;
    int steps = 0;
    for (const auto& e : b.elements) {
      if (e.type != ElementType::Wall) continue;
      walls += e.area;
      steps += e.evidence == WallEvidence::RoofStep;
      EXPECT_GE(e.area, 0.01) << "rise " << rise;
    }
    EXPECT_NEAR(walls, 36 * 3 + 4 * rise, 1e-6) << "rise " << rise;  // nothing lost
    EXPECT_EQ(steps, rise < 0.0025 ? 0 : 1) << "rise " << rise;
  }
}

TEST(Envelope, PartitionArtefactsNeverOpenOrPinchTheSolid) {
  // Two roof levels of a 10 x 8 m building (z 3 west, z 4 east) as a partition
  // may leave them: a 5 mm gap between the levels, a 2 cm thin spike of the
  // west level running to the east wall, and a 0.04 m^2 stray fragment of it
  // inside the east level. The gap must be filled (not a hole in the shell),
  // the spike must not touch the wall (a pinched solid), the fragment must go.
  EnvelopeInput in;
  in.building_id = "t";
  in.outline = Polygon2{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}};
  MultiPolygon2 spike{Polygon2{{{4.995, 3.99}, {10, 4.0}, {4.995, 4.01}}, {}}};
  MultiPolygon2 fragment = poly::box({7.0, 6.0}, {7.2, 6.2});
  MultiPolygon2 west = poly::unite_all({poly::box({0, 0}, {4.995, 8}), spike, fragment});
  MultiPolygon2 east = poly::subtract(poly::box({5.0, 0}, {10, 8}), west);
  Plane low = plane_through({0, 0, 3}, {0, 0, 1}), high = plane_through({0, 0, 4}, {0, 0, 1});
  in.roof = {RoofRegion{0, low, west}, RoofRegion{1, high, east}};
  PlaneFit fit;
  fit.rmse = 0.02;
  fit.inliers = 1000;
  in.fits = {fit, fit};
  in.terrain = [](double, double) { return 0.0; };
  in.default_overhang = 0.0;
  Building b = build_building(in);

  for (const auto& issue : validate_building(b, {}))
    ADD_FAILURE() << issue.code << " at " << issue.where << ": " << issue.message;
  BuildingTotals t = totals(b);
  EXPECT_NEAR(t.roof_plan, 80.0, 1e-6);  // nothing lost, nothing doubled
  EXPECT_NEAR(t.ground, 80.0, 1e-6);
  // The east level keeps its full wall: no spike of the low level reaches it.
  double east_wall = 0;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Wall && std::abs(e.azimuth_deg - 90) < 1) east_wall += e.area;
  EXPECT_NEAR(east_wall, 8 * 4.0, 1e-6);
  // The step between the levels is one wall element (under the east roof),
  // 8 m long and 1 m high, whatever the edge pieces its foot is made of.
  int steps = 0;
  for (const auto& e : b.elements)
    if (e.type == ElementType::Wall && e.evidence == WallEvidence::RoofStep) {
      ++steps;
      EXPECT_NEAR(e.area, 8.0, 0.05);
    }
  EXPECT_EQ(steps, 1);
  // The fragment went to the level around it: the west level is one rectangle.
  for (const auto& e : b.elements)
    if (e.type == ElementType::Roof && e.faces.front().ring.front().z() < 3.5)
      EXPECT_NEAR(e.plan_area, 5.0 * 8, 0.05);
}
