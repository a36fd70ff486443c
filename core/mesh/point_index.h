#pragma once
// A building's points in a k-d tree (PCL), for nearest-point distances: the
// spacing, Poisson's trimming and the mesh-to-cloud figure. Float inside,
// around the first point: a building spans metres, float holds micrometres.
#include <memory>
#include <vector>

#include "core/types.h"

namespace c3d {

class PointIndex {
 public:
  explicit PointIndex(const std::vector<Vec3>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;
  // Distance from p to the nearest point (infinity with no points).
  double nearest(const Vec3& p) const;
  // The nearest point's index (-1 with no points), and its distance in *d.
  int nearest_index(const Vec3& p, double* d) const;
  // Distance from point i to the nearest point at another place (copies of
  // its place skipped); negative when every point is at its place.
  double nearest_other(size_t i) const;
  // Indices of the k points nearest to point i (itself among them).
  std::vector<int> nearest_k(size_t i, size_t k) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace c3d
