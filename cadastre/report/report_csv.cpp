// The report's CSV: one row per parcel and one per element under a shared header.
#include <cmath>
#include <map>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "core/text.h"

namespace c3d {

using namespace report_detail;

namespace {

const char* const kCsvColumns[] = {
    "record", "parcel_id", "status", "reason", "right_type", "building_id", "lod", "element_index",
    "element_type", "area_m2", "sigma_area_m2", "plan_area_m2", "slope_deg", "azimuth_deg",
    "support_points", "rmse_m", "wall_evidence", "unit_cost", "amount", "sigma_amount", "roof_m2",
    "wall_m2", "party_wall_m2", "ground_m2", "outer_ceiling_m2", "land_area_m2",
    "land_area_source", "zone", "land_value", "building_cost", "depreciation", "building_value",
    "sigma_building_value", "njop", "sigma_njop", "tax", "sigma_tax", "currency"};

// One CSV row addressed by column name, so parcel and element rows share a header.
class CsvRow {
 public:
  CsvRow() {
    for (const char* c : kCsvColumns) cells_[c];
  }
  // Text from the data, guarded against formula injection.
  CsvRow& set(const char* col, const std::string& v) {
    cells_.at(col) = csv_text_cell(v);
    return *this;
  }
  CsvRow& num(const char* col, double v, const char* f = "%.2f") {
    if (std::isfinite(v)) cells_.at(col) = csv_cell(fmt(f, v));
    return *this;
  }
  std::string line() const {
    std::string s;
    for (const char* c : kCsvColumns) s += (s.empty() ? "" : ",") + cells_.at(c);
    return s + "\n";
  }

 private:
  std::map<std::string, std::string> cells_;
};

}  // namespace

std::string report_detail::csv_header() {
  std::string s;
  for (const char* c : kCsvColumns) s += (s.empty() ? "" : ",") + std::string(c);
  return s + "\n";
}

std::string report_detail::csv_rows(const Parcel& p, const ParcelResult& r, const ParcelValuation* v) {
  static const char* const area_cols[] = {"roof_m2", "wall_m2", "party_wall_m2", "ground_m2",
                                          "outer_ceiling_m2"};
  std::string s;
  auto tt = type_totals(r);
  CsvRow row;
  row.set("record", "parcel").set("parcel_id", p.id).set("status", to_string(r.status))
      .set("reason", r.reason).set("right_type", p.right_type);
  for (int k = 0; k < 5; ++k) row.num(area_cols[k], tt[kTypes[k]].area, "%.3f");
  if (v) {
    row.num("land_area_m2", v->land_area, "%.3f").set("land_area_source", v->land_area_source)
        .set("zone", v->zone).num("land_value", v->land_value)
        .num("building_cost", v->building_cost).num("depreciation", v->depreciation)
        .num("building_value", v->building_value)
        .num("sigma_building_value", v->sigma_building_value).num("njop", v->njop)
        .num("sigma_njop", v->sigma_njop).num("tax", v->tax).num("sigma_tax", v->sigma_tax)
        .set("currency", v->currency);
  }
  s += row.line();
  std::map<std::pair<std::string, int>, const CostItem*> items;
  if (v)
    for (const auto& c : v->items) items[{c.building_id, c.element_index}] = &c;
  for (const Building& b : r.buildings)
    for (int k = 0; k < int(b.elements.size()); ++k) {
      const Element& e = b.elements[size_t(k)];
      CsvRow er;
      er.set("record", "element").set("parcel_id", p.id).set("building_id", b.id).set("lod", to_string(b.lod))
          .set("element_index", std::to_string(k)).set("element_type", to_string(e.type))
          .num("area_m2", e.area, "%.3f").num("sigma_area_m2", e.sigma_area, "%.3f")
          .num("plan_area_m2", e.plan_area, "%.3f").num("slope_deg", e.slope_deg)
          .num("azimuth_deg", e.azimuth_deg)
          .set("support_points", std::to_string(e.support_points))
          .num("rmse_m", e.rmse, "%.4f").set("wall_evidence", to_string(e.evidence));
      if (auto c = items.find({b.id, k}); c != items.end())
        er.num("unit_cost", c->second->unit_cost).num("amount", c->second->amount)
            .num("sigma_amount", c->second->sigma_amount);
      s += er.line();
    }
  return s;
}

std::string report_csv(const BatchModel& m, const std::vector<ParcelValuation>& vals) {
  auto vmap = by_parcel(vals);
  std::string s = csv_header();
  for (size_t i = 0; i < m.parcels.size(); ++i)
    s += csv_rows(m.parcels[i], m.results[i], find_valuation(vmap, m.parcels[i].id));
  return s;
}

}  // namespace c3d
