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

// The folder a point at a time keeps what one_per_place keeps of the whole:
// random points with many exact and near copies, and points on and beside
// the folder's cell edges and middles (multiples of 5 mm, a hair either side).
TEST(PlaceFolder, SameAsUniquePointsPointByPoint) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 3), jitter(-0.006, 0.006);
  std::uniform_int_distribution<int> step(-40, 40), hair(-1, 1);
  for (const Vec3& o : {Vec3(0, 0, 0), Vec3(-1.5, -0.25, -3.0), Vec3(500123.45, 9312345.67, 41.2)}) {
    std::vector<Vec3> pts;
    for (int i = 0; i < 30000; ++i) {
      if (i % 2 == 0) {  // on the 5 mm lattice: cell edges (10 mm) and middles, +-1e-9
        const Vec3 e(step(rng) * 0.005 + hair(rng) * 1e-9, step(rng) * 0.005 + hair(rng) * 1e-9,
                     step(rng) * 0.005 + hair(rng) * 1e-9);
        pts.push_back(o + e);
        continue;
      }
      const Vec3 p = o + Vec3(u(rng), u(rng), u(rng) / 10);
      pts.push_back(p);
      for (int k = 0; k < i % 4; ++k) pts.push_back(p + Vec3(jitter(rng), jitter(rng), jitter(rng) / 2));
      if (i % 7 == 0) pts.push_back(p);
    }
    std::shuffle(pts.begin() + long(pts.size() / 2), pts.end(), rng);  // copies far from their originals too
    PlaceFolder f;
    for (const Vec3& p : pts) f.add(p);
    const auto want = reference(pts);
    ASSERT_EQ(f.size(), want.size()) << o.transpose();
    const auto got = f.take();
    ASSERT_EQ(got, want) << o.transpose();
    EXPECT_LT(got.size(), pts.size() * 3 / 4);  // the copies did fold
    EXPECT_EQ(f.size(), 0u);                    // taken: empty, and usable again
    f.add(pts[0]);
    f.add(pts[0]);
    EXPECT_EQ(f.take(), std::vector<Vec3>{pts[0]});
    EXPECT_EQ(one_per_place(pts), want);
  }
}
