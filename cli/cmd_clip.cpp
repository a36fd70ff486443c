// cadastre3d clip: how many points each parcel gets (inside, in the overhang
// buffer, roof/wall classes) - the check before a batch (cadastre/inspect).
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cadastre/clip.h"
#include "cadastre/inspect/clip_counts.h"
#include "cadastre/inspect/parcel_inputs.h"
#include "cli/commands.h"

namespace c3d::cli {
namespace {

struct ClipOptions {
  std::vector<std::string> clouds;
  std::string parcels, id_field, csv;
  double buffer = ClipParams{}.overhang_buffer_m;
};

void run_clip(const ClipOptions& o) {
  const ParcelInputs in = read_parcel_inputs(o.parcels, o.id_field, o.clouds);
  for (const std::string& w : in.warnings) std::cerr << "cadastre3d: warning: " << w << "\n";
  const ClipCounts counts = count_points_per_parcel(in.layer, in.clouds, o.buffer);
  std::fputs(clip_table(in.layer, counts).c_str(), stdout);
  if (!o.csv.empty()) write_clip_csv(o.csv, in.layer, counts);
}

}  // namespace

void register_clip(CLI::App& app) {
  auto o = std::make_shared<ClipOptions>();
  auto* cmd = app.add_subcommand(
      "clip", "Clip point clouds to the parcels (with the overhang buffer) and count the points "
              "per parcel");
  cmd->add_option("--cloud", o->clouds, "point clouds (LAS/PLY/PCD/XYZ), one or more")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--parcels", o->parcels, "parcel layer (any OGR vector source)")->required();
  cmd->add_option("--buffer", o->buffer, "overhang buffer around each parcel, m")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--id-field", o->id_field,
                  "parcel id field (default: as the batch, NIB where the layer has it, else the feature id)");
  cmd->add_option("--csv", o->csv, "also write the table as CSV");
  cmd->callback([o] {
    try {
      run_clip(*o);
    } catch (const std::exception& e) {
      std::cerr << "cadastre3d: error: " << e.what() << "\n";
      exit_code() = kExitError;
    }
  });
}

}  // namespace c3d::cli
