// cadastre3d batch: the main job. The batch itself is the library's
// run_batch (cadastre/batch); this file parses the options and prints.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <thread>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/out_dir.h"
#include "cadastre/batch/outputs.h"
#include "cadastre/batch/tile_extents.h"
#include "cadastre/batch/store_sink.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "core/log.h"
#include "ifc_citygml/export.h"

namespace fs = std::filesystem;

namespace c3d::cli {
namespace {

struct BatchOptions {
  InputOptions in;
  std::string out;
  std::string store;   // --store: a GeoPackage path or postgresql://... (default OUT/cadastre.gpkg)
  std::vector<std::string> formats{"gml", "cityjson", "ifc", "obj"};
  BatchSettings settings;
  bool quiet = false;
  bool overwrite = false;                  // replace what a batch wrote into OUT before
  std::string shard;                       // --shard K/N; a shard writes its store only
};

void print_outputs(const WrittenOutputs& w, const std::string& store_path) {
  std::cout << "summary: " << w.summary << "\n"
            << "store:   " << store_path << "\n"
            << "report:  " << w.report << "\n"
            << "preview: " << w.preview_dir << "/<parcel>.svg\n";
  std::set<std::string> dirs;  // OBJ and STEP: one line per folder, not per file
  for (const auto& f : w.exports) {
    std::string parent = fs::path(f).parent_path().filename().string();
    if (parent == "obj" || parent == "step") dirs.insert(fs::path(f).parent_path().string());
    else std::cout << "export:  " << f << "\n";
  }
  for (const auto& d : dirs) std::cout << "export:  " << d << "/\n";
}

void print_timings(const BatchReport& r, double total_s, const std::string& out) {
  const BatchTimings& t = r.timings;
  std::cout << "batch: " << r.parcels << " parcels";
  if (r.held != r.parcels) std::cout << "; the store holds " << r.held;  // --resume
  std::cout << " in " << total_s << " s; outputs in " << out << "\n";
  std::printf("timing: ingest+clip %.3f s, reconstruction %.3f s, store writes %.3f s, "
              "summary+report+exports %.3f s, total %.3f s\n",
              t.ingest_s, t.reconstruct_s - t.sink_s, t.sink_s, total_s - t.ingest_s - t.reconstruct_s,
              total_s);
}

// The last line: every parcel's status as the store holds it. Failed or
// suspect parcels exit kExitPartial (docs/plausibility.md).
int print_counts(const BatchReport& report, bool quiet) {
  const auto& n = report.held_by_status;
  const size_t ok = n[size_t(ParcelStatus::Ok)], empty = n[size_t(ParcelStatus::Empty)];
  const size_t failed = n[size_t(ParcelStatus::Failed)], suspect = n[size_t(ParcelStatus::Suspect)];
  const std::string line = "parcels: " + std::to_string(ok) + " ok, " + std::to_string(empty) + " empty, " +
                           std::to_string(failed) + " failed, " + std::to_string(suspect) + " suspect";
  if (!quiet) std::cout << line << "\n";
  else if (failed + suspect > 0) std::cerr << line << "\n";  // --quiet still says so
  return failed + suspect > 0 ? kExitPartial : kExitOk;
}

// Test hook of the tests' build only (tests/slurm_shards_check.sh):
// C3D_TEST_PAUSE_SHARD="K/N:M" holds shard K/N a minute after its M-th parcel
// is stored, for the test to kill it midway.
void test_pause([[maybe_unused]] const Shard& shard, [[maybe_unused]] const char* stage,
                [[maybe_unused]] size_t done) {
#ifdef C3D_TEST_HOOKS
  const char* hook = std::getenv("C3D_TEST_PAUSE_SHARD");
  const bool named = hook && shard.active() && hook == to_string(shard) + ":" + std::to_string(done);
  if (named && std::string(stage) == "reconstruct") std::this_thread::sleep_for(std::chrono::minutes(1));
#endif
}

// A shard writes its store only: a report of part of the layer would mislead;
// `cadastre3d merge` writes the outputs of all shards (docs/scale.md).
int finish_shard(const BatchReport& report, const StoreSink& sink, const BatchOptions& opt, Progress& progress) {
  progress.done();
  mark_run_finished(sink.path(), sink.run_id());
  if (!opt.quiet)
    std::cout << "shard " << to_string(opt.settings.shard) << ": " << report.held << " of " << report.parcels
              << " parcels in " << sink.path() << "; `cadastre3d merge` writes the report\n";
  return print_counts(report, opt.quiet);
}

int run(BatchOptions opt) {
  const auto t_start = std::chrono::steady_clock::now();
  if (opt.quiet) log::set_level(log::Level::Warn);
  if (!opt.shard.empty()) opt.settings.shard = parse_shard(opt.shard);
  const Config cfg = input_config(opt.in);
  fs::create_directories(opt.out);
  const OutDirLock lock(opt.out);  // one batch per OUT at a time
  if (opt.overwrite) remove_batch_outputs(opt.out);
  const std::string store_path = opt.store.empty() ? (fs::path(opt.out) / "cadastre.gpkg").string() : opt.store;
  StoreSink sink(store_path, opt.settings.resume);
  opt.settings.out_dir = opt.out;
  Progress progress(opt.quiet);
  opt.settings.progress = [&](const char* stage, size_t done, size_t total) {
    progress.show(stage, done, total);
    test_pause(opt.settings.shard, stage, done);
  };
  const BatchReport report = run_batch(opt.in.inputs, cfg, sink, opt.settings);
  if (opt.settings.shard.active()) return finish_shard(report, sink, opt, progress);
  const WrittenOutputs written = write_outputs(report, store_path, opt.out, cfg, opt.formats,
                                               [&](size_t done, size_t total) { progress.show("outputs", done, total); });
  progress.done();
  mark_run_finished(store_path, sink.run_id());  // last: a finished run has every output in place
  if (!opt.quiet) {
    print_outputs(written, store_path);
    print_timings(report, std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count(), opt.out);
  }
  return print_counts(report, opt.quiet);
}

}  // namespace

Config input_config(InputOptions& o) {
  Config cfg = o.config.empty() ? default_config() : load_config(o.config);
  cfg.reconstruction.optimize = cfg.reconstruction.optimize || o.optimize;
  cfg.mesh.ladder = cfg.mesh.ladder || o.mesh;
  if (!o.device.empty()) cfg.reconstruction.optimize_device = o.device;
  if (!o.id_field.empty()) cfg.fields.id = o.id_field, cfg.fields.id_required = true;
  if (o.classify) o.inputs.classifier_model = o.model;
  o.inputs.tile_index = tile_index_path(std::getenv("XDG_CACHE_HOME"), std::getenv("HOME"));
  return cfg;
}

void add_input_options(CLI::App* cmd, InputOptions& o, bool required) {
  const size_t before = cmd->get_options().size();
  cmd->add_option("--cloud", o.inputs.clouds,
                  "Classified point cloud(s): LAS, LAZ, PLY, PCD, XYZ/CSV files, folders of them or globs "
                  "('tiles/*.laz'): the tiles of one cloud")
      ->required(required);
  cmd->add_option("--walls", o.inputs.walls,
                  "Wall-only point cloud(s) from a terrestrial scanner: files, folders or globs");
  cmd->add_option("--parcels", o.inputs.parcels,
                  "Parcel layer: any OGR vector source, a file, folder or connection string (PG:..., /vsizip/...)")
      ->required(required);
  cmd->add_option("--layer", o.inputs.parcel_selection.layer, "The parcels' layer in a source with several");
  cmd->add_option("--where", o.inputs.parcel_selection.where, "Only parcels matching this OGR SQL filter");
  cmd->add_option("--bbox", o.inputs.parcel_selection.bbox,
                  "Only parcels meeting xmin,ymin,xmax,ymax, in the parcel layer's own CRS")
      ->delimiter(',')
      ->expected(4);
  cmd->add_option("--id-field", o.id_field, "Parcel id field (default: the config's [parcel_fields] id)");
  cmd->add_option("--crs", o.inputs.crs,
                  "Working CRS for areas, e.g. EPSG:32748 (default: chosen as docs/inputs.md says)");
  cmd->add_option("--dtm", o.inputs.dtm, "Terrain model (any GDAL raster); default: from ground points")
      ->check(CLI::ExistingFile);
  cmd->add_option("--config", o.config, "TOML config (default: built-in, see config/)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--optimize", o.optimize, "Refine element geometry with the GPU optimizer");
  cmd->add_option("--device", o.device, "Optimizer device: auto, cpu or vulkan")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  cmd->add_flag("--mesh", o.mesh,
                "Mesh each building's points at four levels of detail into OUT/mesh and check the model "
                "against them (config [mesh]; docs/meshes.md)");
  cmd->add_flag("--classify", o.classify,
                "Classify the clouds first (ground/roof/wall/other, Random Forest), replacing their classes");
  cmd->add_option("--model", o.model, "Classifier model for --classify")->capture_default_str();
  const std::vector<CLI::Option*> all = cmd->get_options();
  for (size_t k = before; k < all.size(); ++k) all[k]->group(kInputGroup);
}

void register_batch(CLI::App& app, bool parse_only) {
  auto opt = std::make_shared<BatchOptions>();
  auto* cmd = app.add_subcommand(
      "batch",
      "Parcel batch: point clouds + parcels + DTM -> LoD2 element models, cadastre.gpkg, "
      "summary.json, report.html/.csv, CityGML/CityJSON/IFC/OBJ");
  add_input_options(cmd, opt->in, true);
  cmd->add_option("--out", opt->out, "Output directory")->required();
  cmd->add_option("--store", opt->store,
                  "Store: a GeoPackage path or a PostGIS database, postgresql://user@host:port/db "
                  "(default OUT/cadastre.gpkg; docs/postgis.md)");
  cmd->add_option("--jobs", opt->settings.jobs, "Parallel parcels (default: all cores; at most 4 per core)")
      ->check(CLI::Range(1, 1 << 20));  // 0 and negatives are errors; many: clamped with a warning
  cmd->add_option("--formats", opt->formats, "Exports: gml (CityGML 2.0) gml3 (CityGML 3.0) cityjson cityjsonseq ifc obj step 3dtiles")
      ->delimiter(',')
      ->check(CLI::IsMember(export_format_names()));
  auto* resume = cmd->add_flag("--resume", opt->settings.resume,
                               "Skip parcels already stored from the same inputs and settings; keep a "
                               "store of another run in OUT and add this run's parcels");
  cmd->add_flag("--overwrite", opt->overwrite,
                "Replace what an earlier batch wrote into OUT (store, report, exports, previews)")
      ->excludes(resume);
  cmd->add_option("--shard", opt->shard, "Model and store only shard K of N (K/N, spatial parts of the whole "
                  "layer); writes the store only, `merge` joins the shards (docs/scale.md)")
      ->check(CLI::Validator([](std::string& text) { return shard_problem(text); }, "K/N"));  // usage: exit 2
  cmd->add_flag("--quiet", opt->quiet, "Print nothing but warnings and errors");
  cmd->callback([opt, parse_only] {
    if (!parse_only) exit_code() = run(*opt);
  });
}

}  // namespace c3d::cli
