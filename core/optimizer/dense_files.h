#pragma once
// `cadastre3d optimize` on files: a mesh refined against a point cloud with the
// dense path (mesh_dense.h), read and written in world coordinates.
#include <optional>
#include <string>

#include "core/optimizer/mesh_dense.h"

namespace c3d {

// Reads the cloud (PLY points) and the mesh (PLY/OBJ; none: the cloud is meshed),
// refines the mesh and writes it to out_path as PLY. Works in a local origin,
// the cloud's first point floored, so that the float kernels stay precise.
// Throws InputError on a cloud without points.
DenseReport optimize_dense_files(const std::optional<std::string>& mesh_path,
                                 const std::string& cloud_path, const std::string& out_path,
                                 const DenseOptions& options);

// The lines `optimize` prints: device, points, mesh, energy, distance, output.
std::string dense_report_text(const DenseReport& report, bool meshed_from_points, const std::string& out_path);

}  // namespace c3d
