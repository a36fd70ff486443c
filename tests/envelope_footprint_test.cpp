// Envelope sub-stage "footprint" alone: outline edges moved in by known
// overhangs, steps between edges in one line, a footprint coming apart,
// specks, pinched rings and the terrain level under the footprint.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/geometry/geometry.h"
#include "core/reconstruct/envelope/footprint.h"

using namespace c3d;
using namespace c3d::envelope;

namespace {

// The edges of `outline`'s outer ring with the given overhangs (one per edge).
std::vector<OutlineEdge> edges_of(const Polygon2& outline, const std::vector<double>& overhangs) {
  const Ring2& r = outline.outer;
  std::vector<OutlineEdge> edges(r.size());
  for (size_t i = 0; i < r.size(); ++i) {
    edges[i].a = r[i];
    edges[i].b = r[(i + 1) % r.size()];
    edges[i].overhang = overhangs.at(i);
  }
  return edges;
}

// Whether the ring has a vertex within 1e-9 of p.
bool has_vertex(const Ring2& r, const Vec2& p) {
  for (const Vec2& v : r)
    if ((v - p).norm() < 1e-9) return true;
  return false;
}

const Polygon2 kRect{{{0, 0}, {12, 0}, {12, 10}, {0, 10}}, {}};

}  // namespace

TEST(EnvelopeFootprint, RectangleMovedInByEachEdgesOverhang) {
  // South 0.5, east 1.0, north 0.5, west flush.
  const Polygon2 fp = footprint_from_edges(edges_of(kRect, {0.5, 1.0, 0.5, 0.0}), kRect, 0.3, nullptr);
  EXPECT_NEAR(area(fp), 11.0 * 9.0, 1e-9);
  EXPECT_EQ(fp.outer.size(), 4u);
  for (const Vec2& p : {Vec2(0, 0.5), Vec2(11, 0.5), Vec2(11, 9.5), Vec2(0, 9.5)})
    EXPECT_TRUE(has_vertex(fp.outer, p)) << p.transpose();
}

TEST(EnvelopeFootprint, TwoEdgesInOneLineWithDifferentOverhangsStep) {
  // The south side in two edges: flush (a party wall) to x = 6, then 0.6 m in.
  const Polygon2 outline{{{0, 0}, {6, 0}, {12, 0}, {12, 10}, {0, 10}}, {}};
  const Polygon2 fp = footprint_from_edges(edges_of(outline, {0.0, 0.6, 0.5, 0.5, 0.5}), outline, 0.3, nullptr);
  EXPECT_NEAR(area(fp), 11.0 * 9.5 - 5.5 * 0.6, 1e-9);
  EXPECT_TRUE(has_vertex(fp.outer, {6, 0}));
  EXPECT_TRUE(has_vertex(fp.outer, {6, 0.6}));
  EXPECT_EQ(fp.outer.size(), 6u);
  // A difference under 5 cm is no step: the side is regularised into one wall.
  const Polygon2 even = footprint_from_edges(edges_of(outline, {0.5, 0.52, 0.5, 0.5, 0.5}), outline, 0.3, nullptr);
  EXPECT_EQ(even.outer.size(), 4u);
  EXPECT_GT(area(even), 11 * (9.5 - 0.52));  // between the two edges' lines
  EXPECT_LT(area(even), 11 * (9.5 - 0.5));
}

TEST(EnvelopeFootprint, ANarrowNeckUnderOneRoofComesApart) {
  // Two 8 x 8 m roofs joined by a walkway roof 1.2 m wide and 4 m long; walls
  // 0.6 m in from every edge: the walkway's two walls meet in one line and
  // hold no floor between them.
  const Polygon2 outline{{{0, 0}, {8, 0}, {8, 3.4}, {12, 3.4}, {12, 0}, {20, 0}, {20, 8}, {12, 8}, {12, 4.6},
                          {8, 4.6}, {8, 8}, {0, 8}},
                         {}};
  FootprintApart apart;
  const Polygon2 fp =
      footprint_from_edges(edges_of(outline, std::vector<double>(outline.outer.size(), 0.6)), outline, 0.3, &apart);
  ASSERT_EQ(apart.parts.size(), 2u);
  EXPECT_NEAR(area(apart.parts[0]), 6.8 * 6.8, 1e-6);
  EXPECT_NEAR(area(apart.parts[1]), 6.8 * 6.8, 1e-6);
  EXPECT_DOUBLE_EQ(apart.overhang, 0.6);
  EXPECT_NEAR(area(fp), 6.8 * 6.8, 1e-6);  // one of them
  // The same outline with flush walls stays one footprint.
  FootprintApart whole;
  footprint_from_edges(edges_of(outline, std::vector<double>(outline.outer.size(), 0.0)), outline, 0.3, &whole);
  EXPECT_EQ(whole.parts.size(), 1u);
}

TEST(EnvelopeFootprint, AnOutlineTooSmallForItsOverhangsThrows) {
  const Polygon2 tiny{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {}};
  EXPECT_THROW(footprint_from_edges(edges_of(tiny, {0.6, 0.6, 0.6, 0.6}), tiny, 0.6, nullptr), std::runtime_error);
}

TEST(EnvelopeFootprint, SpecksGoAndOtherEdgesStay) {
  // A 2 mm edge at the north-east corner.
  const Polygon2 specked{{{0, 0}, {10, 0}, {10, 8}, {9.998, 8.0}, {0, 8}}, {}};
  const Polygon2 clean = without_specks(specked);
  EXPECT_EQ(clean.outer.size(), 4u);
  EXPECT_NEAR(area(clean), 80, 1e-9);
  EXPECT_EQ(without_specks(kRect).outer, kRect.outer);
}

TEST(EnvelopeFootprint, APinchedRingSplitsIntoItsLobes) {
  // Two unit squares touching at (1,1), as one ring passing twice through it.
  const Ring2 eight{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}};
  EXPECT_TRUE(pinched(eight));
  EXPECT_TRUE(touches_itself(eight));
  EXPECT_FALSE(pinched(kRect.outer));
  const std::vector<Polygon2> lobes = split_pinched({eight, {}}, 1e-3);
  ASSERT_EQ(lobes.size(), 2u);
  EXPECT_NEAR(area(lobes[0]), 1, 1e-12);
  EXPECT_NEAR(area(lobes[1]), 1, 1e-12);
  EXPECT_EQ(separate_pinched({Polygon2{eight, {}}}).size(), 2u);
  EXPECT_EQ(separate_pinched({kRect}).size(), 1u);
}

TEST(EnvelopeFootprint, MeanTerrainUnderTheFootprint) {
  // z = x over [0,10] x [0,8]: the grid and the corners are symmetric about x = 5.
  const Polygon2 fp{{{0, 0}, {10, 0}, {10, 8}, {0, 8}}, {}};
  EXPECT_NEAR(mean_terrain(fp, [](double x, double) { return x; }), 5.0, 1e-9);
  EXPECT_NEAR(mean_terrain(fp, [](double, double) { return 100.0; }), 100.0, 1e-9);
  EXPECT_THROW(mean_terrain(fp, [](double, double) { return std::nan(""); }), std::runtime_error);
}
