// Issue 35, the parcel layer: which features are read (--layer, --where,
// --bbox), what is refused before any work (duplicate, non-UTF-8 and NUL ids,
// unknown override ids) and what is reported (overlapping parcels).
#include <gtest/gtest.h>

#include <fstream>

#include "cadastre/parcel_checks.h"
#include "cadastre/parcels.h"
#include "core/error.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

std::string square(double x, double y, double size = 10) {
  auto c = [](double a, double b) { return "[" + std::to_string(a) + "," + std::to_string(b) + "]"; };
  return "{\"type\":\"Polygon\",\"coordinates\":[[" + c(x, y) + "," + c(x + size, y) + "," + c(x + size, y + size) +
         "," + c(x, y + size) + "," + c(x, y) + "]]}";
}

// A GeoJSON layer in UTM 48S with one feature per (properties, geometry).
std::string write_layer(const std::string& name, const std::vector<std::pair<std::string, std::string>>& features) {
  std::string s = "{\"type\":\"FeatureCollection\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
                  "\"urn:ogc:def:crs:EPSG::32748\"}},\"features\":[";
  for (size_t i = 0; i < features.size(); ++i)
    s += std::string(i ? "," : "") + "{\"type\":\"Feature\",\"properties\":{" + features[i].first +
         "},\"geometry\":" + features[i].second + "}";
  const std::string path = test::temp_dir("layer") + "/" + name;
  std::ofstream(path, std::ios::binary) << s << "]}";
  return path;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

const std::vector<std::pair<std::string, std::string>> kThree = {
    {"\"NIB\":\"A\",\"KEL\":\"north\"", square(0, 0)},
    {"\"NIB\":\"B\",\"KEL\":\"north\"", square(20, 0)},
    {"\"NIB\":\"C\",\"KEL\":\"south\"", square(40, 0)}};

TEST(ParcelSource, WhereAndBboxSelectFeatures) {
  const std::string path = write_layer("three.geojson", kThree);
  EXPECT_EQ(read_parcels(path, ParcelSelection{"", "KEL = 'north'", {}}).parcels.size(), 2u);
  const ParcelLayer boxed = read_parcels(path, ParcelSelection{"", "", {35, -5, 60, 5}}, parcel_fields("NIB"));
  ASSERT_EQ(boxed.parcels.size(), 1u);
  EXPECT_EQ(boxed.parcels[0].id, "C");
  EXPECT_NE(error_of([&] { read_parcels(path, ParcelSelection{"", "NOSUCH = 1", {}}); })
                .find("--where \"NOSUCH = 1\" is not an OGR SQL filter on layer three (GDAL: \"NOSUCH\" not recognised"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_parcels(path, ParcelSelection{"", "KEL = 'east'", {}}); })
                .find("holds no polygon features (no parcels) that --where/--bbox select"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_parcels(path, ParcelSelection{"", "", {10, 0, 5, 1}}); }).find("xmin < xmax"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_parcels(path, ParcelSelection{"nope", "", {}}); })
                .find("has no layer 'nope' (layers: three (Polygon))"),
            std::string::npos);
}

TEST(ParcelSource, ConnectionStringsAreTriedAndMissingFilesNamed) {
  EXPECT_EQ(error_of([] { read_parcels("/no/such/parcels.gpkg"); }), "/no/such/parcels.gpkg: does not exist");
  const std::string pg = error_of([] { read_parcels("PG:dbname=c3d_no_such_db host=/nonexistent"); });
  EXPECT_NE(pg.find("not a vector source OGR can read (GDAL: "), std::string::npos) << pg;
  EXPECT_EQ(pg.find('\n'), std::string::npos) << pg;
}

TEST(ParcelSource, DuplicateIdsNameBothFeatures) {
  auto features = kThree;
  features[2].first = "\"NIB\":\"A\",\"KEL\":\"south\",\"KODE\":\"K3\"";
  const std::string path = write_layer("dup.geojson", features);
  EXPECT_EQ(error_of([&] { read_parcels(path, parcel_fields("NIB")); }),
            path + ": parcel id 'A' is held by features FID 0 and FID 2; ids must be unique (or name another id "
                   "field with --id-field NAME)");
}

TEST(ParcelSource, NonUtf8AndNulIdsAreRefused) {
  auto features = kThree;
  features[1].first = "\"NIB\":\"B\xE9\"";
  const std::string latin1 = write_layer("latin1.geojson", features);
  EXPECT_NE(error_of([&] { read_parcels(latin1, parcel_fields("NIB")); })
                .find("latin1.geojson: feature FID 1: parcel id 'B\\xE9' is not UTF-8 (byte 1)"),
            std::string::npos);
  features[1].first = "\"NIB\":\"B\xED\xA0\x80\"";  // a UTF-16 surrogate written as UTF-8
  const std::string surrogate = write_layer("surrogate.geojson", features);
  EXPECT_NE(error_of([&] { read_parcels(surrogate, parcel_fields("NIB")); }).find("is not UTF-8"), std::string::npos);
  features[1].first = "\"NIB\":\"B\\u0000X\"";
  const std::string nul = write_layer("nul.geojson", features);
  EXPECT_NE(error_of([&] { read_parcels(nul, parcel_fields("NIB")); }).find("nul.geojson: holds a NUL character at byte"),
            std::string::npos);
  features[1].first = "\"NIB\":\"B\\u00e9\"";  // the same letter, escaped: valid
  EXPECT_EQ(read_parcels(write_layer("escaped.geojson", features), parcel_fields("NIB")).parcels[1].id, "B\xC3\xA9");
}

// Issue 35: overlapping parcels valued one building twice, without a word.
TEST(ParcelSource, OverlapsAreFoundWithTheirArea) {
  auto features = kThree;
  features.push_back({"\"NIB\":\"D\"", square(5, 5, 10)});    // over A by 5 x 5
  features.push_back({"\"NIB\":\"E\"", square(30, 0, 10)});   // touches B and C only
  const ParcelLayer layer = read_parcels(write_layer("overlap.geojson", features), parcel_fields("NIB"));
  const std::vector<ParcelOverlap> overlaps = parcel_overlaps(layer);
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_EQ(overlaps[0].a, 0u);
  EXPECT_EQ(overlaps[0].b, 3u);
  EXPECT_NEAR(overlaps[0].area, 25.0, 1e-6);
  const std::vector<std::string> w = overlap_warnings(layer);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("parcels A and D overlap by 25.00 m2"), std::string::npos) << w[0];
}

TEST(ParcelSource, OverrideIdsMustNameParcels) {
  const ParcelLayer layer = read_parcels(write_layer("three.geojson", kThree), parcel_fields("NIB"));
  std::map<std::string, ParcelValuationOverride> overrides;
  overrides["B"] = {};
  std::vector<std::string> warnings;
  check_override_ids(overrides, layer, "c.toml", false, warnings);
  overrides["Z9"] = {};
  EXPECT_NE(error_of([&] { check_override_ids(overrides, layer, "c.toml", false, warnings); })
                .find("c.toml: [valuation.parcels] names parcel 'Z9', which is not in"),
            std::string::npos);
  check_override_ids(overrides, layer, "c.toml", true, warnings);  // a --where may have left it out
  ASSERT_EQ(warnings.size(), 1u);
}

}  // namespace
}  // namespace c3d
