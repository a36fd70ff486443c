#include "core/reconstruct/segment/neighbours.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace c3d {

NeighbourTable::NeighbourTable(const PointCloudConstPtr& cloud, int k) : Search("NeighbourTable", true) {
  tree_.setInputCloud(cloud);
  input_ = cloud;
  size_t n = cloud->size();
  stored_ = int(std::min<size_t>(size_t(std::max(k, 0)), n));
  nn_.resize(n * size_t(stored_));
  d2_.resize(n * size_t(stored_));
  pcl::Indices nn;
  std::vector<float> d2;
  for (size_t i = 0; i < n; ++i) {
    tree_.nearestKSearch(pcl::index_t(i), stored_, nn, d2);
    std::copy(nn.begin(), nn.end(), nn_.begin() + long(i) * stored_);
    std::copy(d2.begin(), d2.end(), d2_.begin() + long(i) * stored_);
  }
}

void NeighbourTable::setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices) {
  if (cloud != input_ || indices) throw std::logic_error("NeighbourTable serves only the cloud it was built on");
}

int NeighbourTable::nearestKSearch(pcl::index_t index, int k, pcl::Indices& nn, std::vector<float>& d2) const {
  if (k > stored_ && size_t(k) <= input_->size()) return tree_.nearestKSearch(index, k, nn, d2);
  int n = std::min(k, stored_);
  auto first = long(index) * stored_;
  nn.assign(nn_.begin() + first, nn_.begin() + first + n);
  d2.assign(d2_.begin() + first, d2_.begin() + first + n);
  return n;
}

int NeighbourTable::nearestKSearch(const PointCloud& cloud, pcl::index_t index, int k, pcl::Indices& nn,
                                   std::vector<float>& d2) const {
  if (&cloud == input_.get()) return nearestKSearch(index, k, nn, d2);
  return tree_.nearestKSearch(cloud[size_t(index)], k, nn, d2);
}

int NeighbourTable::nearestKSearch(const pcl::PointXYZ& p, int k, pcl::Indices& nn, std::vector<float>& d2) const {
  return tree_.nearestKSearch(p, k, nn, d2);
}

int NeighbourTable::radiusSearch(const pcl::PointXYZ& p, double r, pcl::Indices& nn, std::vector<float>& d2,
                                 unsigned int max_nn) const {
  return tree_.radiusSearch(p, r, nn, d2, max_nn);
}

pcl::Indices remove_statistical_outliers(const NeighbourTable& table, int k, double std_mul) {
  size_t n = table.getInputCloud()->size();
  std::vector<double> mean_dist(n, 0.0);
  pcl::Indices nn;
  std::vector<float> d2;
  for (size_t i = 0; i < n; ++i) {
    int found = table.nearestKSearch(pcl::index_t(i), k + 1, nn, d2);  // the point itself comes first
    for (int j = 1; j < found; ++j) mean_dist[i] += std::sqrt(d2[size_t(j)]);
    mean_dist[i] /= k;
  }
  double sum = 0, sq_sum = 0;
  for (double d : mean_dist) sum += d, sq_sum += d * d;
  double mean = n > 0 ? sum / double(n) : 0.0;
  double sd = n > 1 ? std::sqrt(std::max(0.0, (sq_sum - sum * mean) / double(n - 1))) : 0.0;
  pcl::Indices kept;
  for (size_t i = 0; i < n; ++i)
    if (mean_dist[i] <= mean + std_mul * sd) kept.push_back(pcl::index_t(i));
  return kept;
}

}  // namespace c3d
