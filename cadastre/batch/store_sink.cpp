#include "cadastre/batch/store_sink.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "core/io/crs.h"

namespace c3d {

void StoreSink::begin(const BatchRun& run) {
  parcels_ = run.parcels;
  keys_ = run.parcel_keys;
  frame_ = run.frame;
  const auto dir = std::filesystem::path(path_).parent_path();
  if (!is_database_url(path_) && !dir.empty()) std::filesystem::create_directories(dir);
  store_exists(path_);  // refuses a file that is no store, leaving it as it is
  store_.open(path_, run.crs_wkt, epsg_of(run.crs_wkt));
  Store::Claim claim{run.parameters, run.shard, run.inputs, run.frame, {}, {}, !keep_other_runs_, {}, keys_};
  // Only the run's own parcels are pending: a shard's store says nothing of the others.
  for (size_t i : run.in_shard) claim.parcels.push_back((*parcels_)[i]), claim.keys.push_back(keys_[i]);
  // A shared database holds the parcels of other writers (shards) by
  // design: only this run's parcels count there.
  if (is_database_url(path_))
    for (const Parcel& p : *parcels_) claim.checked.push_back(p.id);
  run_id_ = store_.claim_run(claim);
}

bool StoreSink::has_parcel(size_t i, const std::string& key) {
  return store_.parcel_done((*parcels_)[i].id, key);
}

void StoreSink::write_parcel(size_t i, const ParcelResult& result, const ParcelValuation& valuation) {
  store_.write_parcel((*parcels_)[i], result, valuation, frame_, keys_[i]);
}

SinkCounts StoreSink::end() {
  store_.end_run(false);  // finished: mark_run_finished, once the outputs are in place
  store_.close();
  SinkCounts held;
  for (const JobRecord& j : load_jobs(path_)) {
    // One still pending (another writer's, in a shared store) is counted empty.
    ++held.parcels, ++held.by_status[size_t(j.status.value_or(ParcelStatus::Empty))];
  }
  return held;
}

// Read by the parcels' ids: a store shared with writers of other parcel
// selections holds their parcels under the same layer indices.
BatchModel StoreSink::models(const std::vector<int>& layer_indices) {
  return store_models(path_, *parcels_, layer_indices);
}

BatchModel store_models(const std::string& store, const std::vector<Parcel>& layer,
                        const std::vector<int>& layer_indices) {
  std::vector<int> sorted = layer_indices;
  std::sort(sorted.begin(), sorted.end());  // layer order
  std::vector<std::string> ids;
  for (int i : sorted)
    if (i >= 0 && size_t(i) < layer.size()) ids.push_back(layer[size_t(i)].id);
  return ids.empty() ? BatchModel{} : load_batch_model(store, ids);
}

}  // namespace c3d
