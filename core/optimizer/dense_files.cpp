#include "core/optimizer/dense_files.h"

#include <sstream>

#include "core/error.h"

namespace c3d {

DenseReport optimize_dense_files(const std::optional<std::string>& mesh_path,
                                 const std::string& cloud_path, const std::string& out_path,
                                 const DenseOptions& options) {
  std::vector<Vec3> pts = read_points(cloud_path);
  if (pts.empty()) throw InputError(cloud_path, "no points");
  const Vec3 origin = pts.front().array().floor().matrix();
  for (Vec3& p : pts) p -= origin;
  TriMesh mesh;
  if (mesh_path) {
    mesh = read_mesh(*mesh_path);
    for (Vec3& p : mesh.vertices) p -= origin;
  }
  DenseReport r = optimize_dense(mesh, pts, options);
  for (Vec3& p : mesh.vertices) p += origin;
  write_mesh_ply(out_path, mesh);
  return r;
}

std::string dense_report_text(const DenseReport& r, bool meshed_from_points, const std::string& out_path) {
  const auto& o = r.optimizer;
  std::ostringstream out;
  out << "device: " << o.device << "\n"
      << "points: " << r.input_points << " in, " << r.kept_points << " after filters (" << r.tiles << " tiles)\n"
      << "mesh: " << r.triangles << " triangles" << (meshed_from_points ? " (greedy projection)" : "") << ", "
      << r.constrained_triangles << " on " << r.planes << " RANSAC planes, " << o.junction_vertices
      << " junction vertices\n"
      << "energy: " << o.energy.front() << " -> " << o.energy.back() << "\n"
      << "mean point-to-mesh distance: " << r.deviation_before << " m -> " << r.deviation_after << " m\n"
      << "wrote " << out_path << " (" << o.seconds << " s optimizer)\n";
  return out.str();
}

}  // namespace c3d
