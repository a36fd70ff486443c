#include "core/reconstruct/segment/clusters.h"

#include "core/geometry/cell_key.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace c3d {
namespace {

using Cell = CellKey<3>;

// Union-find over positions in the indices.
struct Sets {
  std::vector<int> parent;
  explicit Sets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    return i;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

// FLANN's L2_Simple, term by term in float, as the k-d tree measures.
float distance2(const pcl::PointXYZ& a, const pcl::PointXYZ& b) {
  float result = 0.f, diff = a.x - b.x;
  result += diff * diff;
  diff = a.y - b.y;
  result += diff * diff;
  diff = a.z - b.z;
  result += diff * diff;
  return result;
}

}  // namespace

std::vector<pcl::PointIndices> euclidean_clusters(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                  const pcl::Indices& indices, float tolerance,
                                                  size_t min_points, size_t max_points) {
  // PCL squares the tolerance in double and compares float squares.
  const float reach2 = float(double(tolerance) * double(tolerance));
  if (!(tolerance > 0)) throw std::invalid_argument("euclidean_clusters: the tolerance must be positive");
  // Cells whose diagonal is a little under the tolerance: any two points of one are near.
  const double side = double(tolerance) / std::sqrt(3.0) * 0.999;
  const int span = int(std::ceil(double(tolerance) / side));  // cells apart that may still hold a near pair
  std::unordered_map<Cell, std::vector<int>, CellKeyHash<3>> cells;  // positions in `indices`
  for (size_t k = 0; k < indices.size(); ++k)
    cells[cell_key<3>(cloud[size_t(indices[k])].getVector3fMap(), side)].push_back(int(k));
  Sets sets(indices.size());
  for (const auto& [cell, members] : cells) {
    for (int k : members) sets.unite(members.front(), k);
    for (int dx = -span; dx <= span; ++dx)
      for (int dy = -span; dy <= span; ++dy)
        for (int dz = -span; dz <= span; ++dz) {
          const Cell other{cell[0] + dx, cell[1] + dy, cell[2] + dz};
          if (!(cell < other)) continue;  // each pair of cells once
          const auto it = cells.find(other);
          if (it == cells.end() || sets.find(members.front()) == sets.find(it->second.front())) continue;
          [&] {
            for (int a : members)
              for (int b : it->second)
                if (distance2(cloud[size_t(indices[size_t(a)])], cloud[size_t(indices[size_t(b)])]) < reach2)
                  return sets.unite(a, b);
          }();
        }
  }
  // In the order PCL grows them: by the first of the indices each holds.
  std::vector<int> cluster_of_root(indices.size(), -1);
  std::vector<pcl::PointIndices> grown;
  for (size_t k = 0; k < indices.size(); ++k) {
    int& c = cluster_of_root[size_t(sets.find(int(k)))];
    if (c < 0) c = int(grown.size()), grown.emplace_back();
    grown[size_t(c)].indices.push_back(indices[k]);
  }
  std::vector<pcl::PointIndices> clusters;
  for (auto& g : grown) {
    std::sort(g.indices.begin(), g.indices.end());
    g.indices.erase(std::unique(g.indices.begin(), g.indices.end()), g.indices.end());
    if (g.indices.size() >= min_points && g.indices.size() <= max_points) {
      g.header = cloud.header;
      clusters.push_back(std::move(g));
    }
  }
  std::sort(clusters.rbegin(), clusters.rend(),
            [](const pcl::PointIndices& a, const pcl::PointIndices& b) { return a.indices.size() < b.indices.size(); });
  return clusters;
}

}  // namespace c3d
