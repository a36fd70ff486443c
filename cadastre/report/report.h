#pragma once
// The officer's report, offline HTML with inline SVG (docs/report.md):
//   OUT/report.html              summary: totals by status, overview map by value,
//                                labelled charts, index of the detail pages
//   OUT/report/parcels-NNN.html  50 parcels each: table and per-parcel sections
//   OUT/report/parcel/<id>.html  one printable A4 page per parcel
//   OUT/report.csv               the per-parcel and per-element figures
#include <string>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

struct ReportInfo {
  std::string title = "Cadastre3D parcel batch";
  std::string source;    // store or input the figures come from
  std::string run_note;  // e.g. tool version, run start/end
};

// One file of the report: its path relative to the output folder, its text.
struct ReportFile {
  std::string path;
  std::string text;
};

// Valuations are matched to parcels by parcel id (any order; missing -> blank).
// Every file of the report, the summary page first.
std::vector<ReportFile> report_files(const BatchModel& model,
                                     const std::vector<ParcelValuation>& valuations,
                                     const ReportInfo& info = {});
// The summary page (OUT/report.html) alone.
std::string report_html(const BatchModel& model, const std::vector<ParcelValuation>& valuations,
                        const ReportInfo& info = {});
std::string report_csv(const BatchModel& model, const std::vector<ParcelValuation>& valuations);
// Axonometric SVG of one parcel: element faces (local coordinates) sorted by
// depth and filled by type, the parcel outline underneath.
std::string parcel_svg(const Parcel& parcel, const ParcelResult& result, const LocalFrame& frame,
                       int width = 360, int height = 260);
// Writes every report file under out_dir (creates folders; removes detail
// pages an earlier report left there).
void write_report(const std::string& out_dir, const BatchModel& model,
                  const std::vector<ParcelValuation>& valuations, const ReportInfo& info = {});

// The report from a store alone: model and valuations read back (so the report
// always agrees with the store). revalue: price the stored model again with
// cfg.valuation instead of using the stored valuations (what-if, --config).
void write_report_from_store(const std::string& store_path, const std::string& out_dir,
                             const Config& cfg, bool revalue = false);
// The same with the model already read from that store (the batch has it).
// own_run: the batch writing its own report, before it marks its run finished.
void write_report_from_store(const BatchModel& model, const std::string& store_path,
                             const std::string& out_dir, const Config& cfg, bool revalue = false,
                             bool own_run = false);

}  // namespace c3d
