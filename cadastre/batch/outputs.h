#pragma once
// Everything a batch writes after reconstruction is read back from the store,
// so summary.json, the report and the exports always agree with it.
#include <functional>
#include <string>
#include <vector>

#include "cadastre/batch/batch.h"
#include "cadastre/store/pages.h"

namespace c3d {

struct WrittenOutputs {
  std::string summary, report, preview_dir;
  std::vector<std::string> exports;  // one per file (OBJ and STEP: one per parcel / building)
};

// Called after each output written (done of total).
using OutputProgress = std::function<void(size_t done, size_t total)>;

// OUT/summary.json, OUT/report.html + .csv, OUT/preview/<parcel>.svg and the
// exports in `formats`, from the batch's report (its counts, deviations and
// timings) and the store at store_loc, read a page of parcels at a time in
// one pass that feeds every output (cadastre/store/pages.h): memory holds one
// page of models, never the town's. Each file is written under OUT/.staging
// and renamed into place once all are written (see out_dir.h). Progress:
// one step per page, one for publishing.
WrittenOutputs write_outputs(const BatchReport& report, const std::string& store_loc,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats,
                             const OutputProgress& progress = {});
// The same from pages of the size a caller chooses (tests: 1, 3, all).
WrittenOutputs write_outputs(const BatchReport& report, const StorePages& pages,
                             const std::string& out_dir, const Config& cfg,
                             const std::vector<std::string>& formats,
                             const OutputProgress& progress = {});

// Each of `formats` of `store` written into `dir`: a store a page of parcels
// at a time, or a CityJSON file this tool wrote (small enough to read whole);
// `buildings` counts the buildings exported.
std::vector<PagesExport> export_store(const std::string& store, const std::string& dir,
                                      const std::vector<std::string>& formats, size_t& buildings);

}  // namespace c3d
