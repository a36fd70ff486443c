#include "cadastre/batch/run_fit.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include <set>

#include "cadastre/batch/batch_deviation.h"
#include "cadastre/batch/batch_inputs.h"
#include "cadastre/batch/resume_key.h"
#include "cadastre/batch/shard.h"
#include "cadastre/batch/store_sink.h"
#include "cadastre/store/store.h"
#include "core/error.h"

namespace c3d {
namespace {

using nlohmann::json;

std::string first_difference(const json& a, const json& b, const std::string& at) {
  if (!a.is_object() || !b.is_object())
    return a == b ? "" : at + ": " + a.dump() + " here, " + b.dump() + " in the store's run";
  std::set<std::string> keys;
  for (const auto& [k, v] : a.items()) keys.insert(k);
  for (const auto& [k, v] : b.items()) keys.insert(k);
  for (const std::string& k : keys) {
    const std::string d = first_difference(a.value(k, json()), b.value(k, json()), at.empty() ? k : at + "." + k);
    if (!d.empty()) return d;
  }
  return "";
}

// Every file the store's run read is among the given ones, by content (its
// path may be spelt otherwise). The given ones may hold more: tiles out of
// the reach of the run's parcels, which it did not read.
void check_files(const std::vector<InputFile>& given, const RunRecord& run, const std::string& store) {
  std::set<std::string> have;
  for (const InputFile& f : given) have.insert(f.sha256);
  for (const InputFile& f : run.inputs)
    if (!have.count(f.sha256))
      throw InputError(store, "its run read " + f.path + ", which these inputs lack or hold changed (SHA-256)");
}

// Every parcel the stores hold is one these inputs select, with the same key
// (parameters, inputs, shape); when they hold every shard's, they hold all
// the inputs select.
void check_parcels(const LoadedInputs& in, const std::vector<std::string>& keys, const std::vector<std::string>& stores) {
  const std::vector<Parcel>& layer = in.layer.parcels;
  std::map<std::string, size_t> at;  // parcel id -> layer index (ids are unique in a store)
  for (size_t i = 0; i < layer.size(); ++i) at[layer[i].id] = i;
  std::set<std::string> held;
  std::set<int> shards;
  int n = 0;
  for (const std::string& store : stores) {
    for (const RunRecord& r : load_runs(store))
      if (!r.shard.empty()) shards.insert(parse_shard(r.shard).k), n = parse_shard(r.shard).n;
    for (const JobRecord& j : load_jobs(store)) {
      const auto i = at.find(j.parcel_id);
      if (i == at.end())
        throw InputError(store, "parcel " + j.parcel_id +
                                    " is not one these inputs select: other --layer, --where or --bbox?");
      if (keys[i->second] != j.inputs_key)
        throw InputError(store, "parcel " + j.parcel_id +
                                    " was modelled from other inputs than these give it: its points, DTM, "
                                    "settings or shape changed since");
      held.insert(j.parcel_id);
    }
  }
  if (int(shards.size()) == n && held.size() != layer.size())
    throw InputError(stores.front(), "its run's shards hold " + std::to_string(held.size()) +
                                         " parcels, these inputs select " + std::to_string(layer.size()) +
                                         ": other --layer, --where or --bbox?");
}

// The models a store holds (store_models, as StoreSink::models after a
// batch); nothing is written.
class StoreModels : public BatchSink {
 public:
  StoreModels(std::string store, const std::vector<Parcel>& layer) : store_(std::move(store)), layer_(layer) {}
  void begin(const BatchRun&) override {}
  bool has_parcel(size_t, const std::string&) override { return false; }
  void write_parcel(size_t, const ParcelResult&, const ParcelValuation&) override {
    throw std::logic_error("StoreModels: read only");
  }
  SinkCounts end() override { return {}; }
  BatchModel models(const std::vector<int>& layer_indices) override {
    return store_models(store_, layer_, layer_indices);
  }

 private:
  std::string store_;
  const std::vector<Parcel>& layer_;
};

}  // namespace

std::string parameters_difference(const std::string& a, const std::string& b) {
  json ja = json::parse(a, nullptr, false), jb = json::parse(b, nullptr, false);
  for (json* j : {&ja, &jb})
    if (j->is_object()) j->erase("config_file"), j->erase("batch");  // [batch] changes no result
  return first_difference(ja, jb, "");
}

LoadedInputs load_run_inputs(const RunInputs& run, const std::vector<std::string>& stores) {
  const std::vector<RunRecord> runs = load_runs(stores.front());
  if (runs.empty()) throw InputError(stores.front(), "holds no run");
  const std::string differs = parameters_difference(run_parameters(run.cfg), runs.back().parameters);
  if (!differs.empty()) throw InputError(stores.front(), "was run with other parameters: " + differs);
  LoadedInputs in = load_fit_inputs(run.inputs, run.cfg);
  const std::vector<InputFile> files = describe_inputs(in, run.inputs);
  check_files(files, runs.back(), stores.front());
  check_parcels(in, parcel_keys(in, run.inputs, run.cfg, files), stores);
  return in;
}

void store_fit(const LoadedInputs& in, const Config& cfg, const std::string& store, BatchReport& report) {
  StoreModels models(store, in.layer.parcels);
  any_model_deviation(in, cfg, models, report);
}

}  // namespace c3d
