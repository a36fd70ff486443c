#pragma once
// The officer's report: OUT/report.html (one self-contained offline page:
// summary, inline SVG charts, per-parcel tables and an axonometric picture of
// each parcel's buildings coloured by element type) and OUT/report.csv (the
// same per-parcel and per-element figures).
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

// Valuations are matched to parcels by parcel id (any order; missing -> blank).
std::string report_html(const BatchModel& model, const std::vector<ParcelValuation>& valuations,
                        const ReportInfo& info = {});
std::string report_csv(const BatchModel& model, const std::vector<ParcelValuation>& valuations);
// Axonometric SVG of one parcel: element faces (local coordinates) sorted by
// depth and filled by type, the parcel outline underneath.
std::string parcel_svg(const Parcel& parcel, const ParcelResult& result, const LocalFrame& frame,
                       int width = 360, int height = 260);
// Writes out_dir/report.html and out_dir/report.csv (creates out_dir).
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
