#pragma once
// Everything a batch writes after reconstruction is read back from the store,
// so summary.json, the report and the exports always agree with it.
#include <map>
#include <string>
#include <vector>

#include "core/config.h"

namespace c3d::cli {

struct OutputTimings {
  double ingest_s = 0, reconstruct_s = 0;
  std::map<std::string, double> stages;  // summed over parcels (CPU seconds)
};

void write_outputs(const std::string& store_path, const std::string& out_dir, const Config& cfg,
                   const std::vector<std::string>& formats, const OutputTimings& timings,
                   bool quiet);

// summary.json alone (also used by tests).
void write_summary(const std::string& store_path, const std::string& path,
                   const OutputTimings& timings);

}  // namespace c3d::cli
