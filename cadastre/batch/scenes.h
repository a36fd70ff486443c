#pragma once
// Cutting the batch into parcel scenes: points clipped per parcel (roof points
// with a wider context than the overhang buffer, so a roof across a boundary is
// seen well enough to tell an overhang from a shared roof), the neighbours each
// parcel must agree with, each parcel in its own local frame.
#include <map>
#include <vector>

#include "cadastre/batch/batch_inputs.h"
#include "cadastre/clip.h"
#include "core/reconstruct/reconstruct.h"

namespace c3d {

// Beyond the overhang buffer, how far roof points reach for ownership to see
// the rest of a roof that crosses the boundary.
constexpr double kOwnershipContextM = 1.5;

// What the scenes of every chunk share, built once for the layer.
struct SceneGeometry {
  ClipParams roof_context, wall_reach;  // the chunks' clippers' buffers
  std::vector<std::vector<int>> neighbours;  // per parcel: parcels that may share a roof
  double overhang_buffer_m = 0;
  double reach_m = 0;  // how far outside a parcel its scene's points lie, at most
};
SceneGeometry scene_geometry(const ParcelLayer& layer, const ClipParams& clip);

// The scenes of the parcels whose points `points` holds (a chunk's region).
struct SceneSource {
  const LoadedInputs* inputs = nullptr;
  const RegionPoints* points = nullptr;
  const SceneGeometry* geometry = nullptr;
  LocalFrame frame;
  const Dtm* terrain = nullptr;  // the region's DTM window; nullptr: inputs->dtm
  std::map<CellIndex, int> density;  // the roof density of the blocks the region touches (DensityBlocks)
  ParcelClipper::IndexLists roof_lists, wall_lists;  // per parcel: indices into points
};

// The region's points to the parcels (of those within reach of `box`, the
// region's box, which holds every point).
SceneSource prepare_scenes(const LoadedInputs& inputs, const RegionPoints& points, const Box& box,
                           const SceneGeometry& geometry, const LocalFrame& frame);

// The frame a parcel is modelled in: the batch's, moved to the 10 m grid
// corner below the parcel. Its model then does not depend on which other
// parcels the batch holds: the primitive search and region growing turn on
// the last bits of local coordinates (a vault of the curved town was
// `suspect` or `ok` as its batch's frame moved).
LocalFrame parcel_frame(const Parcel& parcel, const LocalFrame& batch);

// The scene of one parcel, in its parcel_frame.
ParcelScene make_scene(const SceneSource& source, size_t parcel);

// A result modelled in `from`, moved into `to` (the frames differ in plan).
void move_result(ParcelResult& result, const LocalFrame& from, const LocalFrame& to);

}  // namespace c3d
