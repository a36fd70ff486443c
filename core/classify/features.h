#pragma once
// Per-point geometric features for the point classifier (core/classify/forest.h):
// at three neighbourhood scales the covariance eigenvalues of the neighbourhood
// (linearity, planarity, scattering), its verticality and extent above and below
// the point; over a plan column the height of what stands above and below; the
// height above terrain and the local density relative to the cloud's own.
// Density-independent by construction: each scale searches a voxel-thinned copy
// of the cloud, so 5 and 500 points per m2 give the same neighbourhood shapes.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

constexpr int kScaleCount = 3;
constexpr int kFeaturesPerScale = 8;
constexpr int kFeatureCount = kScaleCount * kFeaturesPerScale + 4;

// Neighbourhood radii, m: a roof tile's bumps, a facade's height band, a tree crown.
constexpr double kScaleRadius[kScaleCount] = {0.6, 1.2, 2.4};

// Row-major, kFeatureCount floats per point.
struct FeatureTable {
  size_t rows = 0;
  std::vector<float> values;
  const float* row(size_t i) const { return values.data() + i * kFeatureCount; }
};

// Feature names in column order (docs and the model's report).
const std::vector<std::string>& feature_names();

// points: local coordinates (metres from a nearby origin); height_above_terrain:
// one per point, z minus the terrain under it.
FeatureTable compute_features(const std::vector<Vec3>& points,
                              const std::vector<double>& height_above_terrain);

// The eigen features of one neighbourhood (exposed for tests): with
// l1 >= l2 >= l3 the covariance eigenvalues, linearity (l1-l2)/l1, planarity
// (l2-l3)/l1, scattering l3/l1, verticality 1 - |n.z| of the normal (smallest
// eigenvector), vertical_direction |e1.z| of the principal direction.
struct EigenFeatures {
  double linearity = 0, planarity = 0, scattering = 0, verticality = 0, vertical_direction = 0;
  bool valid = false;  // fewer than 3 points or all coincident: everything 0
};
EigenFeatures eigen_features(const std::vector<Vec3>& neighbourhood);

}  // namespace c3d
