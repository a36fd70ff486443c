// The checks before a batch, called as a library: points per parcel (`clip`),
// what a file holds (`info`), and a sample town's truth and counts (`sample`).
#include <gtest/gtest.h>

#include "cadastre/inspect/clip_counts.h"
#include "cadastre/inspect/file_info.h"
#include "core/synthetic/sample_summary.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

// Two 10 m squares side by side: P0 x 0..10, P1 x 10..20.
ParcelLayer two_squares() {
  ParcelLayer layer;
  for (int k = 0; k < 2; ++k) {
    Parcel p;
    p.index = k;
    p.id = "P" + std::to_string(k);
    const double x0 = 10.0 * k;
    p.shape = {{{{x0, 0}, {x0 + 10, 0}, {x0 + 10, 10}, {x0, 10}}, {}}};
    layer.parcels.push_back(p);
  }
  return layer;
}

}  // namespace

TEST(Inspect, PointsPerParcelInsideAndInTheBuffer) {
  PointCloud cloud;
  cloud.points = {{5, 5, 0},     // inside P0, roof class
                  {-1, 5, 0},    // in P0's 1.6 m buffer only, wall class
                  {10.5, 5, 0},  // inside P1, in P0's buffer
                  {40, 5, 0}};   // in no parcel
  cloud.classes = {6, 64, 2, 6};
  PointCloud unclassified;
  unclassified.points = {{15, 5, 0}};
  const ClipCounts c = count_points_per_parcel(two_squares(), {cloud, unclassified}, 1.6);
  ASSERT_EQ(c.parcels.size(), 2u);
  EXPECT_EQ(c.parcels[0].in_parcel, 1);
  EXPECT_EQ(c.parcels[0].in_buffer, 2);
  EXPECT_EQ(c.parcels[0].roof, 1);
  EXPECT_EQ(c.parcels[0].wall, 1);
  EXPECT_EQ(c.parcels[1].in_parcel, 2);
  EXPECT_EQ(c.parcels[1].roof, 0);
  EXPECT_EQ(c.points, 5);
  EXPECT_EQ(c.unclipped, 1);
  EXPECT_TRUE(c.any_classes);
  const std::string table = clip_table(two_squares(), c);
  EXPECT_NE(table.find("0      P0                      1          2          1          1\n"), std::string::npos)
      << table;
  EXPECT_NE(table.find("5 points, 1 in no parcel (buffer 1.60 m;"), std::string::npos) << table;
  EXPECT_FALSE(count_points_per_parcel(two_squares(), {unclassified}, 1.6).any_classes);
}

TEST(Inspect, CloudAndRasterDescriptions) {
  PointCloud cloud;
  cloud.points = {{1, 2, 3}, {4, -5, 6}, {0, 0, 9}};
  cloud.classes = {6, 6, 2};
  const CloudInfo c = describe_cloud(cloud);
  EXPECT_EQ(c.points, 3u);
  EXPECT_EQ(c.lo, Vec3(0, -5, 3));
  EXPECT_EQ(c.hi, Vec3(4, 2, 9));
  EXPECT_EQ(c.class_counts[6], 2u);
  EXPECT_EQ(c.classified, 3u);
  EXPECT_EQ(c.crs, "(none)");
  FileInfo info;
  info.cloud = c;
  EXPECT_NE(info_text("c.las", info).find("    class 6: 2 (66.7 %)\n"), std::string::npos);

  Dtm d;  // 4 x 3 cells of 2 m, north up, centre of cell (0,0) at (101, 209)
  d.x0 = 101, d.y0 = 209, d.dx = 2, d.dy = -2, d.nx = 4, d.ny = 3;
  const RasterInfo r = describe_raster(d);
  EXPECT_DOUBLE_EQ(r.x_min, 100);
  EXPECT_DOUBLE_EQ(r.x_max, 108);
  EXPECT_DOUBLE_EQ(r.y_min, 204);
  EXPECT_DOUBLE_EQ(r.y_max, 210);
  EXPECT_DOUBLE_EQ(r.cell_y, 2);

  EXPECT_TRUE(is_point_cloud_file("a/b.LAZ"));
  EXPECT_FALSE(is_point_cloud_file("parcels.gpkg"));
  EXPECT_THROW(describe_file(test::temp_dir("info") + "/nothing.gpkg"), std::exception);
}

TEST(Inspect, SampleTownTruthAsTheBatchsModel) {
  SampleOptions opt;
  opt.parcels = 10;
  opt.seed = 5;
  const SampleTown town = make_sample_town(opt);
  const BatchModel model = truth_model(town);
  ASSERT_EQ(model.results.size(), town.parcels.size());
  const SampleTownCounts n = count_town(town);
  int buildings = 0, parcels = 0;
  for (const auto& r : model.results) {
    buildings += int(r.buildings.size());
    EXPECT_EQ(r.status, r.buildings.empty() ? ParcelStatus::Empty : ParcelStatus::Ok);
  }
  for (const auto& [layout, count] : n.layouts) parcels += count;
  EXPECT_EQ(buildings, n.buildings);
  EXPECT_EQ(parcels, 10);
  EXPECT_EQ(size_t(n.roof_points + n.wall_points + n.other_points), town.cloud.points.size());
  EXPECT_GT(n.roof_points, 0);
  EXPECT_GT(n.wall_points, 0);
}
