// Stage "segment" on clouds as other writers and scanners deliver them:
// stacked copies of each point, coordinates rounded to float32 at national-grid
// offsets, points on scan rows, and small facets at 5 and 200 points/m2.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/config/config.h"
#include "core/geometry/unique_points.h"
#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/segment/segmentation.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::test;

namespace {

// A hipless gable of 12 x 10 m, slopes of 30 degrees falling north and south,
// ridge along x at y = 5 and z = 8, at `density` points/m2 and 2 cm noise.
const Plane kNorth = plane_through({0, 5, 8}, {0, 0.5, 0.866});
const Plane kSouth = plane_through({0, 5, 8}, {0, -0.5, 0.866});

std::vector<Vec3> gable(double density, std::mt19937_64& rng) {
  auto a = sample_plane(kSouth, 0, 12, 0, 5, density, 0.02, rng);
  auto b = sample_plane(kNorth, 0, 12, 5, 10, density, 0.02, rng);
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Each component: points, normal, the y it spans (for failure messages).
std::string describe(const std::vector<Vec3>& pts, const Segmentation& seg) {
  std::string out;
  for (const auto& c : seg.components) {
    double y0 = 1e9, y1 = -1e9;
    for (int i : c.points) y0 = std::min(y0, pts[size_t(i)].y()), y1 = std::max(y1, pts[size_t(i)].y());
    char line[160];
    std::snprintf(line, sizeof line, "\n  %zu points, normal %.3f %.3f %.3f, y %.2f..%.2f", c.points.size(),
                  c.fit.plane.n.x(), c.fit.plane.n.y(), c.fit.plane.n.z(), y0, y1);
    out += line;
  }
  return out;
}

// The gable's two slopes, each one component holding at least `share` of its
// points (by which side of the ridge they lie); `others` more components
// allowed, none holding more than a tenth of the points.
void expect_two_slopes(const std::vector<Vec3>& pts, const Segmentation& seg, double share, size_t others = 0) {
  ASSERT_GE(seg.components.size(), 2u) << describe(pts, seg);
  ASSERT_LE(seg.components.size(), 2u + others) << describe(pts, seg);
  std::vector<const RoofComponent*> by_size;
  for (const auto& c : seg.components) by_size.push_back(&c);
  std::sort(by_size.begin(), by_size.end(), [](auto* a, auto* b) { return a->points.size() > b->points.size(); });
  for (size_t k = 2; k < by_size.size(); ++k) EXPECT_LT(by_size[k]->points.size(), pts.size() / 10);
  size_t south_points = 0;
  for (const auto& q : pts) south_points += q.y() < 5;
  for (size_t k = 0; k < 2; ++k) {
    const auto& c = *by_size[k];
    const bool south = c.fit.plane.n.y() < 0;
    EXPECT_NEAR(c.fit.plane.slope_deg(), 30.0, 1.5);
    size_t own = 0;
    for (int i : c.points) own += (pts[size_t(i)].y() < 5) == south;
    EXPECT_GE(double(own), share * double(south ? south_points : pts.size() - south_points)) << describe(pts, seg);
    EXPECT_GE(double(own), 0.99 * double(c.points.size())) << "points of the other slope taken";
  }
  EXPECT_NE(by_size[0]->fit.plane.n.y() < 0, by_size[1]->fit.plane.n.y() < 0) << "one slope twice";
}

}  // namespace

TEST(UniquePoints, CopiesWithinTheToleranceFoldIntoTheFirst) {
  const std::vector<Vec3> pts = {{0, 0, 0}, {1, 0, 0}, {0.001, 0, 0.001}, {1, 0, 0}, {0.004, 0.004, 0}, {0.02, 0, 0}};
  const UniquePoints u = unique_points(pts, 0.005);
  EXPECT_EQ(u.unique, (std::vector<int>{0, 1, 4, 5}));  // 4 lies 5.7 mm from 0: a place of its own
  EXPECT_EQ(u.of, (std::vector<int>{0, 1, 0, 1, 2, 3}));
}

TEST(SegmentQuantized, StackedCopiesGiveTheSlopesOfTheOriginal) {
  // Every point 2-4 times, exactly or within 1 mm: the 16 nearest of a point
  // were 4 or 5 places, and the nearest neighbour 0 m away (the spacing).
  std::mt19937_64 rng(34);
  const auto pts = gable(10, rng);
  const Segmentation once = segment_roofs(pts, ReconstructionParams{});
  for (double jitter : {0.0, 0.001}) {
    std::vector<Vec3> stacked;
    std::uniform_int_distribution<int> copies(2, 4), step(-1, 1);
    for (const auto& q : pts)
      for (int k = copies(rng); k > 0; --k) stacked.push_back(q + jitter * Vec3(step(rng), step(rng), step(rng)));
    const Segmentation seg = segment_roofs(stacked, ReconstructionParams{});
    expect_two_slopes(stacked, seg, 0.9);
    // The places are the original's (moved by the jitter of the copy kept).
    EXPECT_NEAR(seg.spacing, once.spacing, 0.01 * once.spacing) << "jitter " << jitter;
    EXPECT_NEAR(seg.density, once.density, 0.01 * once.density) << "jitter " << jitter;
  }
}

TEST(SegmentQuantized, Float32CoordinatesAtANationalGridOffset) {
  // Written as float32 at RD (85000, 445000): x in 7.8 mm steps, y in 31 mm.
  std::mt19937_64 rng(35);
  const Vec3 origin(85000, 445000, 0);
  std::vector<Vec3> pts;
  for (const auto& q : gable(10, rng)) {
    const Vec3 w = q + origin;
    pts.push_back(Vec3(double(float(w.x())), double(float(w.y())), double(float(w.z()))) - origin);
  }
  expect_two_slopes(pts, segment_roofs(pts, ReconstructionParams{}), 0.9);
}

TEST(SegmentQuantized, PointsOnScanRowsHalfAMetreApart) {
  // Rows 0.5 m apart across the slopes, shuffled along the row: 0.25 m apart
  // within a row (8 points/m2: the nearest neighbour, in the row, says nothing
  // of the half-metre gaps between rows) and 0.05 m (40 points/m2: a point's
  // 16 nearest all lie on its row, a line that fixes no normal, and rows 0.58 m
  // apart on the slope lie further apart than 4 spacings). Two rows are
  // always coplanar: the pair either side of the ridge may come out as a
  // narrow third plane (left to do: a plane spanning two rows only is none).
  for (double step : {0.25, 0.05}) {
    std::mt19937_64 rng(36);
    std::uniform_real_distribution<double> along(0, step);
    std::normal_distribution<double> noise(0, 0.02);
    std::vector<Vec3> pts;
    for (double y = 0.1; y < 10; y += 0.5)
      for (double x = along(rng); x < 12; x += step) {
        const Plane& pl = y < 5 ? kSouth : kNorth;
        pts.emplace_back(x, y, pl.z_at(x, y) + noise(rng));
      }
    const Segmentation seg = segment_roofs(pts, ReconstructionParams{});
    SCOPED_TRACE("rows " + std::to_string(step) + " m within");
    expect_two_slopes(pts, seg, 0.85, 1);
    EXPECT_EQ(seg.roof_count, 1) << "the rows fell apart into roofs";
  }
}

TEST(SegmentQuantized, ThreeSquareMetreShedGetsItsPlaneAtFiveAndTwoHundredPointsPerM2) {
  // A flat roof of 8 x 8 m and, 2 m beside it, a shed of 2 x 1.5 m falling
  // 15 degrees: at 5 points/m2 its 15 points are fewer than the 30 a plane
  // needed at any density.
  for (double density : {5.0, 200.0})
    for (unsigned seed : {1u, 2u, 3u}) {
      std::mt19937_64 rng(seed);
      auto pts = sample_plane(plane_through({0, 0, 6}, {0, 0, 1}), 0, 8, 0, 8, density, 0.02, rng);
      const size_t house = pts.size();
      const Plane shed = plane_through({10, 0, 2.5}, {0, -0.268, 1});
      auto s = sample_plane(shed, 10, 12, 0, 1.5, density, 0.02, rng);
      pts.insert(pts.end(), s.begin(), s.end());
      const Segmentation seg = segment_roofs(pts, ReconstructionParams{});
      int shed_planes = 0;
      for (const auto& c : seg.components) {
        if (size_t(c.points.front()) < house) continue;
        ++shed_planes;
        EXPECT_NEAR(c.fit.plane.slope_deg(), 15.0, 4.0) << density << " pts/m2, seed " << seed;
        // At 5 points/m2 the 16 nearest of an edge point reach the house's
        // points: a few of its 15 stay loose (roof points all the same).
        EXPECT_GE(double(c.points.size()), 0.7 * double(s.size())) << density << " pts/m2, seed " << seed;
      }
      EXPECT_EQ(shed_planes, 1) << density << " pts/m2, seed " << seed;
    }
}
