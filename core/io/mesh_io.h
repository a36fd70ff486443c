#pragma once
// Polygon meshes in and out: OBJ (groups, materials) and PLY (ASCII and binary)
// in, OBJ out. Coordinates are kept in double as written (world or local).
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

// Faces sharing a label: OBJ "g"/"o" name and "usemtl" material; PLY: one group.
struct MeshGroup {
  std::string name;
  std::string material;
  std::vector<Face> faces;
};

// A file name's extension after its last dot, lower case ("" without one).
std::string lower_ext(const std::string& path);

// Reads .obj or .ply (by extension). Every polygon becomes one Face (no holes);
// consecutive faces with the same (name, material) share a group. An OBJ comment
// "world = local + (x, y, z)" (as write_obj and the exporters write it) is
// added to the vertices after it: faces come back in world coordinates. Throws
// InputError naming the file on unreadable or malformed input.
std::vector<MeshGroup> read_mesh_groups(const std::string& path);
// All faces of all groups.
std::vector<Face> read_mesh_faces(const std::string& path);

// Writes OBJ with one "g" (and "usemtl" when set) per group; vertices are written
// once each, as vertex - offset with 6 decimals (micrometres), and a non-zero
// offset is recorded as "# coordinates local: world = local + (x, y, z)". Faces
// with holes are written as their triangles, since OBJ has no holes.
void write_obj(const std::string& path, const std::vector<MeshGroup>& groups,
               const Vec3& offset = Vec3::Zero());

}  // namespace c3d
