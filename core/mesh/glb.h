#pragma once
// A mesh as binary glTF 2.0 (.glb), written from the public specification
// (Khronos, glTF 2.0, "GLB File Format Specification"): one node, one
// triangle primitive, float32 positions in the local frame, uint32 indices.
// glTF's up is +Y; the node turns the building's +Z up onto it, so the
// positions keep the frame the PLY and the store use. The local frame's
// world offset is recorded in the scene's extras (`world_offset`), as the
// OBJ files record it in a comment.
#include <string>
#include <vector>

#include "core/mesh/tri_mesh.h"

namespace c3d {

// glTF's codes for what the writers use: accessor component types, buffer
// view targets, the triangle primitive mode.
namespace gltf {
inline constexpr int kFloat = 5126, kUnsignedInt = 5125;
inline constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
inline constexpr int kTriangles = 4;
}  // namespace gltf

// A GLB file of a glTF JSON text and its binary chunk, each padded to 4 bytes.
std::vector<unsigned char> glb_container(const std::string& json, std::vector<unsigned char> bin);
// The file's bytes; `name` names the node and the mesh.
std::vector<unsigned char> glb_bytes(const TriMesh& mesh, const Vec3& offset, const std::string& name);
// Throws InputError naming the path when it cannot be written.
void write_glb(const std::string& path, const TriMesh& mesh, const Vec3& offset, const std::string& name);

}  // namespace c3d
