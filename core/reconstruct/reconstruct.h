#pragma once
// One parcel from points to buildings of elements: segment -> own (decided
// once into an Ownership the later steps query) -> plan the buildings (outline)
// -> per plan on a work list: partition -> envelope -> measure (a plan whose
// footprint comes apart is replaced by its houses) -> a building still invalid
// modelled again on the hull's axes, else as its LoD 1.2 prism (lod12.h) ->
// evaluate. Everything in local coordinates.
#include "core/config/config.h"
#include "core/reconstruct/scene/parcel_scene.h"
#include "core/types.h"

namespace c3d {

// Never throws: a parcel that cannot be modelled comes back `failed` with a reason.
ParcelResult reconstruct_parcel(const ParcelScene& scene, const ReconstructionParams& p);

}  // namespace c3d
