#pragma once
// `batch --mesh`: each modelled building's own points meshed at four levels
// (core/mesh), the files written beside the store, and the element model
// checked against the closed level (docs/meshes.md).
#include <string>
#include <vector>

#include "core/mesh/dense.h"
#include "core/mesh/simplify.h"
#include "core/reconstruct/scene/parcel_scene.h"
#include "core/types.h"

namespace c3d {

// Where the ladders go: OUT/mesh/<building>_level<k>.{ply,glb,svg} and
// <building>_ladder.json; the store records them relative to OUT.
struct MeshOutput {
  std::string out_dir;  // the batch's OUT
  DenseMethod method = DenseMethod::AdvancingFront;
  Simplifier simplifier = Simplifier::BoundaryAware;
};
constexpr char kMeshFolder[] = "mesh";

// The element model disagrees with the closed hull of its points by more than
// this share of its volume or roof area: the building is flagged for a look
// (docs/meshes.md: what the hull's own error allows).
constexpr double kMeshVolumeBound = 0.25, kMeshRoofAreaBound = 0.20;

// The points a building's mesh is made of: the scene's roof and wall points
// whose plan lies within their mean spacing of the building's roof plan or
// footprint, no lower than its terrain and no higher than its roof (beyond
// their noise): a taller neighbour's wall or eave is not its own.
std::vector<Vec3> building_points(const ParcelScene& scene, const Building& b);

// What closes the hull where no scan sees: the roof's plan (overhangs
// included) at the terrain, and its outline raised to the points above it
// (the curtain an airborne scan's missing walls leave open), sampled at `step`.
std::vector<Vec3> hull_closure(const Building& b, const std::vector<Vec3>& points, double step);

// Meshes every building of `r` (modelled in `frame`, the scene's), writes
// the files and fills each building's `mesh`; a building that cannot be
// meshed gets its `problem` and the others go on. Files that cannot be
// written throw InputError naming them (the batch stops: the disk is full).
void mesh_buildings(const ParcelScene& scene, const LocalFrame& frame, const MeshOutput& out, ParcelResult& r);

// `merge`: the mesh files of each shard (the `mesh` folder beside its
// store) into OUT/mesh, where the merged store's paths point; linked where
// the file system allows, else copied. Throws InputError naming a file that
// cannot be placed.
void gather_mesh_files(const std::vector<std::string>& shard_stores, const std::string& out_dir);

}  // namespace c3d
