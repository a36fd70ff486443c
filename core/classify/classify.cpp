#include "core/classify/classify.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include "core/classify/ground_filter.h"
#include "core/io/dtm_io.h"

namespace c3d {
namespace {

constexpr double kGroundCell = 1.0;      // m: as the batch builds its DTM from ground points
}  // namespace

Dtm terrain_from_cloud(const PointCloud& cloud, const ClassMapping& classes, std::string* note) {
  std::vector<Vec3> ground;
  for (size_t i = 0; i < cloud.classes.size() && i < cloud.points.size(); ++i)
    if (classes.is_ground(cloud.classes[i])) ground.push_back(cloud.points[i]);
  if (!ground.empty()) {
    if (note) *note = "terrain from " + std::to_string(ground.size()) + " ground-class points";
    return dtm_from_points(ground, cloud.crs_wkt, kGroundCell, DtmCell::Min, cloud.source + " (ground-class points)");
  }
  Dtm d = smrf_ground(cloud.points).terrain;
  d.crs_wkt = cloud.crs_wkt, d.source = cloud.source + " (SMRF ground)";
  if (note) *note = "no DTM and no ground-class points: terrain by the simple morphological filter";
  return d;
}

std::vector<double> heights_above_terrain(const std::vector<Vec3>& world, const Dtm& t) {
  std::vector<double> out(world.size());
  const double xa = t.x0, xb = t.x0 + (t.nx - 1) * t.dx, ya = t.y0, yb = t.y0 + (t.ny - 1) * t.dy;
  for (size_t i = 0; i < world.size(); ++i) {
    const double x = std::clamp(world[i].x(), std::min(xa, xb), std::max(xa, xb));
    const double y = std::clamp(world[i].y(), std::min(ya, yb), std::max(ya, yb));
    const double g = t.height_at(x, y);
    out[i] = std::isfinite(g) ? world[i].z() - g : 0.0;
  }
  return out;
}

namespace {

constexpr int kBlockGrids = 7;  // 67.2 m blocks: a block's features in cache and a bounded table, whatever the cloud

// Calls visit(rows, features) for the points of each plan block in turn,
// each block seen with a margin of its neighbours' points (feature_reach), in
// a local frame: a cloud's features are the same whole or in blocks, and
// memory holds one block's table at a time.
void for_each_block(const PointCloud& cloud, const Dtm& terrain,
                    const std::function<void(const std::vector<size_t>&, const FeatureTable&)>& visit) {
  const std::vector<Vec3>& world = cloud.points;
  if (world.empty()) return;
  const double kBlock = kBlockGrids * feature_grid();
  Vec3 lo = world.front();
  for (const auto& p : world) lo = lo.cwiseMin(p);
  const Vec3 origin(std::floor(lo.x() / kBlock) * kBlock, std::floor(lo.y() / kBlock) * kBlock, std::floor(lo.z()));
  const std::vector<double> hat = heights_above_terrain(world, terrain);
  const bool returns = cloud.returns.size() == world.size() && has_multiple_returns(cloud.returns);
  std::map<std::pair<long, long>, std::vector<size_t>> blocks;
  for (size_t i = 0; i < world.size(); ++i)
    blocks[{long(std::floor((world[i].x() - origin.x()) / kBlock)), long(std::floor((world[i].y() - origin.y()) / kBlock))}]
        .push_back(i);
  const double reach = feature_reach();
  std::vector<Vec3> local;
  std::vector<double> block_hat;
  std::vector<std::uint8_t> block_returns;
  for (const auto& [key, rows] : blocks) {
    std::vector<size_t> all = rows;
    const double x0 = key.first * kBlock - reach, x1 = (key.first + 1) * kBlock + reach;
    const double y0 = key.second * kBlock - reach, y1 = (key.second + 1) * kBlock + reach;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        auto it = blocks.find({key.first + dx, key.second + dy});
        if ((dx == 0 && dy == 0) || it == blocks.end()) continue;
        for (size_t i : it->second) {
          const Vec3 p = world[i] - origin;
          if (p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1) all.push_back(i);
        }
      }
    local.clear(), block_hat.clear(), block_returns.clear();
    for (size_t i : all) {
      local.push_back(world[i] - origin);
      block_hat.push_back(hat[i]);
      if (returns) block_returns.push_back(cloud.returns[i]);
    }
    visit(rows, compute_features(local, block_hat, block_returns, rows.size()));
  }
}

}  // namespace

FeatureTable cloud_features(const PointCloud& cloud, const Dtm& terrain) {
  FeatureTable t;
  t.rows = cloud.points.size();
  t.values.resize(t.rows * kFeatureCount);
  for_each_block(cloud, terrain, [&](const std::vector<size_t>& rows, const FeatureTable& f) {
    for (size_t k = 0; k < rows.size(); ++k)
      std::copy(f.row(k), f.row(k) + kFeatureCount, t.values.begin() + long(rows[k] * kFeatureCount));
  });
  return t;
}

Classification classify_points(const PointForest& forest, const PointCloud& cloud, const Dtm& terrain) {
  Classification c;
  c.classes.assign(cloud.points.size(), PointClass::Other);
  for_each_block(cloud, terrain, [&](const std::vector<size_t>& rows, const FeatureTable& f) {
    const std::vector<PointClass> block = forest.predict(f);
    for (size_t k = 0; k < rows.size(); ++k) c.classes[rows[k]] = block[k];
  });
  for (PointClass k : c.classes) ++c.counts[int(k)];
  return c;
}

std::uint8_t class_code(PointClass c, const ClassMapping& m) {
  auto first = [](const std::vector<int>& codes, int fallback) {
    return std::uint8_t(codes.empty() ? fallback : codes.front());
  };
  switch (c) {
    case PointClass::Ground: return first(m.ground, 2);
    case PointClass::Roof: return first(m.roof, 6);
    case PointClass::Wall: return first(m.wall, 64);
    case PointClass::Other: break;
  }
  return kOtherClassCode;
}

void write_classes(PointCloud& cloud, const std::vector<PointClass>& classes, const ClassMapping& m) {
  cloud.classes.resize(classes.size());
  for (size_t i = 0; i < classes.size(); ++i) cloud.classes[i] = class_code(classes[i], m);
}

}  // namespace c3d
