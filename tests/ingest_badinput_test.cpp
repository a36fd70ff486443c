// Bad input at ingest: every case must throw InputError naming the file (or the
// parcel) and the problem, in one line.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <functional>
#include <limits>

#include "cadastre/parcels.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/error.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

void expect_input_error(const std::function<void()>& f, const std::string& file,
                        const std::string& problem) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected '" << problem << "'";
  } catch (const InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(file), std::string::npos) << "file not named: " << m;
    EXPECT_NE(m.find(problem), std::string::npos) << "problem not said: " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "not one line: " << m;
  }
}

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// A valid LAS 1.4 format 6 file of 100 points; tests damage copies of it.
std::string good_las(const std::string& dir) {
  PointCloud c;
  for (int i = 0; i < 100; ++i) c.points.emplace_back(781800 + i, 9240000 + i, 790);
  c.classes.assign(100, 6);
  c.crs_wkt = wkt_from_epsg(32748);
  std::string path = dir + "/good.las";
  write_las(path, c, 6, 4);
  return path;
}

TEST(BadInput, TruncatedLasHeader) {
  std::string dir = test::temp_dir("bad_trunc_header");
  std::string path = dir + "/cut.las";
  write_bytes(path, read_bytes(good_las(dir)).substr(0, 150));
  expect_input_error([&] { read_point_cloud(path); }, "cut.las", "truncated LAS file");
}

TEST(BadInput, TruncatedLasPoints) {
  std::string dir = test::temp_dir("bad_trunc_points");
  std::string bytes = read_bytes(good_las(dir));
  std::string path = dir + "/cut.las";
  write_bytes(path, bytes.substr(0, bytes.size() - 45));  // 1.5 records missing
  expect_input_error([&] { read_point_cloud(path); }, "cut.las",
                     "header point count 100 is larger than the file holds (98 complete points)");
}

TEST(BadInput, LasPointCountLargerThanFile) {
  std::string dir = test::temp_dir("bad_count");
  std::string bytes = read_bytes(good_las(dir));
  uint64_t count = 1000000;
  std::memcpy(&bytes[247], &count, 8);
  std::string path = dir + "/count.las";
  write_bytes(path, bytes);
  expect_input_error([&] { read_point_cloud(path); }, "count.las",
                     "header point count 1000000 is larger than the file holds");
}

TEST(BadInput, UnknownLasPointFormat) {
  std::string dir = test::temp_dir("bad_format");
  std::string bytes = read_bytes(good_las(dir));
  bytes[104] = 11;
  std::string path = dir + "/f11.las";
  write_bytes(path, bytes);
  expect_input_error([&] { read_point_cloud(path); }, "f11.las", "unknown LAS point format 11");
}

TEST(BadInput, NaNCoordinates) {
  std::string dir = test::temp_dir("bad_nan");
  std::string bytes = read_bytes(good_las(dir));
  double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&bytes[131], &nan, 8);  // x scale factor
  write_bytes(dir + "/nan.las", bytes);
  expect_input_error([&] { read_point_cloud(dir + "/nan.las"); }, "nan.las", "NaN/inf");

  write_bytes(dir + "/nan.xyz", "1 2 3\n4 nan 6\n");
  expect_input_error([&] { read_point_cloud(dir + "/nan.xyz"); }, "nan.xyz",
                     "NaN/inf coordinate at line 2");

  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n";
  double v[6] = {1, 2, 3, 4, 5, std::numeric_limits<double>::infinity()};
  ply.append(reinterpret_cast<const char*>(v), sizeof v);
  write_bytes(dir + "/inf.ply", ply);
  expect_input_error([&] { read_point_cloud(dir + "/inf.ply"); }, "inf.ply",
                     "NaN/inf coordinate at point 1");
}

TEST(BadInput, EmptyFiles) {
  std::string dir = test::temp_dir("bad_empty");
  for (const char* name : {"e.las", "e.ply", "e.xyz", "e.csv", "e.pcd"}) {
    write_bytes(dir + "/" + name, "");
    expect_input_error([&] { read_point_cloud(dir + "/" + name); }, name, "empty file");
  }
  write_bytes(dir + "/comments.xyz", "# only a comment\n");
  expect_input_error([&] { read_point_cloud(dir + "/comments.xyz"); }, "comments.xyz",
                     "no points");
}

TEST(BadInput, NotALasFileAndLaz) {
  std::string dir = test::temp_dir("bad_notlas");
  write_bytes(dir + "/text.las", "x y z\n1 2 3\n");
  expect_input_error([&] { read_point_cloud(dir + "/text.las"); }, "text.las",
                     "not a LAS file");
  write_bytes(dir + "/c.laz", "LASF");  // LAZ is read now (tests/laz_test.cpp): a LAS header first
  expect_input_error([&] { read_point_cloud(dir + "/c.laz"); }, "c.laz", "truncated LAS file");
  expect_input_error([&] { read_point_cloud(dir + "/missing.las"); }, "missing.las",
                     "file not found");
  write_bytes(dir + "/short.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n1234");
  expect_input_error([&] { read_point_cloud(dir + "/short.ply"); }, "short.ply",
                     "truncated PLY file");
}

