#include "core/classify/features.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace c3d {
namespace {

constexpr double kVoxelsPerRadius = 3.0;  // a plane's disc of radius r holds ~28 voxels: a stable covariance
constexpr double kColumnCell = 1.0;       // m: plan cells whose 3 x 3 block reaches a wall's roof edge
constexpr double kPi = 3.14159265358979323846;

std::int64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kOffset = 1 << 20, kMask = (1 << 21) - 1;  // +-1e6 cells each way
  return ((x + kOffset) & kMask) | (((y + kOffset) & kMask) << 21) | (((z + kOffset) & kMask) << 42);
}

// A voxel-thinned copy of the cloud: one centroid per occupied voxel.
struct Voxels {
  std::vector<Vec3> centroids;
  std::vector<int> counts;
  std::vector<int> of_point;  // voxel index per input point
};

Voxels voxelize(const std::vector<Vec3>& pts, double size) {
  Voxels v;
  std::unordered_map<std::int64_t, int> index;
  index.reserve(pts.size() / 4 + 16);
  v.of_point.resize(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec3 c = (pts[i] / size).array().floor();
    auto [it, fresh] = index.emplace(cell_key(std::int64_t(c.x()), std::int64_t(c.y()), std::int64_t(c.z())),
                                     int(v.centroids.size()));
    if (fresh) {
      v.centroids.push_back(Vec3::Zero());
      v.counts.push_back(0);
    }
    v.centroids[it->second] += pts[i];
    ++v.counts[it->second];
    v.of_point[i] = it->second;
  }
  for (size_t k = 0; k < v.centroids.size(); ++k) v.centroids[k] /= v.counts[k];
  return v;
}

EigenFeatures from_covariance(const Eigen::Matrix3d& cov) {
  EigenFeatures f;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);  // ascending
  const double l1 = ev(2), l2 = ev(1), l3 = ev(0);
  if (!(l1 > 1e-12)) return f;
  f.linearity = (l1 - l2) / l1;
  f.planarity = (l2 - l3) / l1;
  f.scattering = l3 / l1;
  f.verticality = 1.0 - std::abs(es.eigenvectors().col(0).z());
  f.vertical_direction = std::abs(es.eigenvectors().col(2).z());
  f.valid = true;
  return f;
}

// Plan columns: lowest and highest z of the points in each cell.
class Columns {
 public:
  explicit Columns(const std::vector<Vec3>& pts) {
    for (const auto& p : pts) {
      auto [it, fresh] = cells_.try_emplace(key(p.x(), p.y()), p.z(), p.z());
      if (!fresh) it->second = {std::min(it->second.first, p.z()), std::max(it->second.second, p.z())};
    }
  }
  // Highest minus z and z minus lowest over the 3 x 3 cells around p.
  std::pair<double, double> above_below(const Vec3& p) const {
    double lo = p.z(), hi = p.z();
    const auto cx = std::int64_t(std::floor(p.x() / kColumnCell)), cy = std::int64_t(std::floor(p.y() / kColumnCell));
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        auto it = cells_.find(cell_key(cx + dx, cy + dy, 0));
        if (it == cells_.end()) continue;
        lo = std::min(lo, it->second.first);
        hi = std::max(hi, it->second.second);
      }
    return {hi - p.z(), p.z() - lo};
  }

 private:
  static std::int64_t key(double x, double y) {
    return cell_key(std::int64_t(std::floor(x / kColumnCell)), std::int64_t(std::floor(y / kColumnCell)), 0);
  }
  std::unordered_map<std::int64_t, std::pair<double, double>> cells_;
};

