// Plausibility end to end (issue 35): the CLI on a 6-parcel sample town with
// hostile DTMs and clouds; the store read with plain SQLite.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>

#include "core/io/dtm_io.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

// The sample town once per test binary: cloud.las, parcels.gpkg, dtm.tif.
const std::string& town() {
  static const std::string dir = [] {
    const std::string d = test::temp_dir("plaus_town");
    std::string out;
    EXPECT_EQ(test::run_cli("sample --out " + d + " --parcels 6 --seed 3", &out), 0) << out;
    return d;
  }();
  return dir;
}

// The town's DTM with its heights changed and/or its columns cut to `columns`.
std::string dtm_variant(const std::string& name, const std::function<void(Dtm&, int, int)>& change,
                        int columns = 0) {
  Dtm d = read_dtm(town() + "/dtm.tif");
  const int nx = columns > 0 ? columns : d.nx;
  GDALAllRegister();
  const std::string path = test::temp_dir("plaus_dtm") + "/" + name;
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), nx, d.ny, 1,
                                                                              GDT_Float32, nullptr);
  double gt[6] = {d.x0 - 0.5 * d.dx, d.dx, 0, d.y0 - 0.5 * d.dy, 0, d.dy};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromWkt(d.crs_wkt.c_str());
  ds->SetSpatialRef(&srs);
  std::vector<float> z(size_t(nx) * d.ny);
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < nx; ++i) z[size_t(j) * nx + i] = d.z[size_t(j) * d.nx + i];
  d.z = z;
  d.nx = nx;
  for (int j = 0; j < d.ny; ++j)
    for (int i = 0; i < nx; ++i) change(d, i, j);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, nx, d.ny, d.z.data(), nx, d.ny, GDT_Float32, 0, 0),
            CE_None);
  GDALClose(ds);
  return path;
}

struct BatchRun {
  int rc = 0;
  std::string output, out;
};

BatchRun batch(const std::string& name, const std::string& cloud, const std::string& dtm) {
  BatchRun r;
  r.out = test::temp_dir("plaus_out_" + name);
  r.rc = test::run_cli("batch --cloud " + cloud + " --parcels " + town() + "/parcels.gpkg --dtm " + dtm +
                           " --out " + r.out + " --formats obj",
                       &r.output);
  return r;
}

// status -> count, and reasons, from the store with plain SQLite.
std::map<std::string, int> statuses(const std::string& store, std::vector<std::string>* reasons = nullptr) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(store.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  std::map<std::string, int> n;
  if (sqlite3_prepare_v2(db, "SELECT status, coalesce(reason,'') FROM parcel_job", -1, &st, nullptr) == SQLITE_OK)
    while (sqlite3_step(st) == SQLITE_ROW) {
      ++n[reinterpret_cast<const char*>(sqlite3_column_text(st, 0))];
      if (reasons) reasons->push_back(reinterpret_cast<const char*>(sqlite3_column_text(st, 1)));
    }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return n;
}

std::string one(const std::string& store, const std::string& sql) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(store.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr);
  sqlite3_stmt* st = nullptr;
  std::string v = "(none)";
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
    v = sqlite3_column_text(st, 0) ? reinterpret_cast<const char*>(sqlite3_column_text(st, 0)) : "NULL";
  sqlite3_finalize(st);
  sqlite3_close(db);
  return v;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(PlausibilityBatch, TheSampleTownIsAllOk) {
  const BatchRun r = batch("plain", town() + "/cloud.las", town() + "/dtm.tif");
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_TRUE(has(r.output, "parcels: 6 ok, 0 empty, 0 failed, 0 suspect")) << r.output;
}

TEST(PlausibilityBatch, ADtmMissingOneParcelFailsThatParcelOnly) {
  // 100 of the 135 columns: the easternmost parcel reaches beyond.
  const BatchRun r = batch("crop", town() + "/cloud.las", dtm_variant("crop.tif", [](Dtm&, int, int) {}, 100));
  EXPECT_EQ(r.rc, 3) << r.output;
  std::vector<std::string> reasons;
  const auto n = statuses(r.out + "/cadastre.gpkg", &reasons);
  EXPECT_EQ(n.count("failed") ? n.at("failed") : 0, 1) << r.output;
  EXPECT_EQ(n.count("ok") ? n.at("ok") : 0, 5) << r.output;
  bool named = false;
  for (const auto& s : reasons) named = named || has(s, "crop.tif does not cover parcel");
  EXPECT_TRUE(named) << r.output;
  EXPECT_TRUE(has(r.output, "parcels: 5 ok, 0 empty, 1 failed, 0 suspect")) << r.output;
  const std::string note = one(r.out + "/cadastre.gpkg",
                               "SELECT v.note FROM vm_valuation v JOIN vm_valuationunit u ON u.fid=v.valuationunit_id "
                               "JOIN parcel_job j ON j.parcel_id=u.parcel_id WHERE j.status='failed'");
  EXPECT_TRUE(has(note, "land only")) << note;
}

