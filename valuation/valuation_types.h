#pragma once
// Valuation results as plain data. valuation/ owns them and depends on core
// only; the store (cadastre/) writes and reads them, the report shows them.
#include <string>
#include <vector>

namespace c3d {

// One priced quantity. Element items point back to their element (building id
// + index in Building.elements) and carry the evidence behind its area, so a
// disputed amount traces to the plane fit and the points that support it.
struct CostItem {
  std::string building_id;      // empty for parcel-level items (land)
  int element_index = -1;       // index in Building.elements; -1: not an element
  std::string element_type;     // "roof", "wall", ..., or "gross_floor", "land"
  std::string quality;          // quality class applied ("" = none)
  double area = 0;              // m2
  double sigma_area = 0;        // m2, 1 sigma
  double unit_cost = 0;         // currency per m2 (quality factor included)
  double amount = 0;            // area * unit_cost
  double sigma_amount = 0;      // unit_cost * sigma_area
  int support_points = 0;
  double rmse = 0;              // plane-fit RMSE, m
};

struct ParcelValuation {
  std::string parcel_id;
  std::string currency;
  std::string zone;
  std::string quality;
  std::string note;             // why a figure is missing or partial
  double land_area = 0;         // m2
  std::string land_area_source; // "official" or "computed"
  double land_price_per_m2 = 0;
  double land_value = 0;
  double building_cost = 0;     // replacement cost: sum of the building items
  double sigma_building_cost = 0;
  double age_years = 0;
  double depreciation_share = 0;
  double depreciation = 0;      // building_cost * depreciation_share
  double building_value = 0;    // building_cost - depreciation
  double sigma_building_value = 0;
  double njop = 0;              // land_value + building_value
  double sigma_njop = 0;
  double tax_rate = 0;
  double njoptkp = 0;
  double taxable = 0;           // max(0, njop - njoptkp)
  double tax = 0;
  double sigma_tax = 0;
  std::vector<CostItem> items;  // building items (element and gross floor)
};

// The amount of element `element` of `building` in v's cost items; -1 where
// v is null or holds no item for it.
inline double element_amount(const ParcelValuation* v, const std::string& building, int element) {
  if (v)
    for (const CostItem& c : v->items)
      if (c.building_id == building && c.element_index == element) return c.amount;
  return -1;
}

}  // namespace c3d
