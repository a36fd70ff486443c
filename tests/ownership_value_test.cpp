// Stage "ownership" on its own: the Ownership value decide_ownership builds
// from a scene and its segmentation, and the boundary queries answered from
// that value alone, on scenes whose answers are known.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/ownership/point_grid.h"
#include "core/reconstruct/segment/segmentation.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::test;

namespace {

Ownership decided(const ParcelScene& s) {
  return decide_ownership(s, segment_roofs(s.roof_points, params()), params());
}

size_t kept_points(const Ownership& own) {
  return size_t(std::count_if(own.label.begin(), own.label.end(), [](int l) { return l >= 0; }));
}

// Parcel A (x 0..10) and B (x 10..20), seen from `own` with `other` beside it.
ParcelScene beside(const Polygon2& own, const Polygon2& other, const std::vector<Vec3>& roof) {
  ParcelScene s = square_parcel_scene();
  s.parcel = {own};
  s.neighbours = {{other}};
  s.roof_points = roof;
  return s;
}

const Polygon2 kA{{{0, 0}, {10, 0}, {10, 20}, {0, 20}}, {}}, kB{{{10, 0}, {20, 0}, {20, 20}, {10, 20}}, {}};

}  // namespace

// The gable house (y 5.5..14.5) on A (y 0..14) hangs 0.5 m over B (y 14..30):
// an overhang. The roof goes whole to A, which holds most of it, and B keeps
// none of it; neither splits against the other.
TEST(OwnershipValue, RoofAcrossTheBoundaryGoesWholeToTheParcelHoldingMostOfIt) {
  std::mt19937_64 rng(12);
  const Polygon2 a{{{0, 0}, {20, 0}, {20, 14}, {0, 14}}, {}}, b{{{0, 14}, {20, 14}, {20, 30}, {0, 30}}, {}};
  const std::vector<Vec3> roof = gable_points(rng);
  const ParcelScene sa = beside(a, b, roof), sb = beside(b, a, roof);
  const Segmentation seg = segment_roofs(roof, params());
  const Ownership on_a = decide_ownership(sa, seg, params()), on_b = decide_ownership(sb, seg, params());
  size_t in_components = 0, across = 0;
  for (const auto& c : seg.components) in_components += c.points.size();
  for (const auto& q : roof) across += q.y() > 14;
  ASSERT_GT(across, 100u);
  EXPECT_EQ(kept_points(on_a), in_components);  // the overhang over B included
  EXPECT_EQ(on_a.label, seg.label);
  EXPECT_TRUE(on_a.split_with.empty());
  EXPECT_TRUE(on_a.cut.empty());
  EXPECT_EQ(kept_points(on_b), 0u);
  for (const auto& points : on_b.component_points) EXPECT_TRUE(points.empty());
  EXPECT_TRUE(on_b.split_with.empty());
}

// One flat roof (x 1..19, y 4..14) over attached houses on A and B reaches
// deep into both: each splits it at the boundary, keeps the part on its own
// land and may not reach onto the other's.
TEST(OwnershipValue, SharedRoofIsSplitAtTheBoundary) {
  std::mt19937_64 rng(59);
  const auto roof = sample_plane(plane_through({0, 0, 104}, {0, 0.02, 1}), 1, 19, 4, 14, 40, 0.02, rng);
  for (const auto& [own_parcel, other] : {std::pair{kA, kB}, std::pair{kB, kA}}) {
    const ParcelScene s = beside(own_parcel, other, roof);
    const Ownership own = decided(s);
    EXPECT_EQ(own.split_with, std::set<int>{0});
    size_t on_own = 0;
    for (size_t i = 0; i < roof.size(); ++i) {
      const bool here = poly::covers(s.parcel, roof[i].head<2>());
      on_own += here;
      if (!here) EXPECT_LT(own.label[i], 0) << roof[i].transpose();
    }
    EXPECT_GT(double(kept_points(own)), 0.97 * double(on_own));
    EXPECT_TRUE(poly::covers(own.cut, (other.outer[0] + other.outer[2]) / 2));  // the other's land
    EXPECT_FALSE(poly::covers(own.cut, (own_parcel.outer[0] + own_parcel.outer[2]) / 2));
  }
}

