#include "core/mesh/spacing.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>

#include <algorithm>

namespace c3d {

PointSpacing point_spacing(const std::vector<Vec3>& points) {
  PointSpacing s;
  s.points = points.size();
  if (points.size() < 2) return s;
  const Vec3 origin = points.front();  // float k-d tree: near the points, centimetres hold
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const Vec3& p : points) {
    const Vec3 q = p - origin;
    cloud->push_back(pcl::PointXYZ(float(q.x()), float(q.y()), float(q.z())));
  }
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  std::vector<double> nearest;
  nearest.reserve(points.size());
  std::vector<int> idx;
  std::vector<float> d2;
  for (size_t i = 0; i < points.size(); ++i) {
    for (int k = 2; k <= 64; k *= 2) {  // past the copies of this place
      tree.nearestKSearch(cloud->points[i], k, idx, d2);
      const auto other = std::find_if(d2.begin(), d2.end(), [](float d) { return d > 1e-12f; });
      if (other != d2.end()) {
        nearest.push_back(std::sqrt(double(*other)));
        break;
      }
      if (int(idx.size()) < k) break;  // every point is here
    }
  }
  if (nearest.empty()) return s;
  std::sort(nearest.begin(), nearest.end());
  const auto at = [&](double q) { return nearest[size_t(q * double(nearest.size() - 1) + 0.5)]; };
  s.min = nearest.front(), s.max = nearest.back(), s.median = at(0.5), s.p95 = at(0.95);
  double sum = 0;
  for (double d : nearest) sum += d;
  s.mean = sum / double(nearest.size());
  return s;
}

}  // namespace c3d
