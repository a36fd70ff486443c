// ParcelBoxes (cadastre/batch/parcel_boxes.h): the grid's answer is the pass
// over every parcel's box it replaces, for small and large parcels, far and
// near queries, and parcels without a shape.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace c3d
