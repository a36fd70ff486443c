// Envelope sub-stage "wall evidence" from an airborne scan's facade points:
// the few points of the roof class lower than the eave show where an edge's
// wall stands (sparse_wall), or the building's overhang (pooled); clutter at
// one height, the opposite wall and a scene with a wall scan do not.

#include <gtest/gtest.h>

#include <vector>

#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/envelope/wall_evidence.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

// A 10 x 8 m flat roof at z = 3 (flat_roof_input: default overhang 0.3 m).
EnvelopeInput shed() { return flat_roof_input("f", Polygon2{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}}); }

// Roof points over the whole roof (on it, never facade points).
void add_roof(EnvelopeInput& in) {
  for (double x = 0.1; x < 10; x += 0.3)
    for (double y = 0.1; y < 8; y += 0.3) in.roof_points.emplace_back(x, y, 3.0);
}

// A facade point under the south edge (y = 0, outward -y) at x, `inside` m
// in from the edge, at height z.
void facade_south(EnvelopeInput& in, double x, double inside, double z) { in.roof_points.emplace_back(x, inside, z); }

}  // namespace

TEST(EnvelopeFacadePoints, ThreePointsUnderAnEdgeShowItsWall) {
  EnvelopeInput in = shed();
  add_roof(in);
  facade_south(in, 2.0, 0.22, 0.8);
  facade_south(in, 5.0, 0.18, 1.9);
  facade_south(in, 7.5, 0.20, 1.3);
  const std::vector<OutlineEdge> edges = measure_edges(in);
  EXPECT_EQ(edges[0].evidence, WallEvidence::Measured);
  EXPECT_NEAR(edges[0].overhang, 0.20, 1e-9);  // their median
  EXPECT_EQ(edges[0].support, 3);
  // The other edges take the building's overhang from the one wall seen.
  for (size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(edges[i].evidence, WallEvidence::Propagated);
    EXPECT_NEAR(edges[i].overhang, 0.20, 1e-9);
  }
}

TEST(EnvelopeFacadePoints, TwoPointsOnTwoEdgesShowTheBuildingsOverhang) {
  EnvelopeInput in = shed();
  add_roof(in);
  facade_south(in, 4.0, 0.05, 0.9);              // south wall, 5 cm in
  in.roof_points.emplace_back(9.93, 4.0, 2.0);   // east wall, 7 cm in
  const std::vector<OutlineEdge> edges = measure_edges(in);
  for (const OutlineEdge& e : edges) {
    EXPECT_EQ(e.evidence, WallEvidence::Propagated);
    EXPECT_NEAR(e.overhang, 0.06, 1e-9);
  }
}

TEST(EnvelopeFacadePoints, ClutterAtOneHeightIsNoWall) {
  // A porch roof 1.2 m inside the south edge at z = 2.2: many points, one height.
  EnvelopeInput in = shed();
  add_roof(in);
  for (double x = 2; x < 8; x += 0.3) facade_south(in, x, 1.2, 2.2);
  for (const OutlineEdge& e : measure_edges(in)) {
    EXPECT_EQ(e.evidence, WallEvidence::Default);
    EXPECT_DOUBLE_EQ(e.overhang, 0.3);
  }
}

TEST(EnvelopeFacadePoints, PointsNearTheEaveOrTheGroundAreNoWall) {
  EnvelopeInput in = shed();
  for (double x = 2; x < 8; x += 1.0) {
    facade_south(in, x, 0.2, 2.7);   // a gutter: within 0.5 m of the eave
    facade_south(in, x, 0.2, 0.1);   // a hedge, a car: within 0.3 m of the terrain
  }
  for (const OutlineEdge& e : measure_edges(in)) EXPECT_EQ(e.evidence, WallEvidence::Default);
}

TEST(EnvelopeFacadePoints, ANarrowShedsOppositeWallIsNotThisEdgesWall) {
  // 2 m deep: the south wall's points lie 1.6 m inside the north edge, within
  // any overhang of it, but nearer the south edge, whose wall they show.
  EnvelopeInput in = flat_roof_input("n", Polygon2{{{0, 0}, {4, 0}, {4, 2}, {0, 2}}, {}});
  for (double x : {1.0, 2.0, 3.0}) in.roof_points.emplace_back(x, 0.4, 0.6 + 0.5 * x);
  const std::vector<OutlineEdge> edges = measure_edges(in);
  EXPECT_EQ(edges[0].evidence, WallEvidence::Measured);  // south
  EXPECT_NEAR(edges[0].overhang, 0.4, 1e-9);
  EXPECT_NE(edges[2].evidence, WallEvidence::Measured);  // north
  EXPECT_NEAR(edges[2].overhang, 0.4, 1e-9);             // the building's, propagated
}

TEST(EnvelopeFacadePoints, AWallScanOutranksTheRoofClasssLowPoints) {
  // With a wall scan in the scene, low roof-class points are porches and
  // clutter the wall scan has placed; the seen wall decides.
  // Here the wall scan saw the east wall 0.5 m in; the south edge's low
  // points take no part, and the south wall takes the building's overhang.
  EnvelopeInput in = shed();
  see_wall(in, {9.5, 0}, {9.5, 8}, 21, 800);
  for (double x = 2; x < 8; x += 1.0) facade_south(in, x, 0.05, 0.5 + 0.2 * x);
  const std::vector<OutlineEdge> edges = measure_edges(in);
  EXPECT_EQ(edges[1].evidence, WallEvidence::Measured);
  EXPECT_NEAR(edges[1].overhang, 0.5, 0.01);
  EXPECT_EQ(edges[0].evidence, WallEvidence::Propagated);
  EXPECT_NEAR(edges[0].overhang, 0.5, 0.01);
}

TEST(EnvelopeFacadePoints, FacadeOffsetsGoToTheNearestEdge) {
  EnvelopeInput in = shed();
  facade_south(in, 5.0, 0.3, 1.0);
  in.roof_points.emplace_back(0.2, 4.0, 1.0);  // west wall
  in.roof_points.emplace_back(5.0, 4.0, 1.0);  // the middle: deeper than any overhang
  const std::vector<OutlineEdge> edges = measure_edges(in);
  const std::vector<FacadePoints> low = facade_offsets(in, edges, in.roof_points);
  ASSERT_EQ(low.size(), 4u);
  ASSERT_EQ(low[0].size(), 1u);
  EXPECT_NEAR(low[0][0].offset, -0.3, 1e-12);
  EXPECT_TRUE(low[1].empty());
  EXPECT_TRUE(low[2].empty());
  ASSERT_EQ(low[3].size(), 1u);
  EXPECT_NEAR(low[3][0].offset, -0.2, 1e-12);
}
