// The sample town's cloud as square tiles (see sample_town.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "core/error.h"
#include "core/io/point_io.h"
#include "core/synthetic/sample_town.h"

namespace c3d {

namespace {

// Tiles more than this: a tile size far too small for the town (a typo).
constexpr size_t kMaxTiles = 100000;

std::string tile_name(long long ix, long long iy, double size, bool laz) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "E%.0f_N%.0f.%s", double(ix) * size, double(iy) * size, laz ? "laz" : "las");
  return buf;
}

}  // namespace

std::vector<std::string> write_cloud_tiles(const PointCloud& cloud, const std::string& dir,
                                           const CloudLayout& layout) {
  const double size = layout.tile_size;
  if (!(size > 0) || !std::isfinite(size)) throw InputError(dir, "tile size must be a positive number of metres");
  // Which points fall in which tile (indices only: the tile clouds are made one at a time).
  std::map<std::pair<long long, long long>, std::vector<uint32_t>> tiles;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const auto key = std::make_pair((long long)std::floor(cloud.points[i].x() / size),
                                    (long long)std::floor(cloud.points[i].y() / size));
    tiles[key].push_back(uint32_t(i));
    if (tiles.size() > kMaxTiles)
      throw InputError(dir, "tiles of " + std::to_string(size) + " m cut the cloud into more than " +
                                std::to_string(kMaxTiles) + " tiles");
  }
  std::filesystem::create_directories(dir);
  std::vector<std::string> written;
  for (const auto& [key, indices] : tiles) {
    PointCloud tile;
    tile.crs_wkt = cloud.crs_wkt;
    tile.points.reserve(indices.size());
    for (uint32_t i : indices) {
      tile.points.push_back(cloud.points[i]);
      if (!cloud.classes.empty()) tile.classes.push_back(cloud.classes[i]);
    }
    const std::string path = (std::filesystem::path(dir) / tile_name(key.first, key.second, size, layout.laz)).string();
    (layout.laz ? write_laz : write_las)(path, tile, 6, 4);
    written.push_back(path);
  }
  return written;
}

}  // namespace c3d
