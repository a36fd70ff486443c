#pragma once
// Cutting the batch into parcel scenes: points clipped per parcel (roof points
// with a wider context than the overhang buffer, so a roof across a boundary is
// seen well enough to tell an overhang from a shared roof), the neighbours each
// parcel must agree with, all in the batch's local frame.
#include <vector>

#include "cadastre/batch/batch_inputs.h"
#include "cadastre/clip.h"
#include "core/reconstruct/reconstruct.h"

namespace c3d {

// Beyond the overhang buffer, how far roof points reach for ownership to see
// the rest of a roof that crosses the boundary.
constexpr double kOwnershipContextM = 1.5;

struct SceneSource {
  const LoadedInputs* inputs = nullptr;
  LocalFrame frame;
  double overhang_buffer_m = 0;
  ParcelClipper::IndexLists roof_lists, wall_lists;  // per parcel: point indices
  std::vector<std::vector<int>> neighbours;          // per parcel: parcels that may share a roof
  int roof_points_per_cell = 0;                      // one density for every scene
};

SceneSource prepare_scenes(const LoadedInputs& inputs, const ClipParams& clip, const LocalFrame& frame);

ParcelScene make_scene(const SceneSource& source, size_t parcel);

}  // namespace c3d
