#pragma once
// A mesh ladder's files: a PLY and a binary glTF per level, and ladder.json with the spacing,
// the method and each level's figures (mesh_metrics.h).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mesh/ladder.h"

namespace c3d {

// Binary little-endian PLY: float32 vertices in the local frame (a building
// spans metres: float keeps them to a micrometre), int32 triangles, and the
// comment "world = local + (x, y, z)" as the OBJ files carry it.
void write_local_ply(const std::string& path, const TriMesh& mesh, const Vec3& offset);
// That PLY read back in world coordinates: its vertices plus the offset its
// header's comment gives (read_mesh, for any PLY, gives them local).
TriMesh read_local_ply(const std::string& path);

// The ladder's figures: spacing, method, level 4's trimmed faces, and per level
// faces, vertices, seconds, cloud-to-mesh mean / std / p95 / max,
// mesh-to-cloud, far share, closed, manifold, volume; levels 2 to 4 each
// planar region's shape, levels 2 and 3 their change (regions.h).
nlohmann::json ladder_json(const MeshLadder& ladder);

// A level's files' path without extension: <name>_level<k>.
std::string level_file_stem(const std::string& name, int level);

// DIR/<name>_level<k>.ply and .glb (a level without faces: no .glb) for
// k = 1..4 and DIR/<name>_ladder.json; returns the paths written. Throws InputError naming a file that cannot be written.
std::vector<std::string> write_ladder(const MeshLadder& ladder, const Vec3& offset, const std::string& dir,
                                      const std::string& name);

// `cadastre3d mesh`: the points of the files (LAS, LAZ, PLY, ...: one
// building's, a clip) in a local frame whose origin is the whole metres
// below their minimum, their ladder, and its files written as write_ladder
// does. Throws InputError naming an unreadable file, or the files when they
// hold fewer than 4 points, or points on a line or at one place.
struct MeshRun {
  MeshLadder ladder;
  Vec3 offset = Vec3::Zero();  // world = local + offset
  std::vector<std::string> files;
};
MeshRun mesh_point_files(const std::vector<std::string>& clouds, DenseMethod method, const std::string& dir,
                         const std::string& name, Simplifier simplifier = Simplifier::BoundaryAware);
// A table of the ladder's levels for the terminal.
std::string ladder_text(const MeshLadder& ladder);

}  // namespace c3d