std::string points_only_layer(const std::string& dir) {
  std::string path = dir + "/points.geojson";
  write_bytes(path,
              "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":"
              "{\"NIB\":\"1\"},\"geometry\":{\"type\":\"Point\",\"coordinates\":[1,2]}}]}");
  return path;
}

TEST(BadInput, ParcelLayerWithoutPolygons) {
  std::string path = points_only_layer(test::temp_dir("bad_nopoly"));
  expect_input_error([&] { read_parcels(path); }, "points.geojson", "no polygon");
}

TEST(BadInput, SelfIntersectingParcelRepairedAndNamed) {
  std::string dir = test::temp_dir("bad_bowtie");
  std::string path = dir + "/bowtie.geojson";
  write_bytes(path,
              "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":"
              "{\"NIB\":\"X9\"},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":"
              "[[[0,0],[10,10],[10,0],[0,10],[0,0]]]}}]}");
  ParcelFields fields;
  fields.id = "NIB";
  std::vector<std::string> warnings;
  ParcelLayer layer = read_parcels(path, fields, &warnings);
  ASSERT_EQ(layer.parcels.size(), 1u);
  EXPECT_NE(layer.parcels[0].repair_note.find("Self-intersection at (5.000 5.000)"),
            std::string::npos)
      << layer.parcels[0].repair_note;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("bowtie.geojson: parcel X9"), std::string::npos) << warnings[0];
}

TEST(BadInput, UnrepairableParcelRejectedAndNamed) {
  std::string dir = test::temp_dir("bad_flat");
  std::string path = dir + "/flat.geojson";
  write_bytes(path,
              "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":"
              "{\"NIB\":\"Z1\"},\"geometry\":{\"type\":\"Polygon\",\"coordinates\":"
              "[[[0,0],[5,0],[10,0],[0,0]]]}}]}");
  ParcelFields fields;
  fields.id = "NIB";
  expect_input_error([&] { read_parcels(path, fields); }, "flat.geojson: parcel Z1 (record 0)",
                     "invalid polygon");
}

TEST(BadInput, CrsMismatch) {
  ParcelLayer parcels;
  parcels.source = "parcels.shp";
  parcels.crs_wkt = wkt_from_epsg(32748);
  std::vector<PointCloud> clouds;
  Dtm dtm;
  dtm.source = "dtm_zone49.tif";
  dtm.crs_wkt = wkt_from_epsg(32749);
  expect_input_error([&] { reconcile_crs(parcels, clouds, &dtm); }, "dtm_zone49.tif",
                     "CRS WGS 84 / UTM zone 49S (EPSG:32749) differs from the working CRS WGS 84 / "
                     "UTM zone 48S (EPSG:32748)");
  PointCloud local;
  local.source = "local.las";
  local.crs_wkt = "LOCAL_CS[\"site grid\",UNIT[\"metre\",1]]";
  local.points = {{1, 2, 3}};
  clouds.push_back(local);
  expect_input_error([&] { reconcile_crs(parcels, clouds); }, "local.las",
                     "cannot reproject from site grid (no EPSG code) to WGS 84 / UTM zone 48S");
}

TEST(BadInput, DtmNotCoveringParcels) {
  std::vector<Vec3> ground = {{0, 0, 1}, {10, 10, 1}};
  Dtm dtm = dtm_from_points(ground, "", 1.0, DtmCell::Min, "small_dtm.tif");
  ParcelLayer layer;
  layer.source = "parcels.gpkg";
  Parcel p;
  p.id = "05764";
  p.shape = {{{{5, 5}, {15, 5}, {15, 15}, {5, 15}}, {}}};
  layer.parcels.push_back(p);
  expect_input_error([&] { check_dtm_covers(dtm, layer); }, "small_dtm.tif",
                     "does not cover parcel 05764");
}

TEST(BadInput, UnreadableRaster) {
  std::string dir = test::temp_dir("bad_raster");
  write_bytes(dir + "/dtm.tif", "not a tiff");
  expect_input_error([&] { read_dtm(dir + "/dtm.tif"); }, "dtm.tif", "not a raster");
}

TEST(BadInput, CliPrintsOneErrorLineAndFails) {
  std::string dir = test::temp_dir("bad_cli");
  write_bytes(dir + "/e.las", "");
  std::string out;
  EXPECT_EQ(test::run_cli("info " + dir + "/e.las", &out), 1);
  EXPECT_EQ(out, "cadastre3d: error: " + dir + "/e.las: empty file\n");
  EXPECT_EQ(test::run_cli("clip --cloud " + dir + "/e.las --parcels " +
                              points_only_layer(dir),
                          &out),
            1);
  EXPECT_NE(out.find("no polygon"), std::string::npos) << out;
}

}  // namespace
}  // namespace c3d
