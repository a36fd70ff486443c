#pragma once
// Everything a batch writes after reconstruction is read back from the store,
// so summary.json, the report and the exports always agree with it.
#include <map>
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"

namespace c3d::cli {

struct OutputTimings {
  double ingest_s = 0, reconstruct_s = 0;
  std::map<std::string, double> stages;  // summed over parcels (CPU seconds)
  // Deviation of every roof point inside any parcel from the nearest roof
  // surface of any model (and wall points within 2 m of a parcel from any wall):
  // the model's fit, free of which parcel a point was counted for.
  Deviation any_model_roof, any_model_wall;
};

// model: the batch model as read back from the store at store_path.
void write_outputs(const BatchModel& model, const std::string& store_path,
                   const std::string& out_dir, const Config& cfg,
                   const std::vector<std::string>& formats, const OutputTimings& timings,
                   bool quiet);

// summary.json alone (also used by tests).
void write_summary(const std::string& store_path, const std::string& path,
                   const OutputTimings& timings);
void write_summary(const BatchModel& model, const std::string& path, const OutputTimings& timings);

}  // namespace c3d::cli
