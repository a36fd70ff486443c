#include "core/reconstruct/segment/normals.h"

#include <pcl/common/centroid.h>
#include <pcl/common/eigen.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/normal_3d_omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace c3d {
namespace {

// k nearest lie on a line when their second spread is under a fifth of the
// first (variance ratio 0.05): a disc, or a half disc at an eave, spreads
// alike both ways; a row's points 3 cm apart spread only by the noise across it.
constexpr float kLineVarianceRatio = 0.05f;
constexpr int kMaxWidening = 8;       // neighbourhoods grown to 8 k at most
constexpr int kGapNeighbours = 64;    // searched for the nearest in each quarter (rows of 50 points a metre)
constexpr size_t kGapSamples = 2000;  // points the gap is measured at

bool on_a_line(const pcl::PointCloud<pcl::PointXYZ>& cloud, const pcl::Indices& nn) {
  if (nn.size() < 3) return false;
  EIGEN_ALIGN16 Eigen::Matrix3f cov;
  Eigen::Vector4f centroid;
  if (pcl::computeMeanAndCovarianceMatrix(cloud, nn, cov, centroid) == 0) return false;
  Eigen::Vector3f ev;
  pcl::eigen33(cov, ev);  // ascending
  return ev(1) < kLineVarianceRatio * ev(2);
}

}  // namespace

PointNormals estimate_normals(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                              const std::shared_ptr<NeighbourTable>& searched, int k) {
  const NeighbourTable& table = *searched;
  PointNormals out;
  out.normals.reset(new pcl::PointCloud<pcl::Normal>);
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(1);  // parcels already run in parallel
  ne.setInputCloud(cloud);
  ne.setSearchMethod(searched);
  ne.setKSearch(k);
  ne.compute(*out.normals);
  std::vector<int> used(cloud->size(), k);
  pcl::Indices nn;
  std::vector<float> d2;
  for (size_t i = 0; i < cloud->size(); ++i) {
    table.nearestKSearch(pcl::index_t(i), k, nn, d2);
    if (!on_a_line(*cloud, nn)) continue;
    int wide = 2 * k;
    for (; wide < kMaxWidening * k && size_t(wide) < cloud->size(); wide *= 2) {
      table.nearestKSearch(pcl::index_t(i), wide, nn, d2);
      if (!on_a_line(*cloud, nn)) break;
    }
    if (size_t(wide) >= cloud->size()) continue;
    table.nearestKSearch(pcl::index_t(i), wide, nn, d2);
    Eigen::Vector4f plane;
    float curvature = 0;
    if (!pcl::computePointNormal(*cloud, nn, plane, curvature)) continue;
    auto& n = (*out.normals)[i];
    n.normal_x = plane[0], n.normal_y = plane[1], n.normal_z = plane[2], n.curvature = curvature;
    const auto& p = (*cloud)[i];
    pcl::flipNormalTowardsViewpoint(p, 0.f, 0.f, 0.f, n.normal_x, n.normal_y, n.normal_z);  // as PCL's default
    used[i] = wide;
  }
  std::nth_element(used.begin(), used.begin() + long(used.size() / 2), used.end());
  out.neighbours = used.empty() ? k : used[used.size() / 2];
  return out;
}

double sampling_gap(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, const NeighbourTable& table) {
  std::vector<double> gaps;
  pcl::Indices nn;
  std::vector<float> d2;
  const int k = int(std::min<size_t>(kGapNeighbours, cloud->size()));
  const size_t step = std::max<size_t>(1, cloud->size() / kGapSamples);
  for (size_t i = 0; i < cloud->size(); i += step) {
    table.nearestKSearch(pcl::index_t(i), k, nn, d2);
    std::array<double, 4> nearest;
    nearest.fill(std::numeric_limits<double>::infinity());
    const auto& p = (*cloud)[i];
    for (size_t j = 1; j < nn.size(); ++j) {
      const auto& q = (*cloud)[size_t(nn[j])];
      const double dx = q.x - p.x, dy = q.y - p.y;
      if (dx == 0 && dy == 0) continue;
      // quarters centred on the axes: a row along x has the next row in the +y and -y quarters
      const int quarter = std::abs(dx) >= std::abs(dy) ? (dx > 0 ? 0 : 2) : (dy > 0 ? 1 : 3);
      nearest[size_t(quarter)] = std::min(nearest[size_t(quarter)], std::sqrt(double(d2[j])));
    }
    const double widest = *std::max_element(nearest.begin(), nearest.end());
    if (std::isfinite(widest)) gaps.push_back(widest);
  }
  if (gaps.empty()) return 0;
  std::nth_element(gaps.begin(), gaps.begin() + long(gaps.size() / 2), gaps.end());
  return gaps[gaps.size() / 2];
}

}  // namespace c3d