TEST(PlausibilityBatch, ADtmOffTheEarthIsAnError) {
  for (float z : {-5000.0f, 1e30f}) {
    const BatchRun r = batch("dtm_off", town() + "/cloud.las",
                        dtm_variant("off.tif", [z](Dtm& d, int i, int j) { d.z[size_t(j) * d.nx + i] = z; }));
    EXPECT_EQ(r.rc, 1) << z << ": " << r.output;
    EXPECT_TRUE(has(r.output, "off.tif: no cell's height lies within -1000..10000 m")) << r.output;
  }
}

TEST(PlausibilityBatch, TerrainOffTheEarthUnderSomeParcelsMakesThemSuspect) {
  // The western 40 columns 5000 m down (the 1,929 storeys).
  const BatchRun r = batch("sunk", town() + "/cloud.las", dtm_variant("sunk.tif", [](Dtm& d, int i, int j) {
                        if (i < 40) d.z[size_t(j) * d.nx + i] -= 5000;
                      }));
  EXPECT_EQ(r.rc, 3) << r.output;
  const std::string store = r.out + "/cadastre.gpkg";
  const auto n = statuses(store);
  ASSERT_TRUE(n.count("suspect")) << r.output;
  EXPECT_EQ(n.at("suspect") + (n.count("ok") ? n.at("ok") : 0), 6) << r.output;
  auto summary = nlohmann::json::parse(std::ifstream(r.out + "/summary.json"));
  EXPECT_EQ(summary["parcels_suspect"], n.at("suspect"));
  EXPECT_EQ(one(store, "SELECT parcels_suspect FROM run"), std::to_string(n.at("suspect")));
  EXPECT_EQ(one(store, "SELECT count(*) FROM vm_valuation v JOIN vm_valuationunit u ON u.fid=v.valuationunit_id "
                      "JOIN parcel_job j ON j.parcel_id=u.parcel_id WHERE j.status='suspect' "
                      "AND v.building_value = 0 AND v.note LIKE 'land only, building not valued (suspect)%'"),
            std::to_string(n.at("suspect")));
  std::ifstream html(r.out + "/report.html");
  const std::string page((std::istreambuf_iterator<char>(html)), {});
  EXPECT_TRUE(has(page, "Suspect<b>" + std::to_string(n.at("suspect")))) << "no suspect card";
  EXPECT_TRUE(has(page, "lies outside -1000..10000 m")) << "no reason in the report";
}

TEST(PlausibilityBatch, ACloudFarFromEveryParcelIsAnError) {
  PointCloud c = read_point_cloud(town() + "/cloud.las");
  for (auto& p : c.points) p.x() += 5000;
  const std::string far = test::temp_dir("plaus_far") + "/far.las";
  write_las(far, c, 6, 4);
  const BatchRun r = batch("far", far, town() + "/dtm.tif");
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_TRUE(has(r.output, "far.las: no point lies within 50 m of any parcel")) << r.output;
}

TEST(PlausibilityBatch, HeightsOffTheEarthInAnyFormatAreAnError) {
  PointCloud c = read_point_cloud(town() + "/cloud.las");
  const std::string path = test::temp_dir("plaus_xyz") + "/up.xyz";
  std::ofstream f(path);
  f.precision(17);
  f << "x y z class\n";
  for (size_t i = 0; i < c.points.size(); i += 4)
    f << c.points[i].x() << " " << c.points[i].y() << " " << c.points[i].z() + 1e15 << " " << int(c.classes[i]) << "\n";
  f.close();
  const BatchRun r = batch("xyz", path, town() + "/dtm.tif");
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_TRUE(has(r.output, "up.xyz: no point's height lies within")) << r.output;
}

TEST(PlausibilityBatch, AStoreFromBeforeSuspectTakesSuspectParcels) {
  const BatchRun first = batch("migrate", town() + "/cloud.las", town() + "/dtm.tif");
  ASSERT_EQ(first.rc, 0) << first.output;
  const std::string store = first.out + "/cadastre.gpkg";
  // The job table as stores before this change wrote it.
  sqlite3* db = nullptr;
  sqlite3_open(store.c_str(), &db);
  ASSERT_EQ(sqlite3_exec(db,
                         "CREATE TABLE j2 (fid INTEGER PRIMARY KEY, parcel_id TEXT NOT NULL UNIQUE, layer_index INTEGER,"
                         " status TEXT NOT NULL CHECK (status IN ('pending','ok','empty','failed')), reason TEXT,"
                         " inputs_key TEXT, run_id INTEGER REFERENCES run(fid), roof_points INTEGER, wall_points"
                         " INTEGER, timings TEXT, updated DATETIME); INSERT INTO j2 SELECT * FROM parcel_job;"
                         " DROP TABLE parcel_job; ALTER TABLE j2 RENAME TO parcel_job;"
                         " ALTER TABLE run DROP COLUMN parcels_suspect;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(db);
  sqlite3_close(db);
  std::string output;
  const int rc = test::run_cli("batch --resume --cloud " + town() + "/cloud.las --parcels " + town() +
                                   "/parcels.gpkg --dtm " +
                                   dtm_variant("sunk2.tif", [](Dtm& d, int i, int j) {
                                     if (i < 40) d.z[size_t(j) * d.nx + i] -= 5000;
                                   }) +
                                   " --out " + first.out + " --formats obj",
                               &output);
  EXPECT_EQ(rc, 3) << output;
  EXPECT_GT(statuses(store)["suspect"], 0) << output;
}

}  // namespace
}  // namespace c3d
