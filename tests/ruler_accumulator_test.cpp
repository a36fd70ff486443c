// The rulers fed a chunk at a time equal ruler_figures over all distances,
// within the accumulator's stated resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/evaluate/ruler.h"

namespace c3d {
namespace {

void expect_equal_within_resolution(const RulerFigures& a, const RulerFigures& b) {
  EXPECT_EQ(a.n, b.n);
  EXPECT_NEAR(a.rmse, b.rmse, 1e-9);
  EXPECT_NEAR(a.rmse_within_1m, b.rmse_within_1m, 1e-9);
  EXPECT_DOUBLE_EQ(a.max, b.max);
  EXPECT_DOUBLE_EQ(a.share_over_0_3m, b.share_over_0_3m);
  EXPECT_DOUBLE_EQ(a.share_over_1m, b.share_over_1m);
  EXPECT_NEAR(a.median, b.median, kRulerBinM / 2);
  EXPECT_NEAR(a.p95, b.p95, kRulerBinM / 2);
  EXPECT_NEAR(a.nmad, b.nmad, 1.4826 * kRulerBinM * 1.001);  // 0.1 mm: median and value each off by half a bin
}

TEST(RulerAccumulator, ChunksGiveTheFiguresOfAllDistances) {
  std::mt19937 rng(7);
  std::exponential_distribution<double> fit(8.0);  // most within a few cm, a tail of metres
  std::vector<double> all;
  RulerAccumulator acc;
  for (int chunk = 0; chunk < 13; ++chunk) {
    std::vector<double> part;
    for (int k = 0; k < 1000 + 37 * chunk; ++k) part.push_back(k % 2 ? fit(rng) : -fit(rng));
    if (chunk == 5) part.push_back(std::numeric_limits<double>::quiet_NaN());  // no surface: a 99 m miss
    if (chunk == 9) part.push_back(250.0);                                     // beyond the miss value
    all.insert(all.end(), part.begin(), part.end());
    acc.add(part);
  }
  expect_equal_within_resolution(acc.figures(), ruler_figures(all));
}

TEST(RulerAccumulator, KnownDistances) {
  RulerAccumulator acc;
  acc.add({0.1, 0.2});
  acc.add({0.3, 0.4, 2.0});
  const RulerFigures f = acc.figures();
  EXPECT_EQ(f.n, 5);
  EXPECT_NEAR(f.median, 0.3, kRulerBinM / 2);
  EXPECT_NEAR(f.p95, 0.4 + 0.8 * 1.6, kRulerBinM / 2);  // rank 3.8: between 0.4 and 2.0
  EXPECT_NEAR(f.nmad, 1.4826 * 0.1, 1.4826 * kRulerBinM * 1.001);  // 0.1 mm: median and value each off by half a bin
  EXPECT_DOUBLE_EQ(f.max, 2.0);
  EXPECT_DOUBLE_EQ(f.share_over_1m, 0.2);
  EXPECT_DOUBLE_EQ(f.share_over_0_3m, 0.4);
  EXPECT_EQ(RulerAccumulator().figures().n, 0);
}

}  // namespace
}  // namespace c3d
