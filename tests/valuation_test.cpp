#include <gtest/gtest.h>

#include <cmath>

#include "core/config/config.h"
#include "tests/store_fixtures.h"
#include "valuation/valuation.h"

using namespace c3d;

namespace {

// Small round numbers so every figure can be checked by hand.
ValuationParams params() {
  ValuationParams p;
  p.currency = "IDR";
  p.unit_cost = {{"roof", 100}, {"wall", 50}, {"party_wall", 25}, {"ground", 40},
                 {"outer_ceiling", 10}};
  p.quality_factor = {{"permanent", 1.0}, {"temporary", 0.5}};
  p.default_quality = "permanent";
  p.land_price = {{"A", 1000}, {"B", 500}};
  p.default_zone = "B";
  p.building_age_years = 10;
  p.depreciation_per_year = 0.02;
  p.max_depreciation = 0.5;
  p.tax_rate = 0.001;
  p.tax_exemption = 10000;
  return p;
}

Building two_elements() {
  Building b;
  b.id = "b0";
  Element roof;
  roof.type = ElementType::Roof;
  roof.area = 120;
  roof.sigma_area = 3;
  roof.support_points = 900;
  roof.rmse = 0.04;
  Element wall;
  wall.type = ElementType::Wall;
  wall.area = 100;
  wall.sigma_area = 8;
  b.elements = {roof, wall};
  return b;
}

}  // namespace

TEST(Valuation, HandComputedCostApproach) {
  Parcel parcel = test::square_parcel(0, "P1", Vec2(0, 0), 10);  // computed area 100
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  r.buildings = {two_elements()};
  ParcelValuation v = value_parcel(parcel, r, params());
  ASSERT_EQ(v.items.size(), 2u);
  // roof: 120 x 100 = 12000 +- 300; wall: 100 x 50 = 5000 +- 400
  EXPECT_DOUBLE_EQ(v.items[0].amount, 12000);
  EXPECT_DOUBLE_EQ(v.items[0].sigma_amount, 300);
  EXPECT_EQ(v.items[0].support_points, 900);
  EXPECT_DOUBLE_EQ(v.items[0].rmse, 0.04);
  EXPECT_EQ(v.items[0].building_id, "b0");
  EXPECT_EQ(v.items[1].element_index, 1);
  EXPECT_DOUBLE_EQ(v.items[1].amount, 5000);
  EXPECT_DOUBLE_EQ(v.building_cost, 17000);
  EXPECT_DOUBLE_EQ(v.sigma_building_cost, 500);  // sqrt(300^2 + 400^2)
  EXPECT_DOUBLE_EQ(v.depreciation_share, 0.2);    // 10 years x 2 %
  EXPECT_DOUBLE_EQ(v.building_value, 13600);
  EXPECT_DOUBLE_EQ(v.sigma_building_value, 400);
  EXPECT_EQ(v.land_area_source, "computed");
  EXPECT_DOUBLE_EQ(v.land_value, 100 * 500.0);
  EXPECT_DOUBLE_EQ(v.njop, 63600);
  EXPECT_DOUBLE_EQ(v.taxable, 53600);
  EXPECT_DOUBLE_EQ(v.tax, 53.6);
  EXPECT_DOUBLE_EQ(v.sigma_tax, 0.4);
}

TEST(Valuation, SharedSigmaPartsOfOneTypeAddLinearly) {
  // Two walls set back from their roof edges by one assumed overhang: 6 of
  // each one's 10 m^2 sigma is that overhang's, shared; 8 is its own.
  Parcel parcel = test::square_parcel(0, "P1", Vec2(0, 0), 10);
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  Building b = two_elements();
  b.elements[1].sigma_area = 10, b.elements[1].sigma_shared = 6;
  b.elements.push_back(b.elements[1]);
  r.buildings = {b};
  ParcelValuation v = value_parcel(parcel, r, params());
  // roof 300; walls: own 50 x 8 twice in quadrature, shared 50 x (6 + 6).
  const double walls = std::hypot(400 * std::sqrt(2.0), 300.0 * 2);
  EXPECT_NEAR(v.sigma_building_cost, std::hypot(300.0, walls), 1e-9);
}

TEST(Valuation, OfficialAreaOverridesZoneQualityAge) {
  Parcel parcel = test::square_parcel(0, "P2", Vec2(0, 0), 10, 96.0);
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  r.buildings = {two_elements()};
  ValuationParams p = params();
  ParcelValuationOverride o;
  o.zone = "A";
  o.quality = "temporary";
  o.age_years = 40;  // 80 % capped at 50 %
  p.parcels["P2"] = o;
  ParcelValuation v = value_parcel(parcel, r, p);
  EXPECT_EQ(v.land_area_source, "official");
  EXPECT_DOUBLE_EQ(v.land_value, 96000);
  EXPECT_DOUBLE_EQ(v.items[0].unit_cost, 50);
  EXPECT_DOUBLE_EQ(v.building_cost, 8500);
  EXPECT_DOUBLE_EQ(v.depreciation_share, 0.5);
  EXPECT_DOUBLE_EQ(v.building_value, 4250);
  EXPECT_DOUBLE_EQ(v.njop, 100250);
  EXPECT_DOUBLE_EQ(v.tax, 0.001 * (100250 - 10000));
}

TEST(Valuation, ExemptionAndFailedParcel) {
  Parcel parcel = test::square_parcel(0, "P3", Vec2(0, 0), 2);  // 4 m2 x 500 = 2000 < NJOPTKP
  ParcelResult r;
  r.status = ParcelStatus::Failed;
  r.reason = "no planes";
  ParcelValuation v = value_parcel(parcel, r, params());
  EXPECT_DOUBLE_EQ(v.njop, 2000);
  EXPECT_DOUBLE_EQ(v.tax, 0);
  EXPECT_DOUBLE_EQ(v.sigma_tax, 0);
  EXPECT_NE(v.note.find("no planes"), std::string::npos);
}

TEST(Valuation, GrossFloorSurchargeAndDefaults) {
  Building b = test::gable_house("h", Vec3::Zero());
  b.storeys = 2;
  Parcel parcel = test::square_parcel(0, "P4", Vec2(0, 0), 20);
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  r.buildings = {b};
  ValuationParams p = params();
  p.gross_floor_cost_per_m2 = 1;
  ParcelValuation v = value_parcel(parcel, r, p);
  ASSERT_EQ(v.items.size(), b.elements.size() + 1);
  EXPECT_EQ(v.items.back().element_type, "gross_floor");
  EXPECT_DOUBLE_EQ(v.items.back().area, 160);  // 80 m2 footprint x 2 storeys
  // The default config values the sample house at a plausible Indonesian level.
  ParcelValuation d = value_parcel(parcel, r, default_config().valuation);
  EXPECT_GT(d.building_value / 80, 1e6);  // > 1 million IDR per m2 footprint
  EXPECT_LT(d.building_value / 80, 5e6);
}
