// cadastre3d export --store OUT/cadastre.gpkg --out DIR [--formats gml,cityjson,ifc,obj,step]
// Reads the model from a store (or a CityJSON file this tool wrote) and writes the
// requested exchange formats.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cadastre/store/pages.h"
#include "cadastre/store/store.h"
#include "cli/commands.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {
namespace {

bool is_cityjson(const std::string& path) {
  return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

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
  cmd->add_option("--formats", args->formats, "Comma-separated: gml,gml3,cityjson,cityjsonseq,ifc,obj,step")
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
    if (is_cityjson(args->store)) {  // a file this tool wrote: small enough to read whole
      BatchModel model = read_cityjson(args->store);
      for (const auto& r : model.results) buildings += r.buildings.size();
      for (const auto& f : formats) {
        auto t0 = std::chrono::steady_clock::now();
        PagesExport e{f};
        e.files = export_formats(model, args->out, {f}, &e.skipped);
        e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        done.push_back(std::move(e));
      }
    } else {  // a store, a page of parcels at a time
      done = export_pages(StorePages(args->store), args->out, formats, &buildings);
    }
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
