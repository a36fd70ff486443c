// cadastre3d optimize MESH CLOUD: dense mesh refinement against a point cloud
// with the primitive-constrained optimizer (Vulkan, or the CPU reference);
// core/optimizer/dense_files.h does the work.
#include <iostream>

#include "cli/commands.h"
#include "core/optimizer/dense_files.h"

namespace c3d::cli {

namespace {

struct OptimizeArgs {
  std::string mesh, cloud, out = "optimized.ply", device = "auto";
  DenseOptions dense;
};

void run_optimize(OptimizeArgs& a) {
  a.dense.optimizer.device = parse_compute_device(a.device);
  a.dense.optimizer.threads = 0;
  const bool meshed_from_points = a.mesh == "-";
  const auto mesh = meshed_from_points ? std::nullopt : std::optional<std::string>(a.mesh);
  const DenseReport r = optimize_dense_files(mesh, a.cloud, a.out, a.dense);
  std::cout << dense_report_text(r, meshed_from_points, a.out);
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
