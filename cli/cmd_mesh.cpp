// cadastre3d mesh: a building's points as a mesh at four levels of detail
// (core/mesh, docs/meshes.md); core/mesh/mesh_files.h does the work.
#include <iostream>

#include "cli/commands.h"
#include "core/mesh/mesh_files.h"

namespace c3d::cli {

void register_mesh(CLI::App& app) {
  struct Args {
    std::vector<std::string> clouds;
    std::string out, name = "building", method = "front", simplify = "boundary";
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("mesh", "Mesh one building's points at four levels of detail (PLY, ladder.json)");
  cmd->add_option("--cloud", a->clouds, "The building's points: LAS, LAZ, PLY, PCD or XYZ files")->required();
  cmd->add_option("--out", a->out, "Output folder (created when missing)")->required();
  cmd->add_option("--name", a->name, "File name stem")->capture_default_str();
  cmd->add_option("--method", a->method, "Dense level: pivot, front, poisson or alpha")
      ->capture_default_str()
      ->check(CLI::IsMember({"pivot", "front", "poisson", "alpha"}));
  cmd->add_option("--simplify", a->simplify,
                  "Levels 3 and 2: boundary (boundary-aware, by regions), or for comparison qem (Lindstrom-Turk), "
                  "garland (Garland-Heckbert) or clustering (vertex clustering)")
      ->capture_default_str()
      ->check(CLI::IsMember({"boundary", "qem", "garland", "clustering"}));
  cmd->callback([a] {
    const MeshRun run =
        mesh_point_files(a->clouds, dense_method_named(a->method), a->out, a->name, simplifier_named(a->simplify));
    std::cout << ladder_text(run.ladder);
    for (const std::string& f : run.files) std::cout << "wrote " << f << "\n";
  });
}

}  // namespace c3d::cli
