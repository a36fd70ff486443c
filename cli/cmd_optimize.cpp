// cadastre3d optimize MESH CLOUD: dense mesh refinement against a point cloud
// with the primitive-constrained optimizer (Vulkan, or the CPU reference).
#include <iostream>

#include "cli/commands.h"
#include "core/error.h"
#include "core/optimizer/mesh_dense.h"

namespace c3d::cli {

namespace {

struct OptimizeArgs {
  std::string mesh, cloud, out = "optimized.ply", device = "auto";
  DenseOptions dense;
};

// Local origin: the cloud's first point, floored, so float kernels stay precise.
void run_optimize(OptimizeArgs& a) {
  a.dense.optimizer.device = parse_compute_device(a.device);
  a.dense.optimizer.threads = 0;
  std::vector<Vec3> pts = read_points(a.cloud);
  if (pts.empty()) throw InputError(a.cloud, "no points");
  const Vec3 origin = pts.front().array().floor().matrix();
  for (Vec3& p : pts) p -= origin;
  TriMesh mesh;
  if (a.mesh != "-") {
    mesh = read_mesh(a.mesh);
    for (Vec3& p : mesh.vertices) p -= origin;
  }
  DenseReport r = optimize_dense(mesh, pts, a.dense);
  for (Vec3& p : mesh.vertices) p += origin;
  write_mesh_ply(a.out, mesh);
  const auto& o = r.optimizer;
  std::cout << "device: " << o.device << "\n"
            << "points: " << r.input_points << " in, " << r.kept_points << " after filters ("
            << r.tiles << " tiles)\n"
            << "mesh: " << r.triangles << " triangles" << (a.mesh == "-" ? " (greedy projection)" : "")
            << ", " << r.constrained_triangles << " on " << r.planes << " RANSAC planes, "
            << o.junction_vertices << " junction vertices\n"
            << "energy: " << o.energy.front() << " -> " << o.energy.back() << "\n"
            << "mean point-to-mesh distance: " << r.deviation_before << " m -> " << r.deviation_after
            << " m\n"
            << "wrote " << a.out << " (" << o.seconds << " s optimizer)\n";
}

}  // namespace

void register_optimize(CLI::App& app) {
  auto a = std::make_shared<OptimizeArgs>();
  auto* cmd = app.add_subcommand("optimize", "refine a dense mesh with the primitive-constrained optimizer");
  cmd->add_option("MESH", a->mesh, "PLY/OBJ mesh, or - to mesh the cloud (greedy projection)")->required();
  cmd->add_option("CLOUD", a->cloud, "PLY point cloud")->required();
  cmd->add_option("--out", a->out, "output PLY mesh");
  cmd->add_option("--device", a->device, "cpu | vulkan | auto (discrete GPU, else lavapipe, else CPU)");
  cmd->add_option("--voxel", a->dense.voxel_m, "voxel size for down-sampling, m (0: off)");
  cmd->add_option("--tile", a->dense.tile_m, "preprocessing tile size, m");
  cmd->add_option("--ransac-threshold", a->dense.ransac_threshold_m, "RANSAC plane inlier distance, m");
  cmd->callback([a] {
    try {
      run_optimize(*a);
    } catch (const std::exception& e) {
      std::cerr << "cadastre3d optimize: " << e.what() << "\n";
      exit_code() = kExitError;
    }
  });
}

}  // namespace c3d::cli
