#pragma once
// Point-to-mesh distance through a uniform grid over the triangles (not brute
// force), on the GPU (shaders/point_distance.comp) or the CPU reference.
// Used for Chamfer distances and for point-to-model deviation.
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "core/types.h"
#include "core/optimizer/vulkan_compute.h"

namespace c3d {

using Triangle3 = std::array<Vec3, 3>;

struct DistanceOptions {
  ComputeDevice device = ComputeDevice::Auto;
  int threads = 0;              // CPU path: 0 = all cores
  std::string* used = nullptr;  // when set, receives which device ran
  // Distances over this are not searched for: reported as infinity (a
  // point far from the mesh visits many cells).
  double beyond_m = std::numeric_limits<double>::infinity();
};

// Unsigned distance from each point to the nearest triangle (local coordinates).
std::vector<double> point_to_mesh_distances(const std::vector<Vec3>& points,
                                            const std::vector<Triangle3>& triangles,
                                            ComputeDevice device = ComputeDevice::Auto);
std::vector<double> point_to_mesh_distances(const std::vector<Vec3>& points,
                                            const std::vector<Triangle3>& triangles,
                                            const DistanceOptions& options);

// Symmetric Chamfer distance: mean of (a -> mesh b) and (b -> mesh a) distances,
// each side sampled at its vertices plus triangle centroids.
double chamfer_distance(const std::vector<Triangle3>& a, const std::vector<Triangle3>& b,
                        const DistanceOptions& options = {});

}  // namespace c3d
