// The report a page of the store at a time (report.h, ReportWriter).
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "core/error.h"

namespace fs = std::filesystem;

namespace c3d {

using namespace report_detail;

namespace {

// What the summary page reads of a parcel once its detail page and CSV rows
// are written: its id, shape, status, reason and element areas, not its
// geometry (faces, solids and lower LoDs are the bulk), timings, attributes
// or notes. Every parcel's row is held to the end, so it is kept small.
void keep_summary_row(Parcel& p, ParcelResult& r) {
  std::vector<ParcelAttribute>().swap(p.attributes);
  std::string().swap(p.repair_note);
  std::vector<Timing>().swap(r.timings);
  for (Building& b : r.buildings) {
    std::vector<Face>().swap(b.solid);
    std::vector<LodShell>().swap(b.lower_lods);
    b.attributes = BuildingAttributes{};
    std::string().swap(b.lod_note), std::string().swap(b.solid_problem);
    for (Element& e : b.elements) std::vector<Face>().swap(e.faces);
  }
}

}  // namespace

ReportWriter::ReportWriter(const std::string& out_dir, size_t parcel_count, const BatchModel& header,
                           ReportInfo info)
    : out_dir_(out_dir), total_(parcel_count), info_(std::move(info)), cells_(out_dir) {
  rows_.frame = header.frame, rows_.epsg = header.epsg, rows_.crs_wkt = header.crs_wkt;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  // Detail pages of an earlier report (more parcels, other ids) must not stay behind.
  const fs::path pages = fs::path(out_dir) / "report";
  for (const char* sub : {"", "parcel"})
    for (const auto& e : fs::directory_iterator(pages / sub, ec))
      if (e.is_regular_file() && e.path().extension() == ".html") fs::remove(e.path(), ec);
  csv_path_ = (fs::path(out_dir) / "report.csv").string();
  csv_.open(csv_path_, std::ios::binary);  // rows as the parcels' pages are written
  csv_ << csv_header();
  if (!csv_) throw InputError(csv_path_, "cannot write report");
}

void ReportWriter::write(const std::string& name, const std::string& text) const {
  const fs::path path = fs::path(out_dir_) / name;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw InputError(path.string(), "cannot write report");
}

void ReportWriter::add(BatchModel page, std::vector<ParcelValuation> valuations) {
  for (size_t i = 0; i < page.parcels.size(); ++i) {
    rows_.parcels.push_back(std::move(page.parcels[i]));
    rows_.results.push_back(std::move(page.results[i]));
  }
  for (auto& v : valuations) {
    val_of_[v.parcel_id] = vals_.size();
    vals_.push_back(std::move(v));
  }
  if (rows_.parcels.size() > total_)  // the store changed under us: page totals would be wrong
    throw InputError(info_.source, "the store gave more parcels than the " + std::to_string(total_) + " counted");
  write_ready(false);
}

// The detail pages of every page of parcels that is whole, with the parcel
// after it in (its links name it), or all at the end.
void ReportWriter::write_ready(bool all) {
  const size_t have = rows_.parcels.size();
  while (written_ < have) {
    const size_t to = std::min(written_ + kParcelsPerPage, total_);
    // Ready: the page's parcels are in, and the next parcel too unless it is the last page.
    if (!all && (have < to || (have == to && to < total_))) return;
    // The page's parcels' valuations alone: looking through every one so far
    // for each page would grow with the square of the parcels.
    std::vector<size_t> on_page;
    for (size_t i = written_; i < to && i < have; ++i) {
      const auto it = val_of_.find(rows_.parcels[i].id);
      if (it != val_of_.end()) on_page.push_back(it->second);
    }
    std::vector<ParcelValuation> page_vals;
    for (size_t k : on_page) page_vals.push_back(vals_[k]);
    write("report/" + group_page(written_), group_html(rows_, page_vals, info_, written_, total_));
    const auto vmap = by_parcel(page_vals);
    for (size_t i = written_; i < to && i < have; ++i) {
      const Parcel& p = rows_.parcels[i];
      const ParcelValuation* v = find_valuation(vmap, p.id);
      write("report/" + parcel_page(p), parcel_html(rows_, v, info_, i, total_));
      csv_ << csv_rows(p, rows_.results[i], v);
      cells_.add(p, rows_.results[i], v, rows_.frame);
      write_mesh_levels(rows_.results[i], p, rows_.frame, info_.files_root, out_dir_);
      keep_summary_row(rows_.parcels[i], rows_.results[i]);
    }
    if (!csv_) throw InputError(csv_path_, "cannot write report");
    // The summary page needs no cost items: only the detail pages and the CSV did.
    for (size_t k : on_page) std::vector<CostItem>().swap(vals_[k].items);
    written_ = std::min(to, have);
  }
}

void ReportWriter::finish() {
  if (rows_.parcels.size() != total_) {  // the store changed under us: page totals would be wrong
    throw InputError(info_.source, "the store holds " + std::to_string(rows_.parcels.size()) +
                                       " parcels, not the " + std::to_string(total_) + " counted");
  }
  write_ready(true);
  write("report.html", report_html(rows_, vals_, info_));
  cells_.finish(map_classes(rows_, vals_), vals_.empty() ? "" : vals_.front().currency);
  csv_.close();
  if (!csv_) throw InputError(csv_path_, "cannot write report");
}

}  // namespace c3d
