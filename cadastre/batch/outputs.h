#pragma once
// Everything a batch writes after reconstruction is read back from the store,
// so summary.json, the report and the exports always agree with it.
#include <functional>
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"

namespace c3d {

struct WrittenOutputs {
  std::string summary, report, preview_dir;
  std::vector<std::string> exports;  // one per file (OBJ and STEP: one per parcel / building)
};

// Called after each output written (done of total).
using OutputProgress = std::function<void(size_t done, size_t total)>;

// OUT/summary.json, OUT/report.html + .csv, OUT/preview/<parcel>.svg and the
// exports in `formats`, from the batch's report (its model as the store at
// store_path holds it). Each file is written under OUT/.staging and renamed
// into place once all are written (see out_dir.h).
WrittenOutputs write_outputs(const BatchReport& report, const std::string& store_path,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats,
                             const OutputProgress& progress = {});

// summary.json alone.
void write_summary(const BatchReport& report, const BatchModel& model, const std::string& path);

}  // namespace c3d
