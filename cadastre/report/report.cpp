#include "cadastre/report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cadastre/report/report_parts.h"
#include "cadastre/store/store.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/io/file_names.h"
#include "core/text.h"
#include "valuation/valuation.h"

namespace c3d {

namespace report_detail {

const char* colour(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "#a0522d";         // red-brown
    case ElementType::Wall: return "#d8d8d8";         // light grey
    case ElementType::PartyWall: return "#f28e2b";    // orange
    case ElementType::Ground: return "#555555";       // dark grey
    case ElementType::OuterCeiling: return "#4e79a7"; // blue
  }
  return "#000";
}

const char* label(ElementType t) {
  switch (t) {
    case ElementType::Roof: return "Roof";
    case ElementType::Wall: return "Wall";
    case ElementType::PartyWall: return "Party wall";
    case ElementType::Ground: return "Ground floor";
    case ElementType::OuterCeiling: return "Outer ceiling";
  }
  return "?";
}

std::string fmt(const char* f, ...) {
  char buf[512];
  va_list a;
  va_start(a, f);
  std::vsnprintf(buf, sizeof buf, f, a);
  va_end(a);
  return buf;
}

// Money with thousands separators, no decimals (IDR has no minor unit in use).
std::string money(double v) {
  if (!std::isfinite(v)) return "";
  std::string digits = fmt("%.0f", std::abs(v));
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return (v < -0.5 ? "-" : "") + out;
}

std::string html_escape(const std::string& s) { return escape_markup(s); }

std::string pm(double v, double sigma, const char* unit) {
  return fmt("%.2f&nbsp;&plusmn;&nbsp;%.2f%s", v, sigma, unit);
}

std::map<std::string, const ParcelValuation*> by_parcel(const std::vector<ParcelValuation>& v) {
  std::map<std::string, const ParcelValuation*> m;
  for (const auto& x : v) m[x.parcel_id] = &x;
  return m;
}

const ParcelValuation* find_valuation(const std::map<std::string, const ParcelValuation*>& m,
                                      const std::string& parcel_id) {
  auto it = m.find(parcel_id);
  return it == m.end() ? nullptr : it->second;
}

bool valued(const ParcelValuation* v) {
  return v && std::isfinite(v->njop) && std::isfinite(v->tax);
}

std::string group_page(size_t parcel_index) {
  return fmt("parcels-%03zu.html", parcel_index / kParcelsPerPage + 1);
}

std::string parcel_page(const Parcel& p) { return "parcel/" + file_stem_for_id(p.id) + ".html"; }

std::map<ElementType, TypeTotal> type_totals(const ParcelResult& r) {
  std::map<ElementType, TypeTotal> t;
  for (const Building& b : r.buildings) {
    std::map<ElementType, SharedSigma> sigma;  // within a building errors may be shared
    for (const Element& e : b.elements) {
      t[e.type].area += e.area;
      sigma[e.type].add(e);
    }
    for (const auto& [type, s] : sigma) t[type].sigma = std::hypot(t[type].sigma, s.total());
  }
  return t;
}

}  // namespace report_detail

void write_report(const std::string& out_dir, const BatchModel& model,
                  const std::vector<ParcelValuation>& valuations, const ReportInfo& info) {
  ReportWriter report(out_dir, model.parcels.size(), model, info);
  report.add(model, valuations);
  report.finish();
}

namespace {

// The run's inputs by role, as an officer checks them: "inputs 152 cloud
// files, parcels parcels.gpkg, dtm dtm.tif, ..." (a record from before roles:
// a count).
std::string inputs_note(const std::vector<InputFile>& inputs) {
  const std::string sums = ", each with its SHA-256 in the store";
  if (inputs.empty()) return "no input files recorded";
  std::vector<std::pair<std::string, std::vector<std::string>>> by_role;  // in the order met
  for (const InputFile& f : inputs) {
    if (f.role.empty()) return std::to_string(inputs.size()) + " input file(s)" + sums;
    auto it = std::find_if(by_role.begin(), by_role.end(), [&](const auto& r) { return r.first == f.role; });
    if (it == by_role.end()) it = by_role.insert(by_role.end(), {f.role, {}});
    it->second.push_back(std::filesystem::path(f.path).filename().string());
  }
  std::string out;
  for (const auto& [role, names] : by_role)
    out += (out.empty() ? "inputs " : ", ") +
           (names.size() == 1 ? role + " " + names.front() : std::to_string(names.size()) + " " + role + " files");
  return out + sums;
}

}  // namespace

ReportInfo store_report_info(const std::string& store_loc, const Config& cfg, bool revalue, bool own_run) {
  ReportInfo info;
  info.source = store_loc;
  std::error_code ec;
  if (std::filesystem::is_regular_file(store_loc, ec))  // a GeoPackage in the batch's output folder
    info.files_root = std::filesystem::path(store_loc).parent_path().string();
  auto runs = load_runs(store_loc);
  if (!runs.empty()) {
    const RunRecord& r = runs.back();
    info.run_note = r.tool_version + ", run " + std::to_string(r.id) + " started " + r.started +
                    (!r.finished.empty() ? ", finished " + r.finished
                     : own_run        ? std::string(", finished with these outputs")
                                      : std::string(" (not finished)")) + ", " +
                    inputs_note(r.inputs);
  }
  if (revalue) info.run_note += (info.run_note.empty() ? "" : "; ") +
                                std::string("re-valued with ") + cfg.source;
  return info;
}

void write_report_from_store(const std::string& store_loc, const std::string& out_dir,
                             const Config& cfg, bool revalue) {
  write_report_from_store(StorePages(store_loc), out_dir, cfg, revalue);
}

void write_report_from_store(const StorePages& pages, const std::string& out_dir, const Config& cfg,
                             bool revalue, bool own_run) {
  ReportWriter report(out_dir, pages.parcel_count(), pages.header(),
                      store_report_info(pages.location(), cfg, revalue, own_run));
  for (size_t k = 0; k < pages.page_count(); ++k) {
    BatchModel page = pages.page(k);
    auto vals = revalue ? value_batch(page, cfg.valuation) : pages.valuations(k);
    report.add(std::move(page), std::move(vals));
  }
  report.finish();
}

}  // namespace c3d
