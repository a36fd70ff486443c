// The scan's roof density by place (core/reconstruct/scene/roof_density.h,
// DensityBlocks in cadastre/batch/tiles.h): each 1 km block holds the median
// count of roof points per 0.5 m cell over its own cells, whatever else the
// tiles hold; a scene finds its cells' blocks through its local frame.
#include <gtest/gtest.h>

#include <memory>

#include "cadastre/batch/tiles.h"
#include "core/reconstruct/scene/roof_density.h"

namespace c3d {
namespace {

// A held tile of 10 x 10 cells of 0.5 m from (x0, y0), `roof` roof points
// and 3 ground points in each cell.
Tile tile_of_cells(double x0, double y0, int roof) {
  auto cloud = std::make_shared<PointCloud>();
  Tile t;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < roof + 3; ++k) {
        const double x = x0 + 0.5 * i + 0.01 + 0.48 * k / (roof + 3), y = y0 + 0.5 * j + 0.25;
        cloud->points.emplace_back(x, y, 10.0);
        cloud->classes.push_back(k < roof ? 6 : 2);
        t.extent.add(x, y);
      }
  t.path = "held";
  t.held = cloud;
  return t;
}

TEST(DensityBlocks, EachBlockHoldsTheMedianOfItsOwnRoofCells) {
  // Block (0, 0) at 8 points a cell, block (1, 0) at 11, and a few cells at
  // 2 in block (0, 0)'s corner that do not move its median.
  const std::vector<Tile> tiles{tile_of_cells(100, 100, 8), tile_of_cells(1100, 100, 11),
                                tile_of_cells(990, 990, 2)};
  const ClassMapping classes;
  DensityBlocks density(tiles, classes);
  Box both;
  both.add(100, 100), both.add(1200, 110);
  const std::map<CellIndex, int> got = density.around(both);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got.at({0, 0}), 8);
  EXPECT_EQ(got.at({1, 0}), 11);
  Box empty_block;  // block (5, 5): no points, so no figure
  empty_block.add(5100, 5100), empty_block.add(5200, 5200);
  EXPECT_TRUE(density.around(empty_block).empty());
}

TEST(DensityBlocks, ATileStraddlingTwoBlocksCountsEachCellInItsOwn) {
  // Cells from x 997.5 to 1002.5 at 4 points, the half past x 1000 in block
  // (1, 0); beside them block (1, 0) holds 9 cells at 9 points.
  const std::vector<Tile> tiles{tile_of_cells(997.5, 0, 4), tile_of_cells(1010, 0, 9)};
  DensityBlocks density(tiles, ClassMapping{});
  Box b;
  b.add(996, 1), b.add(1004, 4);
  const auto got = density.around(b);
  EXPECT_EQ(got.at({0, 0}), 4);  // its 50 cells of the tile
  EXPECT_EQ(got.at({1, 0}), 9);  // 50 cells at 4 and 100 at 9
}

TEST(RoofDensity, LocalCellsFindTheirWorldBlock) {
  RoofDensity d;
  d.offset = {2000, -1};  // local (0, 0) is world cell (2000, -1): x 1000 m, y -0.5 m
  d.typical = {{{1, -1}, 12}, {{0, 0}, 30}};
  EXPECT_EQ(d.at({0, 0}), 12);      // world (2000, -1): block (1, -1)
  EXPECT_EQ(d.at({-1, 1}), 30);     // world (1999, 0): block (0, 0)
  EXPECT_EQ(d.at({-1, 0}), 0);      // world (1999, -1): block (0, -1), not known
  EXPECT_EQ(density_block({-1, -2000}), CellIndex(-1, -1));
  EXPECT_EQ(density_block({-2001, 1999}), CellIndex(-2, 0));
}

}  // namespace
}  // namespace c3d
