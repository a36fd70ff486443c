#include "cadastre/batch/store_sink.h"

#include <filesystem>

#include "core/io/crs.h"

namespace c3d {

void StoreSink::begin(const BatchRun& run) {
  parcels_ = run.parcels;
  keys_ = run.parcel_keys;
  frame_ = run.frame;
  const auto dir = std::filesystem::path(path_).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
  store_.open(path_, run.crs_wkt, epsg_of(run.crs_wkt));
  store_.begin_run(run.parameters, run.inputs, run.frame);
  store_.mark_pending(*parcels_, keys_);
}

bool StoreSink::has_parcel(size_t i, const std::string& key) {
  return store_.parcel_done((*parcels_)[i].id, key);
}

void StoreSink::write_parcel(size_t i, const ParcelResult& result, const ParcelValuation& valuation) {
  store_.write_parcel((*parcels_)[i], result, valuation, frame_, keys_[i]);
}

BatchModel StoreSink::end() {
  store_.end_run();
  store_.close();
  return load_batch_model(path_);
}

}  // namespace c3d
