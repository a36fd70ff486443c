// Envelope sub-stage "roof pieces" alone: roof regions cut by a known
// footprint into pieces inside and outside the walls, whose areas add up.

#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/roof_pieces.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::envelope;
using namespace c3d::test;

namespace {

Polygon2 rect(double x0, double y0, double x1, double y1) { return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}}; }

const Plane kFlat = plane_through({0, 0, 3}, {0, 0, 1});

// Area of the pieces by (region, inside).
std::map<std::pair<int, bool>, double> areas(const std::vector<Piece>& pieces) {
  std::map<std::pair<int, bool>, double> out;
  for (const Piece& p : pieces) out[{p.region, p.inside}] += area(p.plan);
  return out;
}

}  // namespace

TEST(EnvelopeRoofPieces, OneRegionSplitsIntoInsideAndHangingPieces) {
  const std::vector<RoofRegion> roof{RoofRegion{0, kFlat, {rect(0, 0, 12, 10)}}};
  const std::vector<Piece> pieces = roof_pieces(roof, rect(1, 1, 11, 9));
  ASSERT_EQ(pieces.size(), 2u);
  auto a = areas(pieces);
  EXPECT_NEAR((a[{0, true}]), 80, 1e-9);   // the footprint
  EXPECT_NEAR((a[{0, false}]), 40, 1e-9);  // the frame of overhang round it
  EXPECT_EQ(a.size(), 2u);
  for (const Piece& p : pieces)
    if (!p.inside) EXPECT_EQ(p.plan.holes.size(), 1u);  // the frame holds the footprint
}

TEST(EnvelopeRoofPieces, TwoRegionsFourPiecesAddingUpToEachRegion) {
  const std::vector<RoofRegion> roof{RoofRegion{0, kFlat, {rect(0, 0, 6, 10)}},
                                     RoofRegion{1, kFlat, {rect(6, 0, 12, 10)}}};
  const Polygon2 fp = rect(1, 1, 11, 9);
  auto a = areas(roof_pieces(roof, fp));
  EXPECT_NEAR((a[{0, true}]), 5 * 8, 1e-9);
  EXPECT_NEAR((a[{1, true}]), 5 * 8, 1e-9);
  EXPECT_NEAR((a[{0, true}] + a[{0, false}]), 60, 1e-9);
  EXPECT_NEAR((a[{1, true}] + a[{1, false}]), 60, 1e-9);
  EXPECT_NEAR((a[{0, true}] + a[{1, true}]), area(fp), 1e-9);
}

TEST(EnvelopeRoofPieces, AThinStripIsGivenToItsNeighbourNotDropped) {
  // Region 1 a strip 2 cm wide along the north edge: a partition artefact.
  const std::vector<RoofRegion> roof{RoofRegion{0, kFlat, {rect(0, 0, 12, 9.98)}},
                                     RoofRegion{1, kFlat, {rect(0, 9.98, 12, 10)}}};
  auto a = areas(roof_pieces(roof, rect(1, 1, 11, 9)));
  EXPECT_NEAR((a[{0, true}]), 80, 1e-9);
  EXPECT_NEAR((a[{0, false}]), 40, 1e-9);
  EXPECT_EQ(a.count({1, false}), 0u);
  EXPECT_EQ(a.count({1, true}), 0u);
}

TEST(EnvelopeRoofPieces, AMergedStripStaysWithinTheRoofsHeights) {
  // Region 0 (flat, z 3) hangs 4 cm over the west wall and 0.5 m over the
  // east one: the west strip is a fragment beside the larger east overhang.
  // Its one neighbour beyond the walls is a steep region (z = 3 + 2 (y - 9)),
  // whose plane would put the strip's south end 16 m under the roof (AHN3
  // 09087: such a strip dipped under the terrain); it stays with region 0.
  const std::vector<RoofRegion> roof{RoofRegion{0, kFlat, {rect(0.96, 1, 11.5, 9)}},
                                     RoofRegion{1, plane_through({0, 9, 3}, {0, -2, 1}), {rect(0, 9, 12, 10)}}};
  auto a = areas(roof_pieces(roof, rect(1, 1, 11, 9)));
  EXPECT_NEAR((a[{0, false}]), 0.04 * 8 + 0.5 * 8, 1e-9);
  EXPECT_NEAR((a[{1, false}]), 12, 1e-9);
}

TEST(EnvelopeRoofPieces, AGapBetweenRegionsIsFilledByANeighbour) {
  // 4 mm between the two regions: under the footprint 0.032 m^2 of gap.
  const std::vector<RoofRegion> roof{RoofRegion{0, kFlat, {rect(0, 0, 5.998, 10)}},
                                     RoofRegion{1, kFlat, {rect(6.002, 0, 12, 10)}}};
  auto a = areas(roof_pieces(roof, rect(1, 1, 11, 9)));
  EXPECT_NEAR((a[{0, true}] + a[{1, true}]), 80, 1e-9);
  // Beyond the footprint the gap is open (no ring closes it): no roof there.
  EXPECT_NEAR((a[{0, false}] + a[{1, false}]), 40 - 2 * 0.004, 1e-9);
  // A gap of 8 cm is a gap: no roof stands there.
  const std::vector<RoofRegion> apart{RoofRegion{0, kFlat, {rect(0, 0, 5.96, 10)}},
                                      RoofRegion{1, kFlat, {rect(6.04, 0, 12, 10)}}};
  auto b = areas(roof_pieces(apart, rect(1, 1, 11, 9)));
  EXPECT_NEAR((b[{0, true}] + b[{1, true}]), 80 - 0.08 * 8, 1e-9);
}

TEST(EnvelopeRoofPieces, SimplePiecesSplitARingPassingTwiceThroughAVertex) {
  const Ring2 eight{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}};
  const std::vector<Piece> pieces = simple_pieces({Piece{3, false, {eight, {}}}}, rect(5, 5, 6, 6));
  ASSERT_EQ(pieces.size(), 2u);
  for (const Piece& p : pieces) {
    EXPECT_EQ(p.region, 3);
    EXPECT_FALSE(p.inside);
    EXPECT_NEAR(area(p.plan), 1, 1e-12);
  }
}

TEST(EnvelopeRoofPieces, SimplePiecesNodeAVertexOfTheFootprintIntoAPieceEdge) {
  // The footprint's corner (4, 0) lies on the piece's south edge.
  const std::vector<Piece> pieces = simple_pieces({Piece{0, true, rect(0, 0, 10, 5)}}, rect(4, 0, 6, -2));
  ASSERT_EQ(pieces.size(), 1u);
  bool noded = false;
  for (const Vec2& v : pieces[0].plan.outer) noded = noded || (v - Vec2(4, 0)).norm() < 1e-12;
  EXPECT_TRUE(noded);
  EXPECT_NEAR(area(pieces[0].plan), 50, 1e-12);
}
