#pragma once
// The batch's default sink: the LADM GeoPackage store (cadastre/store/store.h), one
// transaction per parcel, so a killed batch leaves whole parcels and --resume
// picks up where it stopped.
#include <string>

#include "cadastre/batch/batch.h"
#include "cadastre/store/store.h"

namespace c3d {

class StoreSink : public BatchSink {
 public:
  // keep_other_runs: a store already at `path` may hold another run's parcels
  // (other inputs, settings or layer: --resume); without it such a store is
  // refused (InputError) before anything is written to it.
  explicit StoreSink(std::string path, bool keep_other_runs = false)
      : path_(std::move(path)), keep_other_runs_(keep_other_runs) {}
  const std::string& path() const { return path_; }
  std::int64_t run_id() const { return run_id_; }  // this batch's run row (after begin)

  void begin(const BatchRun& run) override;
  bool has_parcel(size_t i, const std::string& key) override;
  void write_parcel(size_t i, const ParcelResult& result, const ParcelValuation& valuation) override;
  SinkCounts end() override;  // closes the store; counts its parcel jobs
  BatchModel models(const std::vector<int>& layer_indices) override;  // read back from the store

 private:
  std::string path_;
  bool keep_other_runs_ = false;
  Store store_;
  const std::vector<Parcel>* parcels_ = nullptr;
  std::vector<std::string> keys_;
  LocalFrame frame_;
  std::int64_t run_id_ = 0;
};

// The models `store` holds for these parcels of `layer` (layer indices),
// read by the parcels' ids, in layer order; BatchSink::models of a store.
BatchModel store_models(const std::string& store, const std::vector<Parcel>& layer,
                        const std::vector<int>& layer_indices);

}  // namespace c3d
