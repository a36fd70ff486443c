#pragma once
// The officer's report, offline HTML with inline SVG (docs/report.md):
//   OUT/report.html              summary: totals by status, overview map by value,
//                                labelled charts, index of the detail pages
//   OUT/report/parcels-NNN.html  50 parcels each: table and per-parcel sections
//   OUT/report/parcel/<id>.html  one printable A4 page per parcel
//   OUT/report.csv               the per-parcel and per-element figures
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "cadastre/report/report_3d.h"
#include "cadastre/store/pages.h"
#include "core/config/config.h"
#include "core/mesh/tri_mesh.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

struct ReportInfo {
  std::string title = "Cadastre3D parcel batch";
  std::string source;    // store or input the figures come from
  std::string run_note;  // e.g. tool version, run start/end
  // The batch's output folder, where its per-building files (mesh/) are, for
  // the 3D view's mesh levels; "" where there is none (a PostGIS store).
  std::string files_root;
};

// One file of the report: its path relative to the output folder, its text.
struct ReportFile {
  std::string path;
  std::string text;
};

// Valuations are matched to parcels by parcel id (any order; missing -> blank).
// Every page and the CSV of the report, the summary page first (the 3D
// view's data files are written by write_report and ReportWriter only).
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
// The same view of a triangle mesh (a level of a building's mesh ladder,
// core/mesh): its triangles far to near, grey shaded by their slope to the
// light; a mesh of more than kMaxPictureFaces says so instead.
constexpr size_t kMaxPictureFaces = 60000;
std::string mesh_svg(const TriMesh& mesh, const std::string& title, int width = 360, int height = 260);
// Writes every report file under out_dir (creates folders; removes detail
// pages an earlier report left there).
void write_report(const std::string& out_dir, const BatchModel& model,
                  const std::vector<ParcelValuation>& valuations, const ReportInfo& info = {});

// The report written as a store's pages come (cadastre/store/pages.h): each
// detail page as soon as its parcels (and the next one, for the links) are
// in, the summary page and the CSV at the end from the parcels' figures
// (ids, shapes, statuses, element areas, valuations) without their geometry,
// so memory holds about a page of models and a small row per parcel.
class ReportWriter {
 public:
  // parcel_count: the parcels the pages will bring (the pages' "of N").
  ReportWriter(const std::string& out_dir, size_t parcel_count, const BatchModel& header, ReportInfo info);
  // The next parcels in layer order, with their valuations (any order).
  void add(BatchModel page, std::vector<ParcelValuation> valuations);
  void finish();

 private:
  void write(const std::string& name, const std::string& text) const;
  void write_ready(bool all);
  std::string out_dir_;
  size_t total_;
  ReportInfo info_;
  BatchModel rows_;  // every parcel so far; whole results only of those whose pages wait
  std::vector<ParcelValuation> vals_;  // cost items only of parcels whose pages wait
  std::unordered_map<std::string, size_t> val_of_;  // a parcel id's latest valuation in vals_
  size_t written_ = 0;  // parcels whose detail pages (and CSV rows) are written
  report_detail::SummaryCells cells_;  // the summary's 3D view
  std::string csv_path_;
  std::ofstream csv_;
};

// What the report's pages say of a store's latest run. own_run: the batch
// writing its own report, before it marks its run finished; revalue: priced
// again with cfg.valuation.
ReportInfo store_report_info(const std::string& store_loc, const Config& cfg, bool revalue, bool own_run);

// The report from a store alone, read a page at a time (so the report always
// agrees with the store). revalue: price the stored model again with
// cfg.valuation instead of using the stored valuations (what-if, --config).
void write_report_from_store(const std::string& store_loc, const std::string& out_dir,
                             const Config& cfg, bool revalue = false);
void write_report_from_store(const StorePages& pages, const std::string& out_dir, const Config& cfg,
                             bool revalue = false, bool own_run = false);

}  // namespace c3d
