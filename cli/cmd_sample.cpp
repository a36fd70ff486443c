// cadastre3d sample: a synthetic town with exact ground truth (core/synthetic).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "core/synthetic/sample_summary.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {

namespace {

struct SampleArgs {
  std::string out;
  std::string format = "gpkg";
  SampleOptions opt;
  CloudLayout cloud;
};

void run_sample(const SampleArgs& a) {
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  SampleOptions opt = a.opt;
  if (opt.parcels >= 200)
    opt.progress = [](const char* stage, int done, int total) {
      std::cerr << "\r" << stage << " " << done << "/" << total << "   " << std::flush;
      if (done == total) std::cerr << "\n";
    };
  SampleTown town = make_sample_town(opt);
  auto t1 = clock::now();
  auto files = write_sample_town(town, a.out,
                                 a.format == "geojson" ? ParcelFormat::GeoJson : ParcelFormat::GeoPackage, a.cloud);
  // The exact buildings as the batch writes its models (truth_obj/<parcel>.obj), for `evaluate`.
  const auto truth_obj = (std::filesystem::path(a.out) / "truth_obj").string();
  write_obj_per_parcel(truth_model(town), truth_obj);
  auto t2 = clock::now();
  auto secs = [](auto d) { return std::chrono::duration<double>(d).count(); };
  std::cout << sample_town_text(town, files, truth_obj) << "  time      " << secs(t1 - t0) << " s generate, " << secs(t2 - t1) << " s write\n";
}

}  // namespace

void register_sample(CLI::App& app) {
  auto a = std::make_shared<SampleArgs>();
  auto* cmd = app.add_subcommand(
      "sample", "Generate a synthetic town with exact ground truth (parcels, DTM, LAS, truth.json)");
  cmd->add_option("--out", a->out, "Output directory (created when missing)")->required();
  cmd->add_option("--parcels", a->opt.parcels, "Number of parcels (blocks of 2 x 5)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--seed", a->opt.seed, "Random seed (same seed, same town)")->capture_default_str();
  cmd->add_option("--density", a->opt.roof_density, "Roof points per m2 (UAV)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--wall-density", a->opt.wall_density, "Wall points per m2 (handheld)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--noise", a->opt.roof_noise, "Roof point noise sigma, m")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--wall-noise", a->opt.wall_noise, "Wall point noise sigma, m")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  cmd->add_option("--outliers", a->opt.outlier_share, "Share of roof points that are outliers")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--clutter", a->opt.clutter_share, "Share of buildings with an antenna or a water tank")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--trees", a->opt.trees_per_parcel, "Trees per parcel on open land (class 5); 0: none")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 20.0));
  cmd->add_option("--sheds", a->opt.sheds_per_parcel,
                  "Garden sheds per parcel on open land (not in truth.json); 0: none")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 5.0));
  cmd->add_option("--occlusion", a->opt.wall_occlusion, "Share of exterior walls without points")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  CLI::Option* curved =
      cmd->add_flag("--curved", a->opt.curved, "Vaults, domes, cones (docs/curved.md) and a gable house");
  cmd->add_flag("--curved-plans", a->opt.curved_plans,
                "Flat roofs over round towers and apsed halls (docs/curved.md) and gable houses")
      ->excludes(curved);
  cmd->add_flag("--openings", a->opt.openings,
                "Recessed windows and doors in the scanned walls, their frames in truth.json (docs/meshes.md)");
  cmd->add_option("--format", a->format, "Parcel file format")
      ->capture_default_str()
      ->check(CLI::IsMember({"gpkg", "geojson"}));
  cmd->add_flag("--laz", a->cloud.laz, "Write the cloud LASzip-compressed (.laz)");
  cmd->add_option("--tiles", a->cloud.tile_size, "Cut the cloud into square tiles of this size, m (folder cloud/)")
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("--epsg", a->opt.epsg, "UTM EPSG code of the output")->capture_default_str();
  cmd->add_option("--easting", a->opt.origin_easting, "Easting of the town's south-west corner")
      ->capture_default_str();
  cmd->add_option("--northing", a->opt.origin_northing, "Northing of the town's south-west corner")
      ->capture_default_str();
  cmd->callback([a] {
    run_sample(*a);
    exit_code() = kExitOk;
  });
}

}  // namespace c3d::cli
