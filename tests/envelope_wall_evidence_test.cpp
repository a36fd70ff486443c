// Envelope sub-stage "wall evidence" alone: fit_wall on synthetic wall
// points, the building's and a facade's overhang, roof steps, and the wall
// under each outline edge of a house (measured, propagated, default, party).

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/envelope/wall_evidence.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

// `count` points (`noise` m across, z 0.3 to 3 m) of a wall parallel to the
// edge (0,0) -> (10,0) at signed offset `offset` (negative: inside, +y),
// from x0 to x1 along it.
std::vector<Vec3> wall_along_x(double offset, double x0, double x1, int count, unsigned seed,
                               double noise = 0.02) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uz(0.3, 3.0);
  std::normal_distribution<double> n(0, noise);
  std::vector<Vec3> pts;
  for (int i = 0; i < count; ++i) pts.emplace_back(ux(rng), -offset + n(rng), uz(rng));
  return pts;
}

const Vec2 kA(0, 0), kB(10, 0);  // the edge; outward is -y

}  // namespace

TEST(EnvelopeWallEvidence, FitWallFindsAWallInsideTheEdgeAtItsOffset) {
  const WallFit fit = fit_wall(wall_along_x(-0.45, 0, 10, 1000, 1), kA, kB, 0, 10);
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.offset, -0.45, 0.005);  // the mean of ~800 points of 2 cm noise
  EXPECT_NEAR(fit.rms, 0.02, 0.004);
  EXPECT_GT(fit.support, 600);  // the points along the middle 80 % of the edge
  EXPECT_LE(fit.support, 1000);
}

TEST(EnvelopeWallEvidence, FitWallFindsAWallOutsideTheEdgeUpTo60cm) {
  const WallFit near = fit_wall(wall_along_x(0.3, 0, 10, 1000, 2), kA, kB, 0, 10);
  ASSERT_TRUE(near.found);
  EXPECT_NEAR(near.offset, 0.3, 0.005);
  // Farther out stands a fence or a neighbour: no wall of this edge.
  EXPECT_FALSE(fit_wall(wall_along_x(0.9, 0, 10, 1000, 3), kA, kB, 0, 10).found);
  // Deeper inside than any overhang: an inner facade.
  EXPECT_FALSE(fit_wall(wall_along_x(-2.2, 0, 10, 1000, 4), kA, kB, 0, 10).found);
}

TEST(EnvelopeWallEvidence, NoWallWhereThePointsShowNone) {
  EXPECT_FALSE(fit_wall({}, kA, kB, 0, 10).found);
  // Scattered points, no peak: a few per offset bin.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(0, 10), us(-1.8, 0.6), uz(0.3, 3.0);
  std::vector<Vec3> scatter;
  for (int i = 0; i < 200; ++i) scatter.emplace_back(ux(rng), -us(rng), uz(rng));
  EXPECT_FALSE(fit_wall(scatter, kA, kB, 0, 10).found);
  // A pole: many points at one offset over a few decimetres of the edge.
  EXPECT_FALSE(fit_wall(wall_along_x(-0.5, 4.9, 5.3, 500, 6), kA, kB, 0, 10).found);
  // The wall's points all below min_z (a garden wall) or above max_z.
  EXPECT_FALSE(fit_wall(wall_along_x(-0.5, 0, 10, 1000, 7), kA, kB, 3.5, 10).found);
  EXPECT_FALSE(fit_wall(wall_along_x(-0.5, 0, 10, 1000, 7), kA, kB, 0, 0.2).found);
  // An edge shorter than 0.8 m shows no wall.
  EXPECT_FALSE(fit_wall(wall_along_x(-0.5, 0, 0.7, 1000, 8), kA, Vec2(0.7, 0), 0, 10).found);
}

TEST(EnvelopeWallEvidence, BeyondEndsLooksOnlyPastTheEdgesEnds) {
  // The facade of attached neighbours continuing the edge's line 0.2 m inside.
  std::vector<Vec3> pts = wall_along_x(-0.2, -1.5, 0, 300, 9);
  const auto east = wall_along_x(-0.2, 10, 11.5, 300, 10);
  pts.insert(pts.end(), east.begin(), east.end());
  EXPECT_FALSE(fit_wall(pts, kA, kB, 0, 10).found);
  const WallFit fit = fit_wall(pts, kA, kB, 0, 10, true);
  ASSERT_TRUE(fit.found);
  EXPECT_NEAR(fit.offset, -0.2, 0.01);
}

TEST(EnvelopeWallEvidence, WeightedMedianAndTypicalOverhang) {
  EXPECT_DOUBLE_EQ(weighted_median({{0.0, 1}, {0.5, 1}, {0.8, 3}}), 0.8);
  EXPECT_DOUBLE_EQ(weighted_median({{0.8, 1}, {0.0, 3}, {0.5, 1}}), 0.0);
  // Median 0.5; the flush wall (0.0) is outside the 0.1 m window.
  EXPECT_NEAR(typical_overhang({{0.5, 10}, {0.55, 10}, {0.0, 2}}), 0.525, 1e-12);
}

TEST(EnvelopeWallEvidence, FacadeOverhangWhereAFacadeClearlyDiffers) {
  const Vec2 east(1, 0), north(0, 1);
  const std::vector<SeenWall> seen{{0, east, {0.8, 8}}, {1, north, {0.0, 10}}};
  EXPECT_NEAR(facade_overhang(seen, east, 0.2), 0.8, 1e-12);
  EXPECT_NEAR(facade_overhang(seen, -east, 0.2), 0.8, 1e-12);  // either direction
  EXPECT_NEAR(facade_overhang(seen, north, 0.2), 0.2, 1e-12);  // within 0.3 m of the building's
  // Less than 3 m of seen wall is no facade.
  EXPECT_NEAR(facade_overhang({{0, east, {0.8, 2}}}, east, 0.2), 0.2, 1e-12);
}

