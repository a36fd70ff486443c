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
// The points of one voxel half a radius across share the neighbourhood around
// their centroid: a cloud costs one search per such voxel however dense it is,
// and a point is never farther than 0.43 r from where its neighbourhood is seen.
constexpr double kQueryVoxelsPerRadius = 2.0;
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
  std::vector<int> multiple;  // points of pulses with more than one return
  std::vector<int> of_point;  // voxel index per input point
};

// Cell key -> voxel number, open addressing: std::unordered_map allocates a
// node per voxel, which cost more than the searches on clouds of mostly
// single-point voxels.
class VoxelIndex {
 public:
  explicit VoxelIndex(size_t most) {
    size_t capacity = 16;
    while (capacity < 2 * most) capacity *= 2;
    keys_.assign(capacity, kEmpty);
    values_.resize(capacity);
  }
  // The voxel of key, numbered `next` when it is new (fresh set).
  int find_or_add(std::int64_t key, int next, bool& fresh) {
    const size_t mask = keys_.size() - 1;
    for (size_t at = size_t(std::uint64_t(key) * 0x9E3779B97F4A7C15ull >> 20) & mask;; at = (at + 1) & mask) {
      if (keys_[at] == key) return fresh = false, values_[at];
      if (keys_[at] == kEmpty) return keys_[at] = key, values_[at] = next, fresh = true, next;
    }
  }

 private:
  static constexpr std::int64_t kEmpty = -1;  // cell_key is never negative
  std::vector<std::int64_t> keys_;
  std::vector<int> values_;
};

// The first n points (all by default) in voxels of the given size.
Voxels voxelize(const std::vector<Vec3>& pts, double size, const std::vector<std::uint8_t>& returns = {},
                size_t n = SIZE_MAX) {
  n = std::min(n, pts.size());
  Voxels v;
  VoxelIndex index(n);
  v.of_point.resize(n);
  v.centroids.reserve(n);  // untouched pages cost nothing; regrowing copies and faults
  v.counts.reserve(n);
  v.multiple.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 c = (pts[i] / size).array().floor();
    bool fresh = false;
    const int at = index.find_or_add(cell_key(std::int64_t(c.x()), std::int64_t(c.y()), std::int64_t(c.z())),
                                     int(v.centroids.size()), fresh);
    if (fresh) {
      v.centroids.push_back(Vec3::Zero());
      v.counts.push_back(0);
      v.multiple.push_back(0);
    }
    v.centroids[size_t(at)] += pts[i];
    ++v.counts[size_t(at)];
    if (!returns.empty() && number_of_returns(returns[i]) > 1) ++v.multiple[size_t(at)];
    v.of_point[i] = at;
  }
  for (size_t k = 0; k < v.centroids.size(); ++k) v.centroids[k] /= v.counts[k];
  return v;
}

EigenFeatures from_covariance(const Eigen::Matrix3d& cov) {
  EigenFeatures f;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);  // closed form: several times the iterative solver's speed, ample for features
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

// One scale's neighbourhood, seen from a query voxel's centroid.
struct Neighbourhood {
  EigenFeatures shape;
  double occupancy = 0, zmin = 0, zmax = 0, multiple = 0;
};

Neighbourhood around(const Voxels& v, const Vec3& q, double r, const std::vector<int>& idx,
                     const std::vector<float>& d2) {
  // Each voxel weighs as the points it holds (the surface as sampled, not as
  // the grid cuts it), falling smoothly to 0 at the sphere: without that the
  // few voxels at its edge come and go with the query's place and bias the shape.
  Neighbourhood nb;
  nb.zmin = nb.zmax = q.z();
  thread_local std::vector<double> weight;
  weight.resize(idx.size());
  Vec3 mean = Vec3::Zero();
  double wsum = 0, multiple = 0;
  for (size_t n = 0; n < idx.size(); ++n) {
    const Vec3& c = v.centroids[idx[n]];
    const double u = std::max(0.0, 1.0 - d2[n] / (r * r)), falloff = u * u;
    weight[n] = v.counts[idx[n]] * falloff;
    mean += weight[n] * c;
    wsum += weight[n];
    multiple += v.multiple[idx[n]] * falloff;
    nb.zmin = std::min(nb.zmin, c.z());
    nb.zmax = std::max(nb.zmax, c.z());
  }
  constexpr double kDisc = kPi * kVoxelsPerRadius * kVoxelsPerRadius;  // voxels a plane fills in the sphere
  nb.occupancy = idx.size() / kDisc;
  nb.multiple = wsum > 0 ? multiple / wsum : 0.0;
  if (idx.size() < 3 || !(wsum > 0)) return nb;
  mean /= wsum;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t n = 0; n < idx.size(); ++n) {
    const Vec3 d = v.centroids[idx[n]] - mean;
    cov += weight[n] * d * d.transpose();
  }
  nb.shape = from_covariance(cov / wsum);
  return nb;
}