// Fills the kFeaturesPerScale columns of one scale for every point.
void scale_features(const std::vector<Vec3>& pts, int scale, FeatureTable& t) {
  const double r = kScaleRadius[scale];
  const Voxels v = voxelize(pts, r / kVoxelsPerRadius);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(v.centroids.size());
  for (const auto& c : v.centroids) cloud->push_back(pcl::PointXYZ(float(c.x()), float(c.y()), float(c.z())));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(false);
  tree.setInputCloud(cloud);
  const double disc = kPi * kVoxelsPerRadius * kVoxelsPerRadius;  // voxels a plane fills in the sphere
  std::vector<int> idx;
  std::vector<float> d2;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec3& p = pts[i];
    tree.radiusSearch(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())), r, idx, d2);
    // Each voxel weighs as the points it holds (the surface as sampled, not as
    // the grid cuts it), falling smoothly to 0 at the sphere: without that the
    // few voxels at its edge come and go with the query's place and bias the shape.
    Vec3 mean = Vec3::Zero();
    double zmin = p.z(), zmax = p.z(), wsum = 0;
    for (size_t n = 0; n < idx.size(); ++n) {
      const Vec3& c = v.centroids[idx[n]];
      const double w = v.counts[idx[n]] * std::pow(std::max(0.0, 1.0 - d2[n] / (r * r)), 2);
      mean += w * c;
      wsum += w;
      zmin = std::min(zmin, c.z());
      zmax = std::max(zmax, c.z());
    }
    EigenFeatures e;
    if (idx.size() >= 3 && wsum > 0) {
      mean /= wsum;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (size_t n = 0; n < idx.size(); ++n) {
        const Vec3 d = v.centroids[idx[n]] - mean;
        cov += v.counts[idx[n]] * std::pow(std::max(0.0, 1.0 - d2[n] / (r * r)), 2) * d * d.transpose();
      }
      e = from_covariance(cov / wsum);
    }
    float* f = t.values.data() + i * kFeatureCount + scale * kFeaturesPerScale;
    f[0] = float(e.linearity);
    f[1] = float(e.planarity);
    f[2] = float(e.scattering);
    f[3] = float(e.verticality);
    f[4] = float(e.vertical_direction);
    f[5] = float(idx.size() / disc);
    f[6] = float((zmax - p.z()) / r);
    f[7] = float((p.z() - zmin) / r);
  }
}

}  // namespace

const std::vector<std::string>& feature_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    const char* per_scale[kFeaturesPerScale] = {"linearity",   "planarity",          "scattering",
                                                "verticality", "vertical_direction", "occupancy",
                                                "extent_above", "extent_below"};
    for (int s = 0; s < kScaleCount; ++s)
      for (const char* f : per_scale) {
        char radius[16];
        std::snprintf(radius, sizeof radius, "%.1f", kScaleRadius[s]);
        n.push_back(std::string(f) + "@" + radius + "m");
      }
    n.insert(n.end(), {"height_above_terrain", "column_above", "column_below", "relative_density"});
    return n;
  }();
  return names;
}

EigenFeatures eigen_features(const std::vector<Vec3>& nb) {
  if (nb.size() < 3) return {};
  Vec3 mean = Vec3::Zero();
  for (const auto& p : nb) mean += p;
  mean /= double(nb.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : nb) cov += (p - mean) * (p - mean).transpose();
  return from_covariance(cov / double(nb.size()));
}

FeatureTable compute_features(const std::vector<Vec3>& pts, const std::vector<double>& hat) {
  FeatureTable t;
  t.rows = pts.size();
  t.values.assign(pts.size() * kFeatureCount, 0.0f);
  if (pts.empty()) return t;
  for (int s = 0; s < kScaleCount; ++s) scale_features(pts, s, t);
  // Density relative to the cloud's own median over the finest voxels: a surveyed
  // surface is dense, a facade seen from the air or a crown's interior is sparse.
  const Voxels fine = voxelize(pts, kScaleRadius[0] / kVoxelsPerRadius);
  std::vector<int> counts = fine.counts;
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  const double median = std::max(1, counts[counts.size() / 2]);
  const Columns columns(pts);
  constexpr int kGlobal = kScaleCount * kFeaturesPerScale;
  for (size_t i = 0; i < pts.size(); ++i) {
    float* f = t.values.data() + i * kFeatureCount + kGlobal;
    const auto [above, below] = columns.above_below(pts[i]);
    f[0] = float(hat[i]);
    f[1] = float(above);
    f[2] = float(below);
    f[3] = float(fine.counts[fine.of_point[i]] / median);
  }
  return t;
}

}  // namespace c3d
