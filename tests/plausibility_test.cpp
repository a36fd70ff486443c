// Plausibility (issue 35): inputs no survey can have are errors naming the
// file; a parcel the data do not reach fails alone; a model or a value
// outside the bounds is `suspect`, stored and reported with its reason,
// valued as land only, and the batch exits 3.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <regex>

#include "cadastre/batch/plausibility.h"
#include "core/config/config.h"
#include "core/error.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

std::string input_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no InputError";
}

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

// A copy of a LAS file with one header double replaced.
std::string patched_las(const std::string& from, const std::string& to, size_t offset, double v) {
  std::string b = read_bytes(from);
  std::memcpy(&b[offset], &v, sizeof v);
  std::ofstream(to, std::ios::binary) << b;
  return to;
}

// LAS header: Z scale at byte 147, Z offset at 171 (LAS 1.4 R15, table 3).
constexpr size_t kZScale = 131 + 16, kZOffset = 155 + 16;

TEST(Plausibility, LasScaleNegativeTinyAndHugeOffsetAreErrors) {
  const std::string dir = test::temp_dir("plaus_las");
  PointCloud c;
  for (int i = 0; i < 50; ++i) c.points.emplace_back(781800 + i, 9240000 + i, 790);
  c.classes.assign(50, 6);
  c.crs_wkt = wkt_from_epsg(32748);
  write_las(dir + "/good.las", c, 6, 4);
  EXPECT_EQ(read_point_cloud(dir + "/good.las").points.size(), 50u);
  const std::string neg = patched_las(dir + "/good.las", dir + "/neg.las", kZScale, -0.001);
  const std::string tiny = patched_las(dir + "/good.las", dir + "/tiny.las", kZScale, 1e-300);
  const std::string off = patched_las(dir + "/good.las", dir + "/off.las", kZOffset, 1e15);
  EXPECT_NE(input_error([&] { read_point_cloud(neg); }).find("neg.las: implausible Z scale -0.001"),
            std::string::npos);
  EXPECT_NE(input_error([&] { read_point_cloud(tiny); }).find("tiny.las: implausible Z scale 1e-300"),
            std::string::npos);
  EXPECT_NE(input_error([&] { read_point_cloud(off); }).find("off.las: implausible Z offset 1e+15"),
            std::string::npos);
}

TEST(Plausibility, CloudHeightsOffTheEarthAreLeftOutOrAnError) {
  PointCloud c;
  c.source = "cloud.xyz";
  c.points = {{0, 0, 790}, {1, 0, 1e15}, {2, 0, 791}};
  c.classes = {6, 2, 6};
  std::vector<std::string> warnings;
  keep_plausible_elevations(c, warnings);
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.classes, (std::vector<std::uint8_t>{6, 6}));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 points"), std::string::npos) << warnings[0];
  PointCloud all_off;
  all_off.source = "off.xyz";
  all_off.points = {{0, 0, 1e15}, {1, 0, 1e15 + 3}};
  EXPECT_NE(input_error([&] { keep_plausible_elevations(all_off, warnings); }).find("off.xyz: no point's height"),
            std::string::npos);
}

Building house(double ridge, int storeys, double volume) {
  Building b;
  b.id = "p_b1";
  b.terrain_z = 780;
  b.eave_height = ridge * 0.8;
  b.ridge_height = ridge;
  b.storeys = storeys;
  b.volume = volume;
  Element roof;
  roof.area = 120;
  b.elements.push_back(roof);
  return b;
}

ParcelStatus status_of(const Building& b, std::string* reason = nullptr) {
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  r.buildings.push_back(b);
  check_model(r, 0);
  if (reason) *reason = r.reason;
  return r.status;
}

