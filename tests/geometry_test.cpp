#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/geometry/geometry.h"
#include "core/geometry/label_grid.h"
#include "core/geometry/welding.h"

using namespace c3d;

TEST(Geometry, SquareAreasAndOrientation) {
  Ring2 sq{{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  EXPECT_DOUBLE_EQ(signed_area(sq), 12.0);
  Ring2 cw(sq.rbegin(), sq.rend());
  EXPECT_DOUBLE_EQ(signed_area(cw), -12.0);
  Polygon2 p{sq, {{{1, 1}, {1, 2}, {2, 2}, {2, 1}}}};
  EXPECT_DOUBLE_EQ(area(p), 11.0);
}

TEST(Geometry, SlopedFaceTrueAndPlanArea) {
  // A 30 degree roof plane over a 4 x 3 rectangle: true area = plan / cos(30).
  double t = std::tan(30.0 * M_PI / 180.0);
  Face f{{{0, 0, 0}, {4, 0, 0}, {4, 3, 3 * t}, {0, 3, 3 * t}}, {}};
  EXPECT_NEAR(plan_area(f), 12.0, 1e-12);
  EXPECT_NEAR(area(f), 12.0 / std::cos(30.0 * M_PI / 180.0), 1e-12);
  EXPECT_GT(unit_normal(f).z(), 0.0);
}

TEST(Geometry, LargeCoordinatesKeepPrecision) {
  // UTM-sized coordinates: the Newell sum is taken relative to a vertex.
  Face f{{{781000.0, 9240000.0, 790}, {781010, 9240000.0, 790}, {781010, 9240010, 790},
          {781000, 9240010, 790}}, {}};
  EXPECT_NEAR(area(f), 100.0, 1e-9);
}

TEST(Geometry, TotalsSumElementsAndCombineSigma) {
  Building b;
  Element r1; r1.type = ElementType::Roof; r1.area = 10; r1.plan_area = 8; r1.sigma_area = 3;
  Element r2 = r1; r2.sigma_area = 4;
  Element w; w.type = ElementType::Wall; w.area = 5; w.sigma_area = 1;
  b.elements = {r1, r2, w};
  auto t = totals(b);
  EXPECT_DOUBLE_EQ(t.roof, 20);
  EXPECT_DOUBLE_EQ(t.roof_plan, 16);
  EXPECT_DOUBLE_EQ(t.sigma_roof, 5);
  EXPECT_EQ(t.roof_planes, 2);
  EXPECT_DOUBLE_EQ(t.wall, 5);
}

TEST(Geometry, PointsAlongALineDoNotDependOnItsVertices) {
  // One straight 3 m line drawn with its two ends, and again with 30
  // vertices crowded into its first 0.3 m (as a staircase crowds them):
  // sampled every 0.25 m, both give the same 13 points, evenly spaced.
  const std::vector<Vec2> plain{{0, 0}, {3, 0}};
  std::vector<Vec2> crowded;
  for (int k = 0; k < 30; ++k) crowded.emplace_back(0.01 * k, 0);
  crowded.emplace_back(3, 0);
  const auto a = points_along(plain, 0.25), b = points_along(crowded, 0.25);
  ASSERT_EQ(a.size(), 13u);
  ASSERT_EQ(b.size(), a.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_NEAR(a[k].x(), 0.25 * double(k), 1e-12);
    EXPECT_NEAR((a[k] - b[k]).norm(), 0.0, 1e-12);
  }
  // Around a corner the spacing is kept along the line; the end is always in.
  const auto c = points_along({{0, 0}, {0.3, 0}, {0.3, 0.5}}, 0.25);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NEAR((c[2] - Vec2(0.3, 0.2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c.back() - Vec2(0.3, 0.5)).norm(), 0.0, 1e-12);
}

TEST(Geometry, TJunctionsGoIntoTheEdgeTheyLieOn) {
  // A 3D square; of the candidate vertices, the two on its bottom edge (one
  // 5 mm off it, within the 1 cm tolerance) go in, in order along the edge;
  // one 2 cm off, one at a corner and one beyond the edge's end stay out.
  const std::vector<Vec3> ring{{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}};
  const std::vector<Vec3> verts{{3, 0.005, 0}, {1, 0, 0}, {2, 0.02, 0}, {4, 0, 0}, {5, 0, 0}};
  const std::vector<Vec3> out = EdgeNoder<Vec3>(verts, 0.01).insert_on_edges(ring);
  ASSERT_EQ(out.size(), 6u);
  EXPECT_TRUE(out[1].isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(out[2].isApprox(Vec3(3, 0.005, 0)));
  EXPECT_TRUE(out[3].isApprox(Vec3(4, 0, 0)));
}

// The cell-indexed welder and noder answer as the plain scans over every
// vertex do: the first kept vertex within tol, every vertex on an edge.
TEST(Geometry, WeldingAndNodingOnCellsAnswerAsThePlainScans) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 3);
  std::uniform_int_distribution<int> pick(0, 199);
  const double tol = 0.01;
  std::vector<Vec3> pts;  // clumps a few mm wide (one place), lines of vertices on edges
  for (int i = 0; i < 200; ++i) pts.push_back(Vec3(u(rng), u(rng), u(rng)));
  for (int i = 0; i < 400; ++i) pts.push_back(pts[size_t(pick(rng))] + Vec3(u(rng), u(rng), u(rng)) * 0.004);
  for (int i = 0; i < 100; ++i) {
    const Vec3 a = pts[size_t(pick(rng))], b = pts[size_t(pick(rng))];
    pts.push_back(a + (b - a) * (u(rng) / 3) + Vec3(0, 0, 0.003));
  }
  std::vector<Vec3> plain = pts, seen;
  for (Vec3& v : plain) {
    const auto first = std::find_if(seen.begin(), seen.end(), [&](const Vec3& s) { return (s - v).norm() < tol; });
    if (first != seen.end()) v = *first;
    else seen.push_back(v);
  }
  Welder<Vec3> welder(tol);
  std::vector<Vec3> welded = pts;
  for (Vec3& v : welded) welder.weld(v);
  EXPECT_EQ(welded, plain);
  EXPECT_EQ(welder.seen(), seen);
  ASSERT_LT(seen.size(), 500u);  // the clumps did weld
  const EdgeNoder<Vec3> noder(pts, tol);
  size_t inserted = 0;
  for (int r = 0; r < 50; ++r) {
    const std::vector<Vec3> ring{pts[size_t(pick(rng))], pts[size_t(pick(rng))], pts[size_t(pick(rng))]};
    std::vector<Vec3> want;  // the plain scan
    for (size_t i = 0; i < ring.size(); ++i) {
      const Vec3 a = ring[i], b = ring[(i + 1) % ring.size()], ab = b - a;
      want.push_back(a);
      if (ab.squaredNorm() < tol * tol) continue;
      std::vector<std::pair<double, Vec3>> inner;
      for (const Vec3& v : pts) {
        const double t = (v - a).dot(ab) / ab.squaredNorm();
        if (t > 1e-9 && t < 1 - 1e-9 && (a + t * ab - v).norm() < tol && (v - a).norm() > tol && (v - b).norm() > tol)
          inner.emplace_back(t, v);
      }
      std::sort(inner.begin(), inner.end(), [](auto& x, auto& y) { return x.first < y.first; });
      for (auto& [t, v] : inner)
        if ((v - want.back()).norm() > tol) want.push_back(v);
    }
    const std::vector<Vec3> got = noder.insert_on_edges(ring);
    EXPECT_EQ(got, want) << "ring " << r;
    inserted += got.size() - ring.size();
  }
  EXPECT_GT(inserted, 20u);  // the lines of vertices went into their edges
}

TEST(Dtm, BilinearAndOutside) {
  Dtm d;
  d.x0 = 0.5; d.y0 = 9.5; d.dx = 1; d.dy = -1; d.nx = 2; d.ny = 2;
  d.z = {0, 1, 2, 3};
  EXPECT_NEAR(d.height_at(1.0, 9.0), 1.5, 1e-12);
  EXPECT_TRUE(std::isnan(d.height_at(5, 5)));
}

// Rows go up in y from the origin. Label 0 is an L round a hole of label 1
// (one polygon with a hole and a separate square), label 2 two cells that
// touch only at a corner (two polygons), -1 is nothing.
TEST(LabelGrid, PolygonsFollowTheCellLinesWithHolesAndParts) {
  const int nx = 5, ny = 4;
  // clang-format off
  const std::vector<int> rows_top_down = {
       2, -1,  0,  0,  0,
      -1,  2,  0,  1,  0,
      -1, -1,  0,  0,  0,
      -1, -1,  0,  0, -1};
  // clang-format on
  LabelGrid g{nx, ny, Vec2(100.0, 200.0), 0.5, std::vector<int>(size_t(nx * ny))};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) g.labels[size_t(j * nx + i)] = rows_top_down[size_t((ny - 1 - j) * nx + i)];
  const auto regions = polygonize(g, 4);
  ASSERT_EQ(regions.size(), 4u);
  const double cell = 0.25;
  ASSERT_EQ(regions[0].size(), 1u);
  ASSERT_EQ(regions[0][0].holes.size(), 1u);
  EXPECT_NEAR(area(regions[0][0]), 10 * cell, 1e-12);
  // Only the corners: the L's outer ring has 6, the hole 4.
  EXPECT_EQ(regions[0][0].outer.size(), 6u);
  EXPECT_EQ(regions[0][0].holes[0].size(), 4u);
  ASSERT_EQ(regions[1].size(), 1u);
  EXPECT_NEAR(area(regions[1][0]), cell, 1e-12);
  Vec2 lo = regions[1][0].outer[0], hi = lo;
  for (const auto& v : regions[1][0].outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  EXPECT_NEAR(lo.x(), 101.5, 1e-12);  // column 3, row 2 from the bottom
  EXPECT_NEAR(lo.y(), 201.0, 1e-12);
  EXPECT_NEAR(hi.x(), 102.0, 1e-12);
  EXPECT_NEAR(hi.y(), 201.5, 1e-12);
  EXPECT_EQ(regions[2].size(), 2u);
  EXPECT_TRUE(regions[3].empty());
}

namespace {
// A grid from rows written top-down, as the grid is drawn.
LabelGrid grid_of(int nx, int ny, const std::vector<int>& rows_top_down) {
  LabelGrid g{nx, ny, Vec2(0, 0), 1.0, std::vector<int>(size_t(nx * ny))};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) g.labels[size_t(j * nx + i)] = rows_top_down[size_t((ny - 1 - j) * nx + i)];
  return g;
}
int at(const LabelGrid& g, int column, int row_from_top) { return g.labels[size_t((g.ny - 1 - row_from_top) * g.nx + column)]; }
}  // namespace

// Runs under 3 cells: the 1 shares 5 edges with 0 and 1 with 2, and joins 0;
// the 3 shares 3 with 2 and 1 with 0, and joins 2. The 4 shares 3 edges with
// either big run and joins the lower label.
TEST(LabelGrid, SieveGivesSmallRunsToTheBigNeighbourSharingMostEdges) {
  // clang-format off
  LabelGrid g = grid_of(6, 4, {
      0, 0, 0, 2, 2, 2,
      0, 1, 1, 2, 2, 2,
      0, 0, 0, 3, 2, 2,
      0, 0, 0, 2, 2, 2});
  LabelGrid tie = grid_of(4, 3, {
      0, 0, 2, 2,
      0, 4, 4, 2,
      0, 0, 2, 2});
  // clang-format on
  sieve(g, std::vector<char>(g.labels.size(), 1), 3);
  EXPECT_EQ(at(g, 1, 1), 0);
  EXPECT_EQ(at(g, 2, 1), 0);
  EXPECT_EQ(at(g, 3, 2), 2);
  sieve(tie, std::vector<char>(tie.labels.size(), 1), 3);
  EXPECT_EQ(at(tie, 1, 1), 0);
  EXPECT_EQ(at(tie, 2, 1), 0);
}

// A small run never takes another: the 5 touches only the four one-cell 6s;
// they join 0 first, and then the 5 does (merged with a 6 it would have made
// a run big enough to stay).
TEST(LabelGrid, SieveSmallRunsAmongSmallRunsWaitForABigOne) {
  // clang-format off
  LabelGrid g = grid_of(5, 5, {
      0, 0, 0, 0, 0,
      0, 0, 6, 0, 0,
      0, 6, 5, 6, 0,
      0, 0, 6, 0, 0,
      0, 0, 0, 0, 0});
  // clang-format on
  sieve(g, std::vector<char>(g.labels.size(), 1), 2);
  for (int v : g.labels) EXPECT_EQ(v, 0);
}

// Only counted cells make a run big or small: the 1 holds four cells but one
// counted, so it goes; the 3 has none counted and stays (it lies outside).
TEST(LabelGrid, SieveCountsOnlyTheCellsItIsTold) {
  // clang-format off
  LabelGrid g = grid_of(4, 3, {
      1, 1, 0, 3,
      1, 1, 0, 0,
      0, 0, 0, 0});
  const std::vector<int> counted_top_down = {
      0, 0, 1, 0,
      0, 1, 1, 1,
      1, 1, 1, 1};
  // clang-format on
  std::vector<char> counted(g.labels.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) counted[size_t(j * g.nx + i)] = char(counted_top_down[size_t((g.ny - 1 - j) * g.nx + i)]);
  sieve(g, counted, 2);
  EXPECT_EQ(at(g, 0, 0), 0);
  EXPECT_EQ(at(g, 1, 1), 0);
  EXPECT_EQ(at(g, 3, 0), 3);
}
