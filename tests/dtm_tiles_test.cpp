// A DTM raster with NoData, filled on the raster's own grid of tiles: the
// cells never depend on the windows asked for, equal read_dtm's, and no more
// than a tile and its margin is filled at once. A raster within one tile is
// filled whole, exactly as before tiles.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <thread>

#include "core/io/dtm_fill.h"
#include "core/io/dtm_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

constexpr int kS = DtmSource::kFillTileCells, kM = DtmSource::kFillMarginCells;

// Building-size holes every 97 cells; a lake of 700 x 500 cells across a tile
// corner; and, when corner is set, a 1400 x 1400 NoData corner (its tile has
// no valid cell within its margin).
bool is_hole(int i, int j, bool corner) {
  if (i % 97 >= 80 && j % 97 >= 75) return true;
  if (i >= 2 * kS - 300 && i < 2 * kS + 400 && j >= kS - 200 && j < kS + 300) return true;
  return corner && i < 1400 && j < 1400;
}

std::string write_tif(const std::string& path, int nx, int ny, bool corner) {
  GDALAllRegister();
  const char* const opts[] = {"TILED=YES", "COMPRESS=DEFLATE", nullptr};
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), nx, ny, 1, GDT_Float32,
                                                                           const_cast<char**>(opts));
  double gt[6] = {781000.0, 1.0, 0.0, 9242000.0, 0.0, -1.0};
  ds->SetGeoTransform(gt);
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(-9999.0);
  std::vector<float> row(nx);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i)
      row[i] = is_hole(i, j, corner) ? -9999.0f : float(700.0 + 4.0 * std::sin(i * 0.01) + 0.002 * i + 0.003 * j);
    EXPECT_EQ(band->RasterIO(GF_Write, 0, j, nx, 1, row.data(), nx, 1, GDT_Float32, 0, 0), CE_None);
  }
  GDALClose(ds);
  return path;
}

bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Windows of boxes step_x x step_y cells tiling the raster, in the order given.
void expect_windows_equal(const DtmSource& source, const Dtm& whole, int step_x, int step_y, bool reverse) {
  std::vector<std::pair<int, int>> boxes;
  for (int j = 0; j < whole.ny; j += step_y)
    for (int i = 0; i < whole.nx; i += step_x) boxes.emplace_back(i, j);
  if (reverse) std::reverse(boxes.begin(), boxes.end());
  auto check = [&](size_t from, size_t to) {
    for (size_t k = from; k < to; ++k) {
      const double x = whole.x0 + boxes[k].first, y = whole.y0 - boxes[k].second;
      const Dtm w = source.window(x, y - step_y, x + step_x, y);
      for (int v = 0; v < w.win_ny; ++v)
        for (int u = 0; u < w.win_nx; ++u)
          ASSERT_TRUE(same(w.cell(w.win_x + u, w.win_y + v), whole.cell(w.win_x + u, w.win_y + v)))
              << "cell " << w.win_x + u << " " << w.win_y + v << " of window " << k;
    }
  };
  // Two threads share the source, as a batch's workers do.
  std::thread other(check, 0, boxes.size() / 2);
  check(boxes.size() / 2, boxes.size());
  other.join();
}

TEST(DtmTiles, WindowsInAnyChunkLayoutEqualTheWholeBitForBit) {
  const std::string path = write_tif(test::temp_dir("dtm_tiles") + "/dtm.tif", 2600, 1700, true);
  const Dtm whole = read_dtm(path);
  ASSERT_EQ(whole.z.size(), size_t(2600) * 1700);
  // Every cell filled within the terrain's range; a building hole follows the terrain.
  for (float v : whole.z) ASSERT_TRUE(std::isfinite(v) && v > 690 && v < 720) << v;
  EXPECT_NEAR(whole.cell(2319, 1443), 700.0 + 4.0 * std::sin(2319 * 0.01) + 0.002 * 2319 + 0.003 * 1443, 0.05);
  const DtmSource a(path), b(path);
  expect_windows_equal(a, whole, 300, 300, false);
  expect_windows_equal(b, whole, 530, 370, true);
}

// The fill holds a tile and its margin, never the raster: a raster of 5 x 5
// tiles fills at most (S + 2M)^2 cells at once for a window, and for the whole.
TEST(DtmTiles, FillHoldsATileAndItsMarginNotTheRaster) {
  const std::string path = write_tif(test::temp_dir("dtm_tiles_mem") + "/dtm.tif", 5 * kS, 5 * kS, false);
  const DtmSource source(path);
  EXPECT_EQ(source.peak_fill_cells(), 0u);  // opening fills nothing
  const Dtm& h = source.header();
  const Dtm w = source.window(h.x0 + 2500, h.y0 - 2600, h.x0 + 2700, h.y0 - 2500);
  EXPECT_TRUE(std::isfinite(w.cell(2600, 2550)));
  EXPECT_EQ(source.peak_fill_cells(), size_t(kS + 2 * kM) * size_t(kS + 2 * kM));
  const size_t cells = size_t(h.nx) * size_t(h.ny);
  EXPECT_LT(source.peak_fill_cells() * 10, cells);
  // A child process's peak memory for one window: a tile's worth, not the
  // raster's 100 MB of heights (and its fill's 16 bytes a cell).
  const pid_t pid = fork();
  if (pid == 0) {
    auto status_kb = [](const char* key) {  // VmRSS, VmHWM of /proc/self/status
      FILE* f = std::fopen("/proc/self/status", "r");
      char line[256];
      long kb = -1;
      while (f && std::fgets(line, sizeof line, f))
        if (std::strncmp(line, key, std::strlen(key)) == 0) kb = std::atol(line + std::strlen(key));
      if (f) std::fclose(f);
      return kb;
    };
    malloc_trim(0);  // freed heap would hide the window's own peak
    if (FILE* f = std::fopen("/proc/self/clear_refs", "w")) std::fputs("5", f), std::fclose(f);  // VmHWM = VmRSS
    const long before = status_kb("VmRSS:");
    DtmSource(path).window(h.x0 + 2500, h.y0 - 2600, h.x0 + 2700, h.y0 - 2500);
    _exit(int(std::clamp((status_kb("VmHWM:") - before) / 4096, 0L, 250L)));  // in units of 4 MB
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  const int grown_mb = 4 * WEXITSTATUS(status);
  std::printf("one window of a %zu MB raster: %d MB more at its peak\n", cells * 4 / 1000000, grown_mb);
  EXPECT_LT(grown_mb, 160);
}

// A raster within one tile is filled as one grid: read_dtm gives exactly
// fill_holes on its cells (the fill before tiles).
TEST(DtmTiles, RasterWithinOneTileIsFilledWhole) {
  const std::string path = write_tif(test::temp_dir("dtm_tiles_one") + "/dtm.tif", kS, 700, false);
  const Dtm tiled = read_dtm(path);
  Dtm plain = DtmSource(path).header();
  GdalDataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  plain.z.resize(size_t(plain.nx) * size_t(plain.ny));
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, plain.nx, plain.ny, plain.z.data(), plain.nx, plain.ny,
                                           GDT_Float32, 0, 0),
            CE_None);
  for (float& v : plain.z)
    if (v == -9999.0f) v = std::nanf("");
  fill_holes(plain);
  ASSERT_EQ(tiled.z.size(), plain.z.size());
  for (size_t k = 0; k < plain.z.size(); ++k) ASSERT_TRUE(same(tiled.z[k], plain.z[k])) << k;
  EXPECT_EQ(tiled.nodata_share, plain.nodata_share);
}

}  // namespace
}  // namespace c3d
