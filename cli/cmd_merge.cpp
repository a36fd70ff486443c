// cadastre3d merge --out OUT SHARD_STORE...: joins the stores of `batch --shard
// K/N` into OUT/cadastre.gpkg (cadastre/batch/merge.h), then writes the
// outputs a batch writes (summary, report, previews, exports) from it.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cadastre/batch/merge.h"
#include "cadastre/batch/out_dir.h"
#include "cadastre/batch/outputs.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "cadastre/store.h"
#include "core/error.h"
#include "ifc_citygml/export.h"

namespace fs = std::filesystem;

namespace c3d::cli {
namespace {

struct MergeArgs {
  std::vector<std::string> stores;
  std::string out;
  std::vector<std::string> formats{"gml", "cityjson", "ifc", "obj"};
  bool overwrite = false, quiet = false;
};

// What the merged store lacks, one warning line each.
void warn_incomplete(const MergeSummary& s) {
  if (!s.missing_shards.empty()) {
    std::string ks;
    for (int k : s.missing_shards) ks += (ks.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(s.shard_count);
    std::cerr << "cadastre3d: warning: shard(s) " << ks << " not given: their parcels are missing\n";
  }
  if (!s.pending.empty())
    std::cerr << "cadastre3d: warning: " << s.pending.size() << " parcel(s) never written (first: " << s.pending[0]
              << "): rerun their shard's task with --resume, then merge again\n";
}

int run(const MergeArgs& a) {
  fs::create_directories(a.out);
  const OutDirLock lock(a.out);
  if (a.overwrite) remove_batch_outputs(a.out);
  const std::string store_path = (fs::path(a.out) / "cadastre.gpkg").string();
  if (fs::exists(store_path)) throw InputError(store_path, "exists already; --overwrite replaces it");
  const MergeSummary sum = merge_stores(a.stores, store_path);
  BatchReport report;  // the counts and model as the merged store holds them
  report.model = load_batch_model(store_path);
  report.parcels = report.reconstructed = report.model.parcels.size();
  size_t n[4] = {0, 0, 0, 0};
  for (const auto& r : report.model.results) ++n[size_t(r.status)];
  report.failed = n[size_t(ParcelStatus::Failed)];
  report.suspect = n[size_t(ParcelStatus::Suspect)];
  Progress progress(a.quiet);
  const WrittenOutputs w = write_outputs(report, store_path, a.out, default_config(), a.formats,
                                         [&](size_t done, size_t total) { progress.show("outputs", done, total); });
  progress.done();
  warn_incomplete(sum);
  if (sum.complete()) mark_run_finished(store_path);  // a finished run: every parcel and output in place
  if (!a.quiet)
    std::cout << "merge: " << a.stores.size() << " of " << sum.shard_count << " shards, " << sum.parcels
              << " parcels\nstore:   " << store_path << "\nsummary: " << w.summary << "\nreport:  " << w.report
              << "\nparcels: " << n[size_t(ParcelStatus::Ok)] << " ok, " << n[size_t(ParcelStatus::Empty)] << " empty, "
              << report.failed << " failed, " << report.suspect << " suspect\n";
  return !sum.complete() || report.failed + report.suspect > 0 ? kExitPartial : kExitOk;
}

}  // namespace

void register_merge(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  auto* cmd = app.add_subcommand(
      "merge", "Join the stores of `batch --shard K/N` into OUT/cadastre.gpkg and write the batch's outputs");
  cmd->add_option("stores", a->stores, "The shards' stores (OUT_K/cadastre.gpkg), each shard once")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", a->out, "Output directory")->required();
  cmd->add_option("--formats", a->formats, "Exports, a comma list: gml gml3 cityjson cityjsonseq ifc obj step")
      ->delimiter(',')
      ->allow_extra_args(false)  // the stores follow
      ->check(CLI::IsMember(export_format_names()));
  cmd->add_flag("--overwrite", a->overwrite, "Replace what an earlier batch or merge wrote into OUT");
  cmd->add_flag("--quiet", a->quiet, "Print nothing but warnings and errors");
  cmd->callback([a] { exit_code() = run(*a); });
}

}  // namespace c3d::cli
