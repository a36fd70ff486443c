#include "valuation/valuation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "core/error.h"
#include "core/geometry/geometry.h"

namespace c3d {

namespace {

double quadrature(double a, double b) { return std::sqrt(a * a + b * b); }

double unit_cost_of(const ValuationParams& p, const std::string& type) {
  auto it = p.unit_cost.find(type);
  if (it == p.unit_cost.end())
    throw InputError("valuation", "no unit cost for element type '" + type + "'");
  return it->second;
}

CostItem element_item(const Building& b, int index, double factor, const std::string& quality,
                      const ValuationParams& p) {
  const Element& e = b.elements[size_t(index)];
  CostItem c;
  c.building_id = b.id;
  c.element_index = index;
  c.element_type = to_string(e.type);
  c.quality = quality;
  c.area = e.area;
  c.sigma_area = e.sigma_area;
  c.unit_cost = unit_cost_of(p, c.element_type) * factor;
  c.amount = c.area * c.unit_cost;
  c.sigma_amount = c.unit_cost * c.sigma_area;
  c.support_points = e.support_points;
  c.rmse = e.rmse;
  return c;
}

// Optional surcharge on gross floor area = footprint x storeys.
CostItem gross_floor_item(const Building& b, double factor, const std::string& quality,
                          const ValuationParams& p) {
  BuildingTotals t = totals(b);
  CostItem c;
  c.building_id = b.id;
  c.element_type = "gross_floor";
  c.quality = quality;
  c.area = t.ground * std::max(1, b.storeys);
  c.sigma_area = t.sigma_ground * std::max(1, b.storeys);
  c.unit_cost = p.gross_floor_cost_per_m2 * factor;
  c.amount = c.area * c.unit_cost;
  c.sigma_amount = c.unit_cost * c.sigma_area;
  return c;
}

}  // namespace

double valuation_land_area(const Parcel& parcel, std::string* source) {
  bool official = std::isfinite(parcel.official_area) && parcel.official_area > 0;
  if (source) *source = official ? "official" : "computed";
  return official ? parcel.official_area : area(parcel.shape);
}

ParcelValuation value_parcel(const Parcel& parcel, const ParcelResult& result,
                             const ValuationParams& p) {
  ParcelValuation v;
  v.parcel_id = parcel.id;
  v.currency = p.currency;
  ParcelValuationOverride o;
  if (auto it = p.parcels.find(parcel.id); it != p.parcels.end()) o = it->second;
  v.zone = o.zone.empty() ? p.default_zone : o.zone;
  v.quality = o.quality.empty() ? p.default_quality : o.quality;
  v.age_years = std::isfinite(o.age_years) ? o.age_years : p.building_age_years;

  auto zone = p.land_price.find(v.zone);
  if (zone == p.land_price.end())
    throw InputError("valuation", "parcel " + parcel.id + ": unknown zone '" + v.zone + "'");
  v.land_area = valuation_land_area(parcel, &v.land_area_source);
  v.land_price_per_m2 = zone->second;
  v.land_value = v.land_area * v.land_price_per_m2;

  double factor = 1.0;
  if (!v.quality.empty()) {
    auto q = p.quality_factor.find(v.quality);
    if (q == p.quality_factor.end())
      throw InputError("valuation", "parcel " + parcel.id + ": unknown quality '" + v.quality + "'");
    factor = q->second;
  }

  if (result.status == ParcelStatus::Failed) v.note = "land only, building not modelled: " + result.reason;
  // A suspect model is shown but not priced: its figures await an officer's review.
  const bool suspect = result.status == ParcelStatus::Suspect;
  if (suspect) v.note = "land only, building not valued (suspect): " + result.reason;
  for (const Building& b : suspect ? std::vector<Building>{} : result.buildings) {
    // Within a building the elements' shared sigma parts (one assumed
    // overhang, one fitted roof noise) add linearly per type; buildings
    // and the rest in quadrature.
    std::map<std::string, SharedSigma> cost_sigma;
    for (int i = 0; i < int(b.elements.size()); ++i) {
      const Element& e = b.elements[size_t(i)];
      v.items.push_back(element_item(b, i, factor, v.quality, p));
      const CostItem& c = v.items.back();
      const double own = std::sqrt(std::max(0.0, e.sigma_area * e.sigma_area - e.sigma_shared * e.sigma_shared));
      cost_sigma[c.element_type].add(c.unit_cost * own, c.unit_cost * e.sigma_shared);
    }
    if (p.gross_floor_cost_per_m2 > 0) {
      v.items.push_back(gross_floor_item(b, factor, v.quality, p));
      cost_sigma["gross_floor"].add(v.items.back().sigma_amount, 0);
    }
    for (const auto& [type, sigma] : cost_sigma) v.sigma_building_cost = quadrature(v.sigma_building_cost, sigma.total());
  }
  for (const CostItem& c : v.items) v.building_cost += c.amount;

  v.depreciation_share = std::min(p.max_depreciation, p.depreciation_per_year * v.age_years);
  v.depreciation = v.building_cost * v.depreciation_share;
  v.building_value = v.building_cost - v.depreciation;
  v.sigma_building_value = v.sigma_building_cost * (1 - v.depreciation_share);

  v.njop = v.land_value + v.building_value;
  v.sigma_njop = v.sigma_building_value;  // land area is certified: no sigma
  v.tax_rate = p.tax_rate;
  v.njoptkp = p.tax_exemption;
  v.taxable = std::max(0.0, v.njop - v.njoptkp);
  v.tax = v.tax_rate * v.taxable;
  v.sigma_tax = v.taxable > 0 ? v.tax_rate * v.sigma_njop : 0.0;
  return v;
}

std::vector<ParcelValuation> value_batch(const BatchModel& model, const ValuationParams& p) {
  std::vector<ParcelValuation> out;
  out.reserve(model.parcels.size());
  for (size_t i = 0; i < model.parcels.size(); ++i) {
    ParcelResult empty;
    const ParcelResult& r = i < model.results.size() ? model.results[i] : empty;
    out.push_back(value_parcel(model.parcels[i], r, p));
  }
  return out;
}

}  // namespace c3d
