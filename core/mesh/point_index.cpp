#include "core/mesh/point_index.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace c3d {

struct PointIndex::Tree {
  Vec3 origin = Vec3::Zero();
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pcl::KdTreeFLANN<pcl::PointXYZ> kd;
  pcl::PointXYZ local(const Vec3& p) const {
    const Vec3 q = p - origin;
    return pcl::PointXYZ(float(q.x()), float(q.y()), float(q.z()));
  }
};

PointIndex::PointIndex(const std::vector<Vec3>& points) : tree_(std::make_unique<Tree>()) {
  if (points.empty()) return;
  tree_->origin = points.front();
  tree_->cloud->reserve(points.size());
  for (const Vec3& p : points) tree_->cloud->push_back(tree_->local(p));
  tree_->kd.setInputCloud(tree_->cloud);
}

PointIndex::~PointIndex() = default;

double PointIndex::nearest(const Vec3& p) const {
  double d = 0;
  nearest_index(p, &d);
  return d;
}

int PointIndex::nearest_index(const Vec3& p, double* d) const {
  *d = std::numeric_limits<double>::infinity();
  if (tree_->cloud->empty()) return -1;
  std::vector<int> idx(1);
  std::vector<float> d2(1);
  tree_->kd.nearestKSearch(tree_->local(p), 1, idx, d2);
  *d = std::sqrt(double(d2[0]));
  return idx[0];
}

double PointIndex::nearest_other(size_t i) const {
  std::vector<int> idx;
  std::vector<float> d2;
  for (int k = 2; k <= 64; k *= 2) {  // past the copies of this place
    tree_->kd.nearestKSearch(tree_->cloud->points[i], k, idx, d2);
    const auto other = std::find_if(d2.begin(), d2.end(), [](float d) { return d > 1e-12f; });
    if (other != d2.end()) return std::sqrt(double(*other));
    if (int(idx.size()) < k) break;  // every point is here
  }
  return -1;
}

std::vector<int> PointIndex::nearest_k(size_t i, size_t k) const {
  std::vector<int> idx;
  std::vector<float> d2;
  tree_->kd.nearestKSearch(tree_->cloud->points[i], int(k), idx, d2);
  return idx;
}

}  // namespace c3d