TEST(Plausibility, AbsurdModelsAreSuspectRealOnesOk) {
  EXPECT_EQ(status_of(house(7.5, 2, 900)), ParcelStatus::Ok);
  EXPECT_EQ(status_of(house(828, 163, 9.0e6)), ParcelStatus::Ok);  // Burj Khalifa
  EXPECT_EQ(status_of(house(0.10, 1, 0.25)), ParcelStatus::Suspect);  // a ground patch (AHN3 03102)
  EXPECT_EQ(status_of(house(2.0, 1, 10)), ParcelStatus::Ok);          // a garden shed
  std::string why;
  // The findings: a LAS Z offset of 1e15, a DTM at -5000 m, at 1e30.
  EXPECT_EQ(status_of(house(2.7e9, 921490774, 1e12), &why), ParcelStatus::Suspect);
  EXPECT_NE(why.find("exceeds 1200 m"), std::string::npos) << why;
  EXPECT_EQ(status_of(house(5790, 1929, 4e6), &why), ParcelStatus::Suspect);
  Building low = house(7.5, 2, -2.2e31);
  EXPECT_EQ(status_of(low, &why), ParcelStatus::Suspect);
  EXPECT_NE(why.find("volume -2.2e+31"), std::string::npos) << why;
  Building buried = house(7.5, 2, 900);
  buried.terrain_z = 1e30;
  EXPECT_EQ(status_of(buried, &why), ParcelStatus::Suspect);
  EXPECT_NE(why.find("terrain at 1e+30 m"), std::string::npos) << why;
  Building sunk = house(7.5, 2, 900);
  sunk.eave_height = -0.01;  // AHN3 03038: a height layer meeting sloping ground
  EXPECT_EQ(status_of(sunk), ParcelStatus::Ok);
  sunk.eave_height = -4979;  // a DTM 5000 m too high
  EXPECT_EQ(status_of(sunk), ParcelStatus::Suspect);
}

Parcel square_parcel() {
  Parcel p;
  p.id = "P1";
  p.official_area = 200;
  p.shape = {{{{0, 0}, {20, 0}, {20, 10}, {0, 10}}, {}}};
  return p;
}

TEST(Plausibility, AnInfiniteValueIsNeverStoredAsZero) {
  ValuationParams vp = default_config().valuation;
  vp.unit_cost["roof"] = 1e308;  // what a config file may no longer say
  ParcelResult r;
  r.status = ParcelStatus::Ok;
  r.buildings.push_back(house(7.5, 2, 900));
  r.buildings[0].elements[0].type = ElementType::Roof;
  const ParcelValuation v = value_checked(square_parcel(), r, vp);
  EXPECT_EQ(r.status, ParcelStatus::Suspect);
  EXPECT_NE(r.reason.find("implausible value"), std::string::npos) << r.reason;
  EXPECT_TRUE(v.items.empty());
  EXPECT_DOUBLE_EQ(v.building_value, 0);
  EXPECT_DOUBLE_EQ(v.njop, v.land_value);
  EXPECT_GT(v.tax, 0);
  EXPECT_NE(v.note.find("land only"), std::string::npos) << v.note;
  vp.land_price[vp.default_zone] = 1e300;
  ParcelResult r2;
  const ParcelValuation v2 = value_checked(square_parcel(), r2, vp);
  EXPECT_EQ(r2.status, ParcelStatus::Suspect);
  EXPECT_TRUE(std::isnan(v2.njop) && std::isnan(v2.tax)) << v2.njop << " " << v2.tax;
  EXPECT_NE(v2.note.find("not valued"), std::string::npos) << v2.note;
}

TEST(Plausibility, ConfigRefusesAbsurdUnitCosts) {
  std::string text = default_config_toml();
  text = std::regex_replace(text, std::regex("\nroof = 550000"), "\nroof = 1e308");
  ASSERT_NE(text.find("roof = 1e308"), std::string::npos);
  const std::string path = test::temp_dir("plaus_cfg") + "/c.toml";
  std::ofstream(path) << text;
  const std::string e = input_error([&] { load_config(path); });
  EXPECT_NE(e.find("valuation.unit_cost.roof"), std::string::npos) << e;
}

}  // namespace
}  // namespace c3d
