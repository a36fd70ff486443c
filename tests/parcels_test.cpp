// Parcel layers through OGR: ids, attributes, orientation, repair, skipping.
#include <gtest/gtest.h>

#include <fstream>

#include "cadastre/parcels.h"
#include "core/io/crs.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

std::string feature(const std::string& props, const std::string& geometry) {
  return "{\"type\":\"Feature\",\"properties\":{" + props + "},\"geometry\":" + geometry + "}";
}

std::string geojson(const std::vector<std::string>& features) {
  std::string s =
      "{\"type\":\"FeatureCollection\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
      "\"urn:ogc:def:crs:EPSG::32748\"}},\"features\":[";
  for (size_t i = 0; i < features.size(); ++i) s += (i ? "," : "") + features[i];
  return s + "]}";
}

// Clockwise on purpose: the reader must return it counter-clockwise.
const char* kSquareCw =
    "{\"type\":\"Polygon\",\"coordinates\":[[[0,0],[0,10],[10,10],[10,0],[0,0]]]}";
const char* kBowtie =
    "{\"type\":\"Polygon\",\"coordinates\":[[[20,0],[30,10],[30,0],[20,10],[20,0]]]}";

std::string write(const std::string& dir, const std::string& name, const std::string& text) {
  std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(Parcels, GeoJsonIdsAttributesAndOrientation) {
  std::string path = write(test::temp_dir("parcels_json"), "p.geojson",
                           geojson({feature("\"NIB\":\"05764\",\"TIPEHAK\":\"Hak Milik\","
                                            "\"LUASTERTUL\":112",
                                            kSquareCw),
                                    feature("\"NIB\":\"\",\"TIPEHAK\":\"Hak Guna Bangunan\"",
                                            kSquareCw)}));
  ParcelFields fields;
  fields.id = "NIB";
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(path, fields, &warnings);
  ASSERT_EQ(layer.parcels.size(), 2u);
  EXPECT_EQ(epsg_of(layer.crs_wkt), 32748);
  EXPECT_EQ(layer.parcels[0].id, "05764");  // leading zero kept: ids are text
  EXPECT_EQ(layer.parcels[0].right_type, "Hak Milik");
  EXPECT_DOUBLE_EQ(layer.parcels[0].official_area, 112.0);
  EXPECT_EQ(layer.parcels[1].id, "1");  // empty NIB: feature id
  EXPECT_TRUE(std::isnan(layer.parcels[1].official_area));
  EXPECT_EQ(layer.parcels[1].index, 1);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("empty NIB"), std::string::npos) << warnings[0];
  const Ring2& outer = layer.parcels[0].shape.at(0).outer;
  EXPECT_EQ(outer.size(), 4u);  // closing vertex dropped
  EXPECT_GT(signed_area(outer), 0);
  EXPECT_DOUBLE_EQ(area(layer.parcels[0].shape), 100.0);
  EXPECT_TRUE(layer.parcels[0].repair_note.empty());
}

TEST(Parcels, DefaultIdIsFeatureIdAndMissingFieldIsAnError) {
  std::string path = write(test::temp_dir("parcels_fid"), "p.geojson",
                           geojson({feature("\"NIB\":\"1\"", kSquareCw),
                                    feature("\"NIB\":\"2\"", kSquareCw)}));
  ParcelLayer layer = read_parcels(path);
  EXPECT_EQ(layer.parcels[0].id, "0");
  EXPECT_EQ(layer.parcels[1].id, "1");
  ParcelFields fields;
  fields.id = "PARCEL_NO";
  try {
    read_parcels(path, fields);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("p.geojson"), std::string::npos) << m;
    EXPECT_NE(m.find("'PARCEL_NO' not found"), std::string::npos) << m;
  }
  // The built-in default id field is optional: a layer without it uses feature ids.
  fields.id_required = false;
  std::vector<std::string> warnings;
  ParcelLayer fallback = read_parcels(path, fields, &warnings);
  EXPECT_EQ(fallback.parcels[1].id, "1");
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.front().find("PARCEL_NO"), std::string::npos) << warnings.front();
}

TEST(Parcels, SelfIntersectingParcelIsRepairedAndNamed) {
  std::string path = write(test::temp_dir("parcels_bowtie"), "p.geojson",
                           geojson({feature("\"NIB\":\"A1\"", kSquareCw),
                                    feature("\"NIB\":\"B2\"", kBowtie)}));
  ParcelFields fields;
  fields.id = "NIB";
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(path, fields, &warnings);
  ASSERT_EQ(layer.parcels.size(), 2u);
  const Parcel& p = layer.parcels[1];
  EXPECT_NE(p.repair_note.find("Self-intersection"), std::string::npos) << p.repair_note;
  EXPECT_EQ(p.shape.size(), 2u);  // two triangles
  EXPECT_NEAR(area(p.shape), 50.0, 1e-9);
  EXPECT_EQ(validity_problem(p.shape), "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("parcel B2"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("p.geojson"), std::string::npos) << warnings[0];
}

TEST(Parcels, NonPolygonFeaturesSkippedWithWarning) {
  std::string path = write(
      test::temp_dir("parcels_mixed"), "p.geojson",
      geojson({feature("\"NIB\":\"A\"", "{\"type\":\"Point\",\"coordinates\":[1,2]}"),
               feature("\"NIB\":\"B\"", kSquareCw)}));
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(path, ParcelFields{}, &warnings);
  ASSERT_EQ(layer.parcels.size(), 1u);
  EXPECT_EQ(layer.parcels[0].index, 0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not a polygon, skipped"), std::string::npos) << warnings[0];
}

TEST(Parcels, CimahiShapefile) {
  C3D_REQUIRE_CIMAHI();
  ParcelFields fields;
  fields.id = "NIB";
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(test::cimahi_dir() + "/parcels.shp", fields, &warnings);
  ASSERT_EQ(layer.parcels.size(), 30u);
  EXPECT_EQ(epsg_of(layer.crs_wkt), 32748);
  EXPECT_EQ(layer.parcels[0].id, "05764");
  EXPECT_EQ(layer.parcels[0].right_type, "Hak Milik");
  EXPECT_DOUBLE_EQ(layer.parcels[0].official_area, 112.0);
  EXPECT_EQ(layer.parcels[2].right_type, "Hak Guna Bangunan");
  // Record 9 has a null NIB: its FID stands in, with a warning.
  EXPECT_EQ(layer.parcels[9].id, "9");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("feature 9"), std::string::npos);
  for (const Parcel& p : layer.parcels) {
    EXPECT_TRUE(p.repair_note.empty()) << p.id;
    // Map area close to the certified area (within 15 %).
    EXPECT_NEAR(area(p.shape), p.official_area, 0.15 * p.official_area) << p.id;
  }
}

}  // namespace
}  // namespace c3d
