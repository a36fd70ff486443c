#pragma once
// Joins the GeoPackage stores of the shards of one batch (`batch --shard K/N`)
// into one store that equals an unsharded run's (docs/scale.md, "Sharding and
// Slurm"). Every row of every parcel is copied as it is (geometry blobs, the
// layer's own fields, GIS layers, valuations), with the row ids moved past the
// rows already merged. A PostgreSQL store needs no merge: shards write to it.
#include <string>
#include <vector>

#include "cadastre/batch/outputs.h"
#include "cadastre/batch/run_fit.h"

namespace c3d {

struct MergeSummary {
  int shard_count = 0;                // N of the shards' K/N
  std::vector<int> missing_shards;    // K of N not given
  std::vector<std::string> pending;   // parcels a shard marked but never wrote (a killed task not rerun)
  size_t parcels = 0;                 // parcels the merged store holds (written ones)
  std::string parameters;             // the shards' run parameters (JSON text)
  bool complete() const { return missing_shards.empty() && pending.empty(); }
};

// Merges `shards` into a new store at out_store (which must not exist). Refuses
// (InputError naming the file) a store that is no shard's, stores of other
// parameters, inputs, CRS or shard count, a shard given twice, and a parcel in
// two stores with different content (the same content is taken once).
MergeSummary merge_stores(const std::vector<std::string>& shards, const std::string& out_store);

struct MergedRun {
  MergeSummary merge;
  WrittenOutputs written;
  std::string store;
  size_t status_counts[4] = {0, 0, 0, 0};  // by ParcelStatus
  std::string fit_missing;  // why the whole-run fit is not in the summary; "" when it is
};

// `cadastre3d merge`: merge_stores into OUT/cadastre.gpkg, then the outputs a
// batch writes (write_outputs), under OUT's lock; --overwrite replaces what a
// batch or merge wrote into OUT before. The run is marked finished only when
// every shard and parcel is in. With the batch's inputs (and every shard in),
// the summary holds the whole-run fit (store_fit), as an unsharded run's;
// without, it says why it has none.
MergedRun merge_run(const std::vector<std::string>& shards, const std::string& out_dir,
                    const std::vector<std::string>& formats, bool overwrite, const OutputProgress& progress = {},
                    const RunInputs* inputs = nullptr);

// `cadastre3d merge --store URL`: a store every shard wrote (PostgreSQL)
// needs no merge; its outputs as merge_run writes them. Missing shards are
// those that never began a run in it.
MergedRun finish_shared_store(const std::string& store, const std::string& out_dir,
                              const std::vector<std::string>& formats, bool overwrite,
                              const OutputProgress& progress = {}, const RunInputs* inputs = nullptr);

}  // namespace c3d
