// cadastre3d validate FILE: geometry validation (val3dity rules and codes) of every
// building of a CityJSON file or a Cadastre3D store (a GeoPackage or a
// postgresql:// URL). Exit 0 when all are valid, 1 when any issue is found
// (one line per issue).
#include <iostream>
#include <string>

#include "cadastre/store/store.h"
#include "cli/commands.h"
#include "ifc_citygml/export.h"
#include "ifc_citygml/validate.h"

namespace c3d::cli {

void register_validate(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto planarity = std::make_shared<double>(0.01);
  auto* cmd = app.add_subcommand(
      "validate", "Check building solids (closed, manifold, oriented, planar; val3dity codes)");
  cmd->add_option("file", *file, "CityJSON file (.city.json / .json) or store (.gpkg or postgresql://...)")
      ->required()
      ->check(existing_store);
  cmd->add_option("--planarity", *planarity, "Planarity tolerance in metres (default 0.01)");
  cmd->callback([file, planarity] {
    const std::string& f = *file;
    bool json = f.size() >= 5 && f.compare(f.size() - 5, 5, ".json") == 0;
    BatchModel model = json ? read_cityjson(f) : load_batch_model(f);
    ValidationOptions opt;
    opt.planarity_tol = *planarity;
    size_t buildings = 0;
    for (const auto& r : model.results) buildings += r.buildings.size();
    auto issues = validate_model(model, opt);
    for (const auto& i : issues) std::cout << to_string(i) << "\n";
    std::cout << "validate: " << buildings << " buildings, " << issues.size() << " issue(s)\n";
    exit_code() = issues.empty() ? kExitOk : kExitError;
  });
}

}  // namespace c3d::cli
