// ParcelBoxes and BoxGrid (cadastre/batch/box_grid.h): the grid's answer is
// the pass over every box it replaces, for small and large boxes, far and
// near queries, parcels without a shape, and boxes too wide for the grid.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "cadastre/batch/parcel_boxes.h"

namespace c3d {
namespace {

Parcel rectangle(double x, double y, double w, double h) {
  Parcel p;
  p.shape = {Polygon2{{Vec2(x, y), Vec2(x + w, y), Vec2(x + w, y + h), Vec2(x, y + h)}, {}}};
  return p;
}

std::vector<size_t> every_touching(const ParcelLayer& layer, const Box& box, double reach) {
  std::vector<size_t> out;
  for (size_t i = 0; i < layer.parcels.size(); ++i)
    if (box_of(layer.parcels[i].shape).grown(reach).touches(box)) out.push_back(i);
  return out;
}

TEST(ParcelBoxes, TheGridFindsWhatAPassOverEveryParcelFinds) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> at(-3000, 3000), size(2, 60);
  ParcelLayer layer;
  for (int i = 0; i < 2000; ++i) layer.parcels.push_back(rectangle(at(rng), at(rng), size(rng), size(rng)));
  layer.parcels.push_back(rectangle(-500, -500, 1200, 900));  // a farm across many cells
  layer.parcels.push_back(Parcel{});                          // no shape: in no answer
  const ParcelBoxes boxes(layer);
  ASSERT_EQ(boxes.size(), layer.parcels.size());
  size_t found = 0;
  for (int q = 0; q < 300; ++q) {
    Box b;
    const double x = at(rng), y = at(rng);
    b.add(x, y), b.add(x + size(rng) * 5, y + size(rng) * 5);
    for (double reach : {0.0, 3.1, 50.0}) {
      const auto want = every_touching(layer, b, reach);
      EXPECT_EQ(boxes.touching(b, reach), want);
      found += want.size();
    }
  }
  EXPECT_GT(found, 500u);  // the queries met parcels, not only empty land
  EXPECT_TRUE(boxes.touching(Box{}, 10).empty());
}

TEST(ParcelBoxes, BoxesThatOnlyShareAnEdgeTouch) {
  ParcelLayer layer;
  layer.parcels = {rectangle(0, 0, 64, 64), rectangle(64, 0, 10, 10)};
  const ParcelBoxes boxes(layer);
  Box edge;
  edge.add(64, 20), edge.add(70, 30);  // meets parcel 0 on x = 64 only
  EXPECT_EQ(boxes.touching(edge, 0), std::vector<size_t>({0}));
  EXPECT_EQ(boxes.touching(edge, 10), std::vector<size_t>({0, 1}));
}


std::vector<size_t> every_touching(const std::vector<Box>& boxes, const Box& box, double reach) {
  std::vector<size_t> out;
  for (size_t i = 0; i < boxes.size(); ++i)
    if (boxes[i].grown(reach).touches(box)) out.push_back(i);
  return out;
}

// A tile header with an absurd extent, or a NaN, must neither fill the grid
// nor be lost; a query wider than the grid still finds every box once.
TEST(BoxGrid, WideAndBrokenBoxesAndWideQueries) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> at(-2000, 2000), size(50, 600);
  std::vector<Box> boxes;
  for (int i = 0; i < 300; ++i) {
    const double x = at(rng), y = at(rng);
    boxes.push_back(Box{x, y, x + size(rng), y + size(rng)});
  }
  boxes.push_back(Box{-1e12, -1e12, 1e12, 1e12});  // a header's absurd extent: touches everything
  const double nan = std::numeric_limits<double>::quiet_NaN();
  boxes.push_back(Box{nan, 0, 10, 10});  // touches nothing
  boxes.push_back(Box{});                // empty
  const BoxGrid grid(boxes, 128);
  for (int q = 0; q < 200; ++q) {
    const double x = at(rng), y = at(rng), w = q % 10 == 0 ? 1e5 : size(rng);
    const Box b{x, y, x + w, y + w};
    for (double reach : {0.0, 40.0}) EXPECT_EQ(grid.touching(b, reach), every_touching(boxes, b, reach));
  }
  const auto all = grid.touching(Box{-1e9, -1e9, 1e9, 1e9}, 0);
  EXPECT_EQ(all.size(), 301u);  // the 300, the wide one; not the NaN or the empty box
  EXPECT_TRUE(grid.touching(Box{nan, nan, nan, nan}, 5).empty());
}

}  // namespace
}  // namespace c3d
