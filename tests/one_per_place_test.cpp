// one_per_place keeps exactly the points unique_points keeps (first come,
// first kept: each point kept unless an earlier kept one lies within
// kSamePlaceM), in input order, on clouds with copies, near copies and
// points exactly one tolerance apart on a millimetre grid at national-grid
// offsets (where a cell search that misses a neighbour would show).

#include <gtest/gtest.h>

#include <random>

#include "core/geometry/unique_points.h"

using namespace c3d;

namespace {

std::vector<Vec3> reference(const std::vector<Vec3>& pts) {
  std::vector<Vec3> out;
  for (int i : unique_points(pts, kSamePlaceM).unique) out.push_back(pts[size_t(i)]);
  return out;
}

// Points on a millimetre grid near (x0, y0, z0): many pairs 0-10 mm apart.
std::vector<Vec3> grid_cloud(double x0, double y0, double z0, size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> mm(0, 60);
  std::vector<Vec3> pts;
  for (size_t i = 0; i < n; ++i)
    pts.emplace_back(x0 + mm(rng) * 0.001, y0 + mm(rng) * 0.001, z0 + (mm(rng) % 12) * 0.001);
  return pts;
}

}  // namespace

TEST(OnePerPlace, SameAsUniquePointsOnGrids) {
  for (const Vec3& o : {Vec3(0, 0, 0), Vec3(-3.0, -7.0, -2.0), Vec3(500123.456, 9312345.678, 41.2),
                        Vec3(3512345.001, 5801234.999, 2999.995)})
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const auto pts = grid_cloud(o.x(), o.y(), o.z(), 4000, seed);
      const auto got = one_per_place(pts), want = reference(pts);
      ASSERT_EQ(got.size(), want.size()) << o.transpose() << " seed " << seed;
      for (size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], want[i]);
      EXPECT_LT(got.size(), pts.size());  // the grid holds copies
    }
}

TEST(OnePerPlace, CopiesAndSpacedPoints) {
  std::vector<Vec3> pts;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 50), jitter(-0.003, 0.003);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng) / 10);
    pts.push_back(p);
    if (i % 3 == 0) pts.push_back(p);                                         // an exact copy
    if (i % 5 == 0) pts.push_back(p + Vec3(jitter(rng), jitter(rng), 0.0));  // a near copy
  }
  const auto got = one_per_place(pts), want = reference(pts);
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], want[i]);
  const std::vector<Vec3> spaced{{0, 0, 0}, {0.01, 0, 0}, {0.02, 0, 0}};
  EXPECT_EQ(one_per_place(spaced), spaced);  // nothing folds: the same points back
}
