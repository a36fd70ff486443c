#pragma once
// Pieces shared by the report's HTML, SVG and CSV writers (internal to
// cadastre/report/): element colours and labels, number formatting, escaping,
// per-type area totals, page names and the pictures the pages embed.
#include <map>
#include <string>
#include <vector>

#include "cadastre/report/report.h"
#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d::report_detail {

// Element types in the order of the legend, the tables and the CSV columns.
inline constexpr ElementType kTypes[] = {ElementType::Roof, ElementType::Wall,
                                         ElementType::PartyWall, ElementType::Ground,
                                         ElementType::OuterCeiling};
// Parcels per detail page: ~50 sections of ~7 kB keep a page near 400 kB.
inline constexpr size_t kParcelsPerPage = 50;

const char* colour(ElementType t);
const char* label(ElementType t);
// printf into a std::string (at most 511 characters).
std::string fmt(const char* f, ...);
// Money with thousands separators, no decimals (IDR has no minor unit in use).
std::string money(double v);
std::string html_escape(const std::string& s);
// "v ± sigma unit" for HTML, two decimals.
std::string pm(double v, double sigma, const char* unit = "");
std::map<std::string, const ParcelValuation*> by_parcel(const std::vector<ParcelValuation>& v);
// The valuation of a parcel (nullptr when there is none).
const ParcelValuation* find_valuation(const std::map<std::string, const ParcelValuation*>& m,
                                      const std::string& parcel_id);
// Money the totals count: NJOP and tax both finite (else "not valued").
bool valued(const ParcelValuation* v);

// Sum of element areas of one type over a parcel, sigma in quadrature.
struct TypeTotal {
  double area = 0, sigma = 0;
};
std::map<ElementType, TypeTotal> type_totals(const ParcelResult& r);

// Page names. The summary is OUT/report.html; detail pages live in OUT/report/.
std::string group_page(size_t parcel_index);   // "parcels-001.html" (relative to report/)
std::string parcel_page(const Parcel& p);      // "parcel/<file stem>.html" (relative to report/)
// "<!DOCTYPE html>...<body>" with the shared style and print rules.
std::string page_head(const std::string& title);

// Pictures (report_svg.cpp, report_map.cpp).
std::string legend_svg();
std::string area_chart(const BatchModel& m);
// NJOP per parcel as stacked land / building bars; a labelled histogram when there are many.
std::string value_chart(const BatchModel& m, const std::vector<ParcelValuation>& vals);
// Value classes of the overview map: NJOP per m² of land, quantile breaks
// rounded to a unit of 1-10 % of the range; class k holds breaks[k-1] <= v < breaks[k].
struct ValueClasses {
  std::vector<double> breaks;
  size_t of(double v) const;
  size_t count() const { return breaks.size() + 1; }
  const char* colour(size_t k) const;
  std::string label(size_t k) const;
};
ValueClasses value_classes(std::vector<double> values);
double njop_per_m2(const ParcelValuation* v);  // NaN when not valued or no land area
// The overview map's classes: of the modelled and empty parcels' values.
ValueClasses map_classes(const BatchModel& m, const std::vector<ParcelValuation>& vals);
// The parcels in the layer's CRS coloured by value class, status drawn apart,
// each linking to link_prefix + parcel_page(p); legend, scale bar, north arrow.
std::string overview_map(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                         const std::string& link_prefix);
// One parcel seen from above: its outline and its buildings' roofs, to scale.
std::string plan_svg(const Parcel& p, const ParcelResult& r, const LocalFrame& frame, int width,
                     int height);
// A scale bar (longest 1/2/5 x 10^k metres under max_px) at x, y in pixels.
std::string scale_bar(double px_per_m, double x, double y, double max_px);
std::string north_arrow(double x, double y);

// Parcel detail (report_pages.cpp): heading links, building lines, elements, valuation.
// printed: the parcel's own page, where a building of many elements prints its
// totals by type instead of every row (all rows stay on screen).
std::string parcel_detail(const Parcel& p, const ParcelResult& r, const ParcelValuation* v,
                          bool printed = false);
std::string parcel_rows(const BatchModel& m, const std::vector<ParcelValuation>& vals, size_t from,
                        size_t to, const std::string& link_prefix);
std::string parcel_table_head();
// report.csv (report_csv.cpp): its header line, and the rows of one parcel
// (the parcel's, then one per element).
std::string csv_header();
std::string csv_rows(const Parcel& p, const ParcelResult& r, const ParcelValuation* v);
// Detail page OUT/report/parcels-NNN.html of the parcels from `from` (a
// multiple of kParcelsPerPage) of `total`; m holds them, their results whole.
std::string group_html(const BatchModel& m, const std::vector<ParcelValuation>& vals,
                       const ReportInfo& info, size_t from, size_t total);
// The printable page of parcel i of `total`; m holds it whole and the ids of its neighbours.
std::string parcel_html(const BatchModel& m, const ParcelValuation* v, const ReportInfo& info,
                        size_t i, size_t total);

}  // namespace c3d::report_detail
