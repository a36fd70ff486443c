#pragma once
// Per-point geometric features for the point classifier (core/classify/forest.h):
// at three neighbourhood scales the covariance eigenvalues of the neighbourhood
// (linearity, planarity, scattering), its verticality and extent above and below
// the point; over a plan column the height of what stands above and below; the
// height above terrain and the local density relative to the cloud's own.
// Density-independent by construction: each scale searches a voxel-thinned copy
// of the cloud, so 5 and 500 points per m2 give the same neighbourhood shapes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

constexpr int kScaleCount = 4;
constexpr int kFeaturesPerScale = 9;
constexpr int kFeatureCount = kScaleCount * kFeaturesPerScale + 5;
// The value of the return features where a cloud carries no multiple returns.
constexpr float kUnknownReturns = -1.0f;

// Neighbourhood radii, m: a roof tile's bumps, a facade's height band, a tree
// crown, a storey of facade (balconies and windows, rough at 1 m, are one
// vertical slab at 5 m; a crown is not).
constexpr double kScaleRadius[kScaleCount] = {0.6, 1.2, 2.4, 4.8};

// Row-major, kFeatureCount floats per point.
struct FeatureTable {
  size_t rows = 0;
  std::vector<float> values;
  const float* row(size_t i) const { return values.data() + i * kFeatureCount; }
};

// Feature names in column order (docs and the model's report).
const std::vector<std::string>& feature_names();

// points: local coordinates (metres from a nearby origin); height_above_terrain:
// one per point, z minus the terrain under it; returns: the LAS return fields
// (pack_returns), or empty where the cloud has no pulse with more than one
// return (has_multiple_returns decides, for a whole cloud). A laser pulse
// through a crown returns several times, one on a roof once: the share of
// multiple returns around a point tells vegetation from buildings where
// geometry alone does not; without them those features are kUnknownReturns.
// Features are computed for the first `core` points; the points after them
// (a margin around a block of the cloud) are neighbours only.
FeatureTable compute_features(const std::vector<Vec3>& points, const std::vector<double>& height_above_terrain,
                              const std::vector<std::uint8_t>& returns = {}, size_t core = SIZE_MAX);
// How far a point's features reach: the widest neighbourhood, seen from up
// to 0.43 of its radius away, with its voxels, and the plan columns.
double feature_reach();
// Every voxel grid of the features divides this length: blocks of a multiple
// of it cut no voxel, so a cloud's features are the same whole or in blocks.
double feature_grid();
// Whether a cloud's return fields say anything: some pulse returned more than once.
bool has_multiple_returns(const std::vector<std::uint8_t>& returns);

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
