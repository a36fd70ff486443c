#include "core/classify/classify.h"

#include <algorithm>
#include <cmath>

#include "core/io/dtm_io.h"

namespace c3d {
namespace {

constexpr double kGroundCell = 1.0;      // m: as the batch builds its DTM from ground points
constexpr double kCoarseCell = 10.0;     // m: without ground points, cells of lowest points ...
constexpr int kCoarseErosionCells = 2;   // ... lowered to the lowest within 2 cells: a 50 m window
                                         // reaches past the roofs of all but the largest halls

// Each cell lowered to the lowest cell within r cells (grey-scale erosion).
void erode(Dtm& d, int r) {
  const std::vector<float> z = d.z;
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < d.nx; ++i) {
      float lo = z[size_t(j) * d.nx + i];
      for (int b = std::max(0, j - r); b <= std::min(d.ny - 1, j + r); ++b)
        for (int a = std::max(0, i - r); a <= std::min(d.nx - 1, i + r); ++a) lo = std::min(lo, z[size_t(b) * d.nx + a]);
      d.z[size_t(j) * d.nx + i] = lo;
    }
}

}  // namespace

Dtm terrain_from_cloud(const PointCloud& cloud, const ClassMapping& classes, std::string* note) {
  std::vector<Vec3> ground;
  for (size_t i = 0; i < cloud.classes.size() && i < cloud.points.size(); ++i)
    if (classes.is_ground(cloud.classes[i])) ground.push_back(cloud.points[i]);
  if (!ground.empty()) {
    if (note) *note = "terrain from " + std::to_string(ground.size()) + " ground-class points";
    return dtm_from_points(ground, cloud.crs_wkt, kGroundCell, DtmCell::Min, cloud.source + " (ground-class points)");
  }
  Dtm d = dtm_from_points(cloud.points, cloud.crs_wkt, kCoarseCell, DtmCell::Min, cloud.source);
  erode(d, kCoarseErosionCells);
  if (note) *note = "no DTM and no ground-class points: terrain from the lowest points of 10 m cells (give --dtm for better heights)";
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