// Fills the kFeaturesPerScale columns of one scale for the table's rows;
// returns the scale's voxels (the finest give the density).
Voxels scale_features(const std::vector<Vec3>& pts, const std::vector<std::uint8_t>& returns, int scale,
                      FeatureTable& t) {
  const size_t core = t.rows;
  const double r = kScaleRadius[scale];
  Voxels v = voxelize(pts, r / kVoxelsPerRadius, returns);
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(v.centroids.size());
  for (const auto& c : v.centroids) cloud->push_back(pcl::PointXYZ(float(c.x()), float(c.y()), float(c.z())));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(false);
  tree.setInputCloud(cloud);
  const Voxels queries = voxelize(pts, r / kQueryVoxelsPerRadius, {}, core);
  std::vector<Neighbourhood> around_query(queries.centroids.size());
  std::vector<int> idx;
  std::vector<float> d2;
  for (size_t k = 0; k < queries.centroids.size(); ++k) {
    const Vec3& q = queries.centroids[k];
    tree.radiusSearch(pcl::PointXYZ(float(q.x()), float(q.y()), float(q.z())), r, idx, d2);
    around_query[k] = around(v, q, r, idx, d2);
  }
  for (size_t i = 0; i < core; ++i) {
    const Neighbourhood& nb = around_query[size_t(queries.of_point[i])];
    const double z = pts[i].z();
    float* f = t.values.data() + i * kFeatureCount + scale * kFeaturesPerScale;
    f[0] = float(nb.shape.linearity);
    f[1] = float(nb.shape.planarity);
    f[2] = float(nb.shape.scattering);
    f[3] = float(nb.shape.verticality);
    f[4] = float(nb.shape.vertical_direction);
    f[5] = float(nb.occupancy);
    f[6] = float((std::max(nb.zmax, z) - z) / r);
    f[7] = float((z - std::min(nb.zmin, z)) / r);
    f[8] = returns.empty() ? kUnknownReturns : float(nb.multiple);
  }
  return v;
}

}  // namespace

const std::vector<std::string>& feature_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    const char* per_scale[kFeaturesPerScale] = {"linearity",   "planarity",          "scattering",
                                                "verticality", "vertical_direction", "occupancy",
                                                "extent_above", "extent_below", "multiple_returns"};
    for (int s = 0; s < kScaleCount; ++s)
      for (const char* f : per_scale) {
        char radius[16];
        std::snprintf(radius, sizeof radius, "%.1f", kScaleRadius[s]);
        n.push_back(std::string(f) + "@" + radius + "m");
      }
    n.insert(n.end(), {"height_above_terrain", "column_above", "column_below", "relative_density", "not_last_return"});
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

double feature_reach() {
  // A query voxel's centroid lies up to half its diagonal from a point, and a
  // neighbour voxel's points up to half theirs from its centroid.
  const double half_diagonal = 0.5 * std::sqrt(3.0);
  return kScaleRadius[kScaleCount - 1] * (1 + half_diagonal / kQueryVoxelsPerRadius + half_diagonal / kVoxelsPerRadius) +
         kColumnCell;
}

double feature_grid() { return 2 * kScaleRadius[kScaleCount - 1]; }

bool has_multiple_returns(const std::vector<std::uint8_t>& returns) {
  for (auto r : returns)
    if (number_of_returns(r) > 1) return true;
  return false;
}

FeatureTable compute_features(const std::vector<Vec3>& pts, const std::vector<double>& hat,
                              const std::vector<std::uint8_t>& given_returns, size_t core) {
  FeatureTable t;
  t.rows = std::min(core, pts.size());
  t.values.assign(t.rows * kFeatureCount, 0.0f);
  if (t.rows == 0) return t;
  static const std::vector<std::uint8_t> kNone;
  const auto& returns = given_returns.size() == pts.size() ? given_returns : kNone;
  const Voxels fine = scale_features(pts, returns, 0, t);
  for (int s = 1; s < kScaleCount; ++s) scale_features(pts, returns, s, t);
  // Density relative to the cloud's own median over the finest voxels: a surveyed
  // surface is dense, a facade seen from the air or a crown's interior is sparse.
  std::vector<int> counts = fine.counts;
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  const double median = std::max(1, counts[counts.size() / 2]);
  const Columns columns(pts);
  constexpr int kGlobal = kScaleCount * kFeaturesPerScale;
  for (size_t i = 0; i < t.rows; ++i) {
    float* f = t.values.data() + i * kFeatureCount + kGlobal;
    const auto [above, below] = columns.above_below(pts[i]);
    f[0] = float(hat[i]);
    f[1] = float(above);
    f[2] = float(below);
    f[3] = float(fine.counts[fine.of_point[i]] / median);
    f[4] = returns.empty() ? kUnknownReturns
                           : float(return_number(returns[i]) < number_of_returns(returns[i]) ? 1 : 0);
  }
  return t;
}

}  // namespace c3d
