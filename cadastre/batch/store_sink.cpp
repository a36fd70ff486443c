#include "cadastre/batch/store_sink.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "core/io/crs.h"

namespace c3d {
namespace {

// Refuses a store holding a parcel this run would not write with the same key:
// another data set, other settings or other inputs. A rerun of the same run
// (or a killed one's leftovers) passes. A shared database holds the parcels
// of other writers (shards) by design: there only this run's parcels count.
void refuse_other_run(const std::string& path, const std::vector<std::string>& keys,
                      const std::vector<Parcel>& parcels) {
  const std::set<std::string> ours(keys.begin(), keys.end());
  std::set<std::string> ids;
  const bool shared = is_database_url(path);
  if (shared)
    for (const Parcel& p : parcels) ids.insert(p.id);
  size_t other = 0;
  for (const JobRecord& j : load_jobs(path))
    if (!shared || ids.count(j.parcel_id)) other += ours.count(j.inputs_key) == 0;
  if (other > 0)
    throw InputError(path, "holds " + std::to_string(other) +
                               " parcel(s) of another run (other inputs, settings or parcels); "
                               "--resume keeps them and adds this run's, --overwrite replaces "
                               "the folder's outputs, or choose another --out");
}

}  // namespace

void StoreSink::begin(const BatchRun& run) {
  parcels_ = run.parcels;
  keys_ = run.parcel_keys;
  frame_ = run.frame;
  const auto dir = std::filesystem::path(path_).parent_path();
  if (!is_database_url(path_) && !dir.empty()) std::filesystem::create_directories(dir);
  if (!keep_other_runs_ && store_exists(path_)) refuse_other_run(path_, keys_, *parcels_);
  store_.open(path_, run.crs_wkt, epsg_of(run.crs_wkt));
  run_id_ = store_.begin_run(run.parameters, run.inputs, run.frame, run.shard);
  // Only the run's own parcels are pending: a shard's store says nothing of the others.
  std::vector<Parcel> own;
  std::vector<std::string> own_keys;
  for (size_t i : run.in_shard) own.push_back((*parcels_)[i]), own_keys.push_back(keys_[i]);
  store_.mark_pending(own, own_keys);
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
