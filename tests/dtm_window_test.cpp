// DtmSource: a raster read a window at a time gives the same cells, extent and
// lookups as the whole raster read by read_dtm.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "core/io/dtm_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

constexpr int kNx = 300, kNy = 200;

bool in_hole(int i, int j) { return i >= 100 && i < 120 && j >= 50 && j < 70; }

// A tiled 300 x 200 GeoTIFF of a rolling surface (cells of 0.5 m, origin off
// the grid of whole metres), with a NoData block when holes is set.
std::string write_tif(const std::string& dir, bool holes) {
  GDALAllRegister();
  const std::string path = dir + (holes ? "/holes.tif" : "/dtm.tif");
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  const char* const opts[] = {"TILED=YES", "BLOCKXSIZE=64", "BLOCKYSIZE=64", "COMPRESS=DEFLATE", nullptr};
  GDALDataset* ds = gtiff->Create(path.c_str(), kNx, kNy, 1, GDT_Float32, const_cast<char**>(opts));
  double gt[6] = {781481.918, 0.5, 0.0, 9240308.091, 0.0, -0.5};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32748);
  ds->SetSpatialRef(&srs);
  std::vector<float> z(size_t(kNx) * kNy);
  for (int j = 0; j < kNy; ++j)
    for (int i = 0; i < kNx; ++i) {
      const bool hole = holes && in_hole(i, j);
      z[size_t(j) * kNx + i] = hole ? -9999.0f : float(700.0 + 3.0 * std::sin(i * 0.05) + 0.01 * i * j / 7.0);
    }
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(-9999.0);
  EXPECT_EQ(band->RasterIO(GF_Write, 0, 0, kNx, kNy, z.data(), kNx, kNy, GDT_Float32, 0, 0), CE_None);
  GDALClose(ds);
  return path;
}

// Same bits (NaN equals NaN).
bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_window_equals_whole(const std::string& path, bool holes) {
  const Dtm whole = read_dtm(path);
  const DtmSource source(path);
  EXPECT_EQ(source.nodata_cells(), holes ? 400u : 0u);
  const Dtm& h = source.header();
  EXPECT_EQ(h.nx, whole.nx);
  EXPECT_EQ(h.ny, whole.ny);
  EXPECT_TRUE(same(h.x0, whole.x0) && same(h.y0, whole.y0) && same(h.dx, whole.dx) && same(h.dy, whole.dy));
  EXPECT_EQ(h.crs_wkt, whole.crs_wkt);
  EXPECT_TRUE(same(h.nodata_share, whole.nodata_share));
  EXPECT_TRUE(h.z.empty());
  // A box in the middle, 30 x 20 m: cells 120..190, 40..80 or so.
  const double bx = whole.x0 + 120 * whole.dx, by = whole.y0 + 80 * whole.dy;
  const Dtm w = source.window(bx, by, bx + 30.0, by + 20.0);
  EXPECT_EQ(w.win_nx, 60 + 1 + 2 * DtmSource::kWindowMarginCells);
  EXPECT_EQ(w.win_ny, 40 + 1 + 2 * DtmSource::kWindowMarginCells);
  EXPECT_EQ(w.z.size(), size_t(w.win_nx) * size_t(w.win_ny));
  for (int j = 0; j < w.win_ny; ++j)
    for (int i = 0; i < w.win_nx; ++i)
      ASSERT_TRUE(same(w.cell(w.win_x + i, w.win_y + j), whole.cell(w.win_x + i, w.win_y + j))) << i << " " << j;
  EXPECT_TRUE(std::isnan(w.cell(w.win_x - 1, w.win_y)));  // not held
  for (int k = 0; k <= 400; ++k) {  // lookups anywhere in the box, and just beyond it
    const double x = bx - 0.4 + 30.8 * ((k * 37) % 401) / 400.0, y = by - 0.4 + 20.8 * k / 400.0;
    ASSERT_TRUE(same(w.height_at(x, y), whole.height_at(x, y))) << x << " " << y;
    EXPECT_EQ(w.covers(x, y), whole.covers(x, y));
  }
  // A box over the raster's corner: clipped, lookups still equal; beyond: no cell.
  const Dtm corner = source.window(h.x0 - 10, h.y0 - 10, h.x0 + 5, h.y0 + 5);
  EXPECT_EQ(corner.win_x, 0);
  EXPECT_EQ(corner.win_y, 0);
  EXPECT_TRUE(same(corner.height_at(h.x0 + 1.1, h.y0 - 2.3), whole.height_at(h.x0 + 1.1, h.y0 - 2.3)));
  const Dtm beyond = source.window(h.x0 - 100, h.y0 + 50, h.x0 - 90, h.y0 + 60);
  EXPECT_TRUE(std::isnan(beyond.height_at(h.x0 - 95, h.y0 + 55)));
  // The block-wise count sees every valid cell (NoData ones are not heights).
  float first = 0;
  const size_t high = source.count_cells([](float v) { return v > 702.0f; }, &first);
  size_t expected = 0;
  float expected_first = 0;
  for (int j = 0; j < kNy; ++j)
    for (int i = 0; i < kNx; ++i) {
      const float v = whole.cell(i, j);
      if (!(holes && in_hole(i, j)) && v > 702.0f && expected++ == 0) expected_first = v;
    }
  EXPECT_EQ(high, expected);
  EXPECT_GT(high, 0u);
  EXPECT_EQ(first, expected_first);
}

TEST(DtmWindow, WindowOfARasterEqualsTheSameCellsOfTheWhole) {
  expect_window_equals_whole(write_tif(test::temp_dir("dtm_window"), false), false);
}

TEST(DtmWindow, RasterWithNoDataIsFilledAndCut) {
  expect_window_equals_whole(write_tif(test::temp_dir("dtm_window_holes"), true), true);
}

TEST(DtmWindow, WindowLargerThanTheBudgetIsRefused) {
  const std::string path = write_tif(test::temp_dir("dtm_window_budget"), false);
  const DtmSource source(path, 1000);  // the whole raster is over budget: only windows count
  EXPECT_NO_THROW(source.window(781490, 9240290, 781495, 9240295));
  EXPECT_THROW(source.window(781481, 9240208, 781631, 9240308), InputError);
}

TEST(DtmWindow, UnreadableRasterKeepsItsMessage) {
  const std::string dir = test::temp_dir("dtm_window_bad");
  { std::ofstream(dir + "/dtm.tif") << "not a raster"; }
  try {
    DtmSource source(dir + "/dtm.tif");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a raster"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace c3d
