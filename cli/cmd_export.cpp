// cadastre3d export --store OUT/cadastre.gpkg --out DIR [--formats gml,cityjson,ifc,obj,step]
// Reads the model from a store (or a CityJSON file this tool wrote) and writes the
// requested exchange formats.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cadastre/batch/out_dir.h"
#include "cadastre/batch/outputs.h"
#include "cadastre/store/pages.h"
#include "cadastre/store/store.h"
#include "cli/commands.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {
namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item == "citygml" ? "gml" : item);
  return out;
}

}  // namespace

void register_export(CLI::App& app) {
  struct Args {
    std::string store, out, formats = "gml,cityjson,ifc,obj,step";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "export", "Write CityGML 2.0 (or 3.0), CityJSON 2.0, IFC4, OBJ and STEP from a store");
  cmd->add_option("--store", args->store, "Cadastre3D store (.gpkg or postgresql://...) or a CityJSON file")
      ->required()
      ->check(existing_store);
  cmd->add_option("--out", args->out, "Output directory")->required();
  cmd->add_option("--formats", args->formats, "Comma-separated: gml,gml3,cityjson,cityjsonseq,ifc,obj,step,3dtiles")
      ->check([](const std::string& s) {
        const auto& names = export_format_names();
        for (const auto& f : split(s))
          if (std::find(names.begin(), names.end(), f) == names.end())
            return "unknown format '" + f + "'";
        return std::string();
      });
  cmd->callback([args] {
    const std::vector<std::string> formats = split(args->formats);
    std::vector<PagesExport> done;
    size_t buildings = 0;
    write_staged_into(args->out, [&](const std::string& stage) {
      done = export_store(args->store, stage, formats, buildings);
      for (auto& e : done)
        for (auto& f : e.files) f = moved(f, stage, args->out);
    }, {"obj", "step"});
    for (const auto& e : done) {
      for (const auto& w : e.skipped) std::cerr << "export " << e.format << ": skipped " << w << "\n";
      std::cout << "export " << e.format << ": " << e.files.size() << " file(s), " << buildings
                << " buildings, " << e.seconds << " s"
                << (e.files.size() == 1 ? " -> " + e.files[0] : "") << "\n";
    }
    exit_code() = kExitOk;
  });
}

}  // namespace c3d::cli