TEST(EnvelopeWallEvidence, AShortEdgeOnTheLineOfARoofStepContinuesIt) {
  const Plane low = plane_through({0, 0, 3}, {0, 0, 1}), high = plane_through({0, 0, 6}, {0, 0, 1});
  const std::vector<RoofRegion> roof{RoofRegion{0, low, {Polygon2{{{0, 0}, {10, 0}, {10, 5}, {0, 5}}, {}}}},
                                     RoofRegion{1, high, {Polygon2{{{0, 5}, {10, 5}, {10, 10}, {0, 10}}, {}}}}};
  OutlineEdge on_step;  // on the line y = 5 running west into the step
  on_step.a = {11.5, 5};
  on_step.b = {10.5, 5};
  EXPECT_TRUE(continues_step(on_step, roof));
  OutlineEdge longer = on_step;  // a wall of its own
  longer.a = {13, 5};
  EXPECT_FALSE(continues_step(longer, roof));
  OutlineEdge off_step = on_step;  // on a line with one level on both sides
  off_step.a = {11.5, 2};
  off_step.b = {10.5, 2};
  EXPECT_FALSE(continues_step(off_step, roof));
}

TEST(EnvelopeWallEvidence, EdgesOfAHouseMeasuredPropagatedAndParty) {
  // Flat roof 11 x 9 m with 0.5 m overhang over a 10 x 8 m house; the south
  // and west walls seen, the east edge on the parcel boundary.
  EnvelopeInput in = flat_roof_input("t", Polygon2{{{-0.5, -0.5}, {10.5, -0.5}, {10.5, 8.5}, {-0.5, 8.5}}, {}});
  see_south_and_west_walls(in, 7);
  in.party_edge = {false, true, false, false};
  const std::vector<OutlineEdge> edges = measure_edges(in);
  ASSERT_EQ(edges.size(), 4u);
  EXPECT_EQ(edges[0].evidence, WallEvidence::Measured);  // south
  EXPECT_NEAR(edges[0].overhang, 0.5, 0.01);
  EXPECT_GT(edges[0].support, 100);
  EXPECT_EQ(edges[1].evidence, WallEvidence::ParcelBoundary);  // east
  EXPECT_TRUE(edges[1].party);
  EXPECT_EQ(edges[1].overhang, 0.0);
  EXPECT_EQ(edges[2].evidence, WallEvidence::Propagated);  // north: the building's overhang
  EXPECT_NEAR(edges[2].overhang, 0.5, 0.01);
  EXPECT_EQ(edges[2].support, 0);
  EXPECT_EQ(edges[3].evidence, WallEvidence::Measured);  // west
  EXPECT_NEAR(edges[3].overhang, 0.5, 0.01);
  EXPECT_LT(edges[0].sigma, edges[2].sigma);  // a seen wall is known better
}

TEST(EnvelopeWallEvidence, NoWallSeenTakesTheDefaultOverhang) {
  EnvelopeInput in = flat_roof_input("t", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}});
  in.default_overhang = 0.4;
  for (const OutlineEdge& e : measure_edges(in)) {
    EXPECT_EQ(e.evidence, WallEvidence::Default);
    EXPECT_DOUBLE_EQ(e.overhang, 0.4);
    // One assumed overhang for every wall: its error is theirs together.
    EXPECT_DOUBLE_EQ(e.sigma, 0.0);
    EXPECT_DOUBLE_EQ(e.sigma_shared, kUnseenSpread);
  }
}

TEST(EnvelopeWallEvidence, FacadeOnTheNeighboursPropagatesWhenNoWallIsSeen) {
  // A row house: no wall of its own seen, but its street facade runs on
  // 0.3 m inside the south edge on both neighbours.
  EnvelopeInput in = flat_roof_input("row", Polygon2{{{0, 0}, {8, 0}, {8, 10}, {0, 10}}, {}});
  see_wall(in, {-1.6, 0.3}, {0, 0.3}, 11, 400);
  see_wall(in, {8, 0.3}, {9.6, 0.3}, 12, 400);
  const std::vector<OutlineEdge> edges = measure_edges(in);
  EXPECT_EQ(edges[0].evidence, WallEvidence::Propagated);
  EXPECT_NEAR(edges[0].overhang, 0.3, 0.01);
  EXPECT_GT(edges[0].support, 0);
  EXPECT_EQ(edges[2].evidence, WallEvidence::Default);  // the yard side: nothing seen
}

TEST(EnvelopeWallEvidence, GrowsTheOutlineOntoAWallJustOutsideIt) {
  // The outline stops 0.3 m short of the south wall (the eave's points missing).
  EnvelopeInput in = flat_roof_input("g", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}});
  see_wall(in, {0, -0.3}, {10, -0.3}, 13, 1500);
  const MultiPolygon2 room{Polygon2{{{-5, -5}, {15, -5}, {15, 15}, {-5, 15}}, {}}};
  const GrownOutline g = grow_to_walls_outside(in, room);
  EXPECT_NEAR(area(g.outline), 10 * 8.3, 0.1);
  ASSERT_EQ(g.walls.size(), 1u);
  EXPECT_NEAR(g.walls[0].a.y(), -0.3, 0.01);
  // No land to grow on: the outline as it is.
  const MultiPolygon2 parcel{Polygon2{{{-5, 0}, {15, 0}, {15, 15}, {-5, 15}}, {}}};
  const GrownOutline kept = grow_to_walls_outside(in, parcel);
  EXPECT_NEAR(area(kept.outline), 80, 1e-9);
  EXPECT_TRUE(kept.walls.empty());
}
