#pragma once
// Pieces shared by the report's HTML, SVG and CSV writers (internal to
// cadastre/report/): element colours and labels, number formatting, escaping,
// per-type area totals, and the charts the HTML page embeds.
#include <map>
#include <string>
#include <vector>

#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d::report_detail {

// Element types in the order of the legend, the tables and the CSV columns.
inline constexpr ElementType kTypes[] = {ElementType::Roof, ElementType::Wall,
                                         ElementType::PartyWall, ElementType::Ground,
                                         ElementType::OuterCeiling};

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

// Sum of element areas of one type over a parcel, sigma in quadrature.
struct TypeTotal {
  double area = 0, sigma = 0;
};
std::map<ElementType, TypeTotal> type_totals(const ParcelResult& r);

// SVG pieces of the HTML page (report_svg.cpp).
std::string legend_svg();
std::string area_chart(const BatchModel& m);
// NJOP per parcel as stacked land / building bars; a histogram when there are many.
std::string value_chart(const BatchModel& m, const std::vector<ParcelValuation>& vals);

}  // namespace c3d::report_detail
