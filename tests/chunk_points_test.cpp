// A chunk is bounded by the points its region reads, not only by its parcel
// count: in a town whose east half is ten times as dense (tiles' header
// counts over their extents), the east gets more, smaller chunks; every
// parcel is in exactly one chunk, in Hilbert order.

#include <gtest/gtest.h>

#include <algorithm>

#include "cadastre/batch/chunks.h"

using namespace c3d;

namespace {

// 20 x 10 parcels of 20 m, the grid starting at (500000, 9000000).
ParcelLayer grid_town() {
  ParcelLayer layer;
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) {
      Parcel p;
      p.index = int(layer.parcels.size());
      const double x0 = 500000 + x * 20.0, y0 = 9000000 + y * 20.0;
      p.shape = {Polygon2{{Vec2(x0, y0), Vec2(x0 + 20, y0), Vec2(x0 + 20, y0 + 20), Vec2(x0, y0 + 20)}, {}}};
      layer.parcels.push_back(p);
    }
  return layer;
}

Tile tile(double x0, double x1, double points_per_m2) {
  Tile t;
  t.extent = {x0, 9000000 - 50, x1, 9000200 + 50};
  t.points = uint64_t(points_per_m2 * (x1 - x0) * 300);
  return t;
}

}  // namespace

TEST(ChunkPoints, DenseAreaGetsSmallerChunks) {
  const ParcelLayer layer = grid_town();
  // West half (x < 500200): 10 points/m2; east half: 100.
  const std::vector<Tile> tiles{tile(500000 - 50, 500200, 10), tile(500200, 500400 + 50, 100)};
  std::vector<size_t> all(layer.parcels.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  // A parcel's grown box (30 x 30 m) reads ~9,000 points in the west, ~90,000 in the east.
  const auto chunks = spatial_chunks(ParcelBoxes(layer), tiles, all, ChunkLimits{1000, 400000, 5});
  const auto by_parcels = spatial_chunks(ParcelBoxes(layer), tiles, all, ChunkLimits{1000, 0, 5});
  ASSERT_EQ(by_parcels.size(), 1u);  // no point bound: one chunk of all
  std::vector<size_t> flat;
  size_t west_most = 0, east_most = 0, west_chunks = 0, east_chunks = 0;
  for (const auto& c : chunks) {
    flat.insert(flat.end(), c.begin(), c.end());
    size_t east = 0;
    for (size_t i : c) east += (i % 20) >= 10;
    const bool is_east = 2 * east > c.size();
    (is_east ? east_most : west_most) = std::max(is_east ? east_most : west_most, c.size());
    ++(is_east ? east_chunks : west_chunks);
    EXPECT_GE(c.size(), 1u);
  }
  EXPECT_EQ(flat, by_parcels[0]);  // the same Hilbert order, cut into runs
  EXPECT_GT(east_chunks, 2 * west_chunks);
  EXPECT_LT(4 * east_most, west_most);
  // The estimate counts each 5 m cell once: a run's region, not the sum of its parts.
  RegionPointsEstimate e(tiles);
  const Box west{500000, 9000000, 500020, 9000020};
  const double one = e.add(west);
  EXPECT_NEAR(one, 10 * 25 * 25, 1.0);  // cells from 500000 to 500020 inclusive: 5 x 5 of 25 m2
  EXPECT_EQ(e.add(west), one);           // the same part again adds nothing
  // The parcel-count bound still holds.
  for (const auto& c : spatial_chunks(ParcelBoxes(layer), tiles, all, ChunkLimits{7, 1e12, 5})) EXPECT_LE(c.size(), 7u);
}
