#include "core/classify/classify.h"

#include <algorithm>
#include <cmath>

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

FeatureTable cloud_features(const std::vector<Vec3>& world, const Dtm& terrain) {
  if (world.empty()) return {};
  Vec3 lo = world.front();
  for (const auto& p : world) lo = lo.cwiseMin(p);
  const Vec3 origin(std::floor(lo.x() / 10) * 10, std::floor(lo.y() / 10) * 10, std::floor(lo.z()));
  std::vector<Vec3> local(world.size());
  for (size_t i = 0; i < world.size(); ++i) local[i] = world[i] - origin;
  return compute_features(local, heights_above_terrain(world, terrain));
}

Classification classify_points(const PointForest& forest, const std::vector<Vec3>& world, const Dtm& terrain) {
  Classification c;
  c.classes = forest.predict(cloud_features(world, terrain));
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