// This parcel's flat roof (x 3..17, y 2..10) reaches the boundary y = 10. With
// the neighbour's roof running on 6 m beyond it, the north edge is a party
// edge; with only a 0.3 m strip of roof across (a gutter), it is not.
TEST(OwnershipValue, PartyEdgeWhereTheNeighboursRoofIsRightAcross) {
  const Polygon2 outline{{{3, 2}, {17, 2}, {17, 10}, {3, 10}}, {}};
  for (const double depth : {6.0, 0.3}) {
    std::mt19937_64 rng(23);
    const Ownership own = decided(flat_roof_at_the_line(rng, 101.5, 2, 18, 10.05, 10.05 + depth));
    EXPECT_EQ(find_party_edges(outline, own), (std::vector<bool>{false, false, depth > 1, false})) << depth;
    EXPECT_EQ(split_where_neighbour_roof_ends(outline, own).outer.size(), 4u) << depth;  // across all of it, or none
  }
}

// The queries read the value only: decided from a scene that is gone, and
// from a copy, they give the scene's answers. The neighbour's house across
// y = 10 meets this roof from x = 2 to x = 10 only: a vertex there, the
// stretch along the house a party edge.
TEST(OwnershipValue, QueriesAnswerFromTheValueAlone) {
  const Ownership own = [] {
    std::mt19937_64 rng(29);
    const ParcelScene s = flat_roof_at_the_line(rng, 101.5, 2, 10, 10.05, 16);
    return decided(s);
  }();
  const Ownership copy = own;
  const Polygon2 outline{{{3, 2}, {17, 2}, {17, 10}, {3, 10}}, {}};
  for (const Ownership* o : {&own, &copy}) {
    const Polygon2 split = split_where_neighbour_roof_ends(outline, *o);
    ASSERT_EQ(split.outer.size(), 5u);
    EXPECT_NEAR(split.outer[3].x(), 10, 0.2);
    EXPECT_EQ(find_party_edges(split, *o), (std::vector<bool>{false, false, false, true, false}));
  }
}

// The shed roof (x 3..17, y 2..9.7) stops 0.3 m short of the boundary under
// the neighbour's eave 5 m higher (x 1..19, y 9.7..18): its outline runs on
// under the eave to the boundary. With its north wall seen under the edge, it
// stands free and keeps its outline.
TEST(OwnershipValue, OutlineGrowsUnderANeighboursHigherEave) {
  auto grown = [](bool north_wall_seen) {
    const ParcelScene s = roof_under_a_neighbours_eave(north_wall_seen);
    const Segmentation seg = segment_roofs(s.roof_points, params());
    const Ownership own = decide_ownership(s, seg, params());
    std::set<int> roofs;  // the shed's: the roofs of the components kept on the parcel
    for (size_t c = 0; c < seg.components.size(); ++c)
      if (!own.component_points[c].empty()) roofs.insert(seg.components[c].roof);
    const Polygon2 outline{{{3, 2}, {17, 2}, {17, 9.7}, {3, 9.7}}, {}};
    return grow_under_neighbour_eaves(outline, own, roofs, poly::buffer(s.parcel, 0.3));
  };
  EXPECT_NEAR(area(grown(false)), 14 * 8, 0.1);
  EXPECT_NEAR(area(grown(true)), 14 * 7.7, 1e-9);
}

// The point index finds every point in a box, in the points' order.
TEST(OwnershipValue, PointGridFindsEveryPointInABoxInOrder) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-7, 23);
  std::vector<Vec3> points;
  for (int i = 0; i < 2000; ++i) points.emplace_back(u(rng), u(rng), 0);
  const PointGrid grid = index_points(points, 2.0);
  const Vec2 lo(1.3, -2.1), hi(6.7, 4.05);
  const std::vector<int> found = points_in_box(grid, lo, hi);
  EXPECT_TRUE(std::is_sorted(found.begin(), found.end()));
  size_t inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec2 q = points[i].head<2>();
    if (q.x() < lo.x() || q.x() > hi.x() || q.y() < lo.y() || q.y() > hi.y()) continue;
    ++inside;
    EXPECT_TRUE(std::binary_search(found.begin(), found.end(), int(i))) << i;
  }
  EXPECT_GT(inside, 0u);
  EXPECT_LT(found.size(), points.size() / 4);  // the cells around the box, not the whole scene
  EXPECT_TRUE(points_in_box(index_points({}, 2.0), lo, hi).empty());
}
