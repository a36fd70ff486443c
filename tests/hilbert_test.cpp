#include <gtest/gtest.h>

#include <cstdlib>
#include <set>

#include "core/geometry/hilbert.h"

using namespace c3d;

TEST(Hilbert, FirstOrderVisitsTheFourCellsInCurveOrder) {
  EXPECT_EQ(hilbert_index(0, 0, 1), 0u);
  EXPECT_EQ(hilbert_index(0, 1, 1), 1u);
  EXPECT_EQ(hilbert_index(1, 1, 1), 2u);
  EXPECT_EQ(hilbert_index(1, 0, 1), 3u);
}

// Every cell once, and each step along the curve moves to an edge neighbour.
TEST(Hilbert, CurveIsAPathThroughEveryCell) {
  const int order = 5, side = 1 << order;
  std::vector<std::pair<int, int>> at(side * side, {-1, -1});
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y) {
      const auto d = hilbert_index(x, y, order);
      ASSERT_LT(d, at.size());
      ASSERT_EQ(at[d].first, -1) << "cell visited twice";
      at[d] = {x, y};
    }
  for (size_t d = 1; d < at.size(); ++d)
    EXPECT_EQ(std::abs(at[d].first - at[d - 1].first) + std::abs(at[d].second - at[d - 1].second), 1) << d;
}

TEST(Hilbert, OrderOfAGridWalksNeighbours) {
  std::vector<Vec2> pts;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) pts.emplace_back(1000.0 + 10 * x, 5000.0 + 10 * y);
  const auto order = hilbert_order(pts);
  ASSERT_EQ(order.size(), pts.size());
  EXPECT_EQ(std::set<size_t>(order.begin(), order.end()).size(), pts.size());
  for (size_t k = 1; k < order.size(); ++k)
    EXPECT_NEAR((pts[order[k]] - pts[order[k - 1]]).norm(), 10.0, 1e-9) << k;
}

TEST(Hilbert, SamePlacesKeepInputOrder) {
  const std::vector<Vec2> pts{{5, 5}, {0, 0}, {5, 5}, {0, 0}};
  EXPECT_EQ(hilbert_order(pts), (std::vector<size_t>{1, 3, 0, 2}));
}

TEST(Hilbert, PartsCoverEveryItemOnceWithSizesWithinOne) {
  for (size_t n : {0u, 1u, 7u, 10000u})
    for (int count : {1, 2, 3, 7}) {
      size_t next = 0, lo = n, hi = 0;
      for (int k = 1; k <= count; ++k) {
        const IndexRange r = part_range(n, k, count);
        EXPECT_EQ(r.begin, next);
        next = r.end;
        lo = std::min(lo, r.end - r.begin), hi = std::max(hi, r.end - r.begin);
      }
      EXPECT_EQ(next, n);
      EXPECT_LE(hi - lo, 1u);
    }
}
