// cadastre3d merge --out OUT SHARD_STORE... [the batch's inputs]: the stores
// of `batch --shard K/N` into OUT/cadastre.gpkg and the batch's outputs; or
// --store URL, one store the shards wrote, its outputs (cadastre/batch/merge.h).
#include <iostream>
#include <memory>

#include "cadastre/batch/merge.h"
#include "cli/commands.h"
#include "cli/progress.h"
#include "core/error.h"
#include "ifc_citygml/export.h"

namespace c3d::cli {

void register_merge(CLI::App& app) {
  struct Args {
    std::vector<std::string> stores, formats{"gml", "cityjson", "ifc", "obj"};
    std::string out, store;
    bool overwrite = false, quiet = false;
    InputOptions in;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("merge", "Join the stores of `batch --shard K/N` into OUT and write the batch's outputs; "
                                          "with the batch's input options, the whole-run fit too");
  cmd->add_option("stores", a->stores, "The shards' stores (cadastre.gpkg), each shard once")->check(CLI::ExistingFile);
  cmd->add_option("--store", a->store, "Instead: one store every shard wrote (postgresql://...), nothing to merge")
      ->check(existing_store);
  cmd->add_option("--out", a->out, "Output directory")->required();
  cmd->add_option("--formats", a->formats, "Exports, a comma list: gml gml3 cityjson cityjsonseq ifc obj step 3dtiles")
      ->delimiter(',')->allow_extra_args(false)->check(CLI::IsMember(export_format_names()));
  cmd->add_flag("--overwrite", a->overwrite, "Replace what an earlier batch or merge wrote into OUT");
  cmd->add_flag("--quiet", a->quiet, "Print nothing but warnings and errors");
  add_input_options(cmd, a->in, false);
  cmd->callback([a] {
    if (a->stores.empty() == a->store.empty()) throw InputError("merge", "give the shards' stores or one --store");
    if (a->in.given() && (a->in.inputs.clouds.empty() || a->in.inputs.parcels.empty())) throw InputError("merge", "the batch's inputs need --cloud and --parcels");
    std::unique_ptr<RunInputs> inputs;
    if (a->in.given()) inputs.reset(new RunInputs{{}, input_config(a->in)}), inputs->inputs = a->in.inputs;
    Progress progress(a->quiet);
    const OutputProgress shown = [&](size_t done, size_t total) { progress.show("outputs", done, total); };
    const MergedRun m = a->store.empty() ? merge_run(a->stores, a->out, a->formats, a->overwrite, shown, inputs.get()) : finish_shared_store(a->store, a->out, a->formats, a->overwrite, shown, inputs.get());
    progress.done();
    const MergeSummary& s = m.merge;
    for (int k : s.missing_shards)
      std::cerr << "cadastre3d: warning: shard " << k << "/" << s.shard_count << " not given: its parcels are missing\n";
    if (!s.pending.empty())
      std::cerr << "cadastre3d: warning: " << s.pending.size() << " parcel(s) never written (first: " << s.pending[0]
                << "): rerun their shard with --resume, then merge again\n";
    const size_t* n = m.status_counts;
    if (!a->quiet)
      std::cout << "merge: " << s.shard_count - s.missing_shards.size() << " of " << s.shard_count << " shards, " << s.parcels
                << " parcels\nstore:   " << m.store << "\nsummary: " << m.written.summary << "\nreport:  " << m.written.report
                << "\nfit:     " << (m.fit_missing.empty() ? "computed" : "not computed: " + m.fit_missing) << "\nparcels: " << n[0]
                << " ok, " << n[1] << " empty, " << n[2] << " failed, " << n[3] << " suspect\n";
    exit_code() = !s.complete() || n[2] + n[3] > 0 ? kExitPartial : kExitOk;
  });
}

}  // namespace c3d::cli
