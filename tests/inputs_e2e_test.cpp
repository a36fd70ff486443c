// Issue 35, inputs: the batch as a user runs it on real-world parcel sources:
// a Web-Mercator layer measured in UTM, layers picked from multi-layer and
// zipped sources, bad ids refused before any work with one line naming the
// file and the features, GDAL's own messages folded into that line.
#include <gdal_utils.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cpl_conv.h>

#include "cadastre/parcels.h"
#include "core/gdal_dataset.h"
#include "tests/batch_e2e_support.h"

namespace e2e {
namespace {

using json = nlohmann::json;

// ogr2ogr, through the library: `args` as on its command line.
void translate(const std::string& dst, const std::string& src, std::vector<std::string> args, bool update = false) {
  register_gdal_drivers();
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  GDALVectorTranslateOptions* opts = GDALVectorTranslateOptionsNew(argv.data(), nullptr);
  ASSERT_NE(opts, nullptr);
  GDALDatasetH in = GDALOpenEx(src.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr);
  ASSERT_NE(in, nullptr) << src;
  GDALDatasetH out_ds = update ? GDALOpenEx(dst.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE, nullptr, nullptr, nullptr)
                               : nullptr;
  int failed = 0;
  GDALDatasetH out = GDALVectorTranslate(update ? nullptr : dst.c_str(), out_ds, 1, &in, opts, &failed);
  GDALVectorTranslateOptionsFree(opts);
  ASSERT_EQ(failed, 0) << dst;
  GDALClose(out);
  GDALClose(in);
}

std::map<int, double> parcel_areas(const std::string& store) {
  Sqlite db(store);
  std::map<int, double> out;
  for (const Row& r : db.rows("SELECT layer_index, computed_area FROM la_spatialunit")) out[int(r[0].d)] = r[1].d;
  return out;
}

double total(const std::string& store, const std::string& column) {
  return Sqlite(store).number("SELECT sum(" + column + ") FROM building");
}

// Lines of output that are not the tool's own ("ERROR 1: ..." from GDAL).
int foreign_lines(const std::string& log) {
  int n = 0;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) n += !line.empty() && line.rfind("cadastre3d", 0) != 0;
  return n;
}

// Issue 35: a parcel layer in EPSG:3857 made Cimahi's areas 2 % too large.
TEST(InputsE2E, WebMercatorParcelsGiveTheAreasOfUtm) {
  const std::string dir = test::temp_dir("mercator"), town = dir + "/town";
  make_town(town, 6, 5);
  translate(town + "/parcels_3857.gpkg", town + "/parcels.gpkg", {"-t_srs", "EPSG:3857"});
  std::string log;
  ASSERT_EQ(test::run_cli(batch_args(town, dir + "/utm") + " --formats cityjson", &log) % 3, 0) << log;
  const std::string mercator = "batch --cloud " + town + "/cloud.las --parcels " + town +
                               "/parcels_3857.gpkg --dtm " + town + "/dtm.tif --out " + dir + "/mercator --formats cityjson";
  ASSERT_EQ(test::run_cli(mercator, &log) % 3, 0) << log;
  EXPECT_NE(log.find("Pseudo-Mercator (EPSG:3857) to WGS 84 / UTM zone 48S (EPSG:32748)"), std::string::npos) << log;
  const auto utm = parcel_areas(dir + "/utm/cadastre.gpkg"), merc = parcel_areas(dir + "/mercator/cadastre.gpkg");
  ASSERT_EQ(utm.size(), 6u);
  ASSERT_EQ(merc.size(), utm.size());
  for (const auto& [index, a] : utm) EXPECT_NEAR(merc.at(index) / a, 1.0, 1e-4) << "parcel " << index;
  for (const char* column : {"ground_area", "roof_area", "volume"})
    EXPECT_NEAR(total(dir + "/mercator/cadastre.gpkg", column) / total(dir + "/utm/cadastre.gpkg", column), 1.0, 1e-4)
        << column;
  const json summary = json::parse(read_file(dir + "/mercator/summary.json"));
  EXPECT_EQ(summary["areas_crs"], "EPSG:32748 (WGS 84 / UTM zone 48S)");
  EXPECT_NE(read_file(dir + "/mercator/report.html").find("in EPSG:32748 (WGS 84 / UTM zone 48S)"), std::string::npos);
  EXPECT_EQ(Sqlite(dir + "/mercator/cadastre.gpkg").number("SELECT crs_epsg FROM run"), 32748);
}

// Issue 35: a GeoPackage's first layer (roads) was read as the parcels; a
// /vsizip/ source was refused as "path does not exist".
TEST(InputsE2E, LayersAreChosenByNameAndAnyOgrSourceIsRead) {
  const std::string dir = test::temp_dir("layers"), town = dir + "/town";
  make_town(town, 6, 5);
  translate(dir + "/two.gpkg", town + "/parcels.gpkg", {"-nln", "roads", "-where", "fid <= 2"});
  translate(dir + "/two.gpkg", town + "/parcels.gpkg", {"-nln", "parcels"}, true);
  const std::string rest = " --cloud " + town + "/cloud.las --dtm " + town + "/dtm.tif --formats cityjson";
  std::string log;
  EXPECT_EQ(test::run_cli("batch --parcels " + dir + "/two.gpkg --out " + dir + "/a" + rest, &log), 1);
  EXPECT_NE(log.find("two.gpkg: holds 2 layers; name the parcel layer with --layer (layers: roads (Polygon), "
                     "parcels (Polygon))"),
            std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(dir + "/a/cadastre.gpkg"));
  // A zip of the GeoPackage, its parcels layer, two parcels by an OGR SQL filter.
  void* zip = CPLCreateZip((dir + "/parcels.zip").c_str(), nullptr);
  ASSERT_NE(zip, nullptr);
  ASSERT_EQ(CPLCreateFileInZip(zip, "two.gpkg", nullptr), CE_None);
  const std::string bytes = read_file(dir + "/two.gpkg");
  ASSERT_EQ(CPLWriteFileInZip(zip, bytes.data(), int(bytes.size())), CE_None);
  CPLCloseFileInZip(zip);
  CPLCloseZip(zip);
  const std::string source = "/vsizip/" + dir + "/parcels.zip/two.gpkg";
  const int rc = test::run_cli("batch --parcels " + source + " --layer parcels --where \"fid IN (2, 5)\" --out " +
                                   dir + "/b" + rest, &log);
  ASSERT_EQ(rc % 3, 0) << log;
  const json summary = json::parse(read_file(dir + "/b/summary.json"));
  ASSERT_EQ(summary["parcels_total"], 2);
  const ParcelLayer all = read_parcels(town + "/parcels.gpkg", default_config().fields);
  EXPECT_EQ(summary["parcels"][0]["parcel_id"], all.parcels[1].id);
  EXPECT_EQ(summary["parcels"][1]["parcel_id"], all.parcels[4].id);
}

// Issue 35: two features with one id: "2 parcels", the store held 1 and a building was lost.
TEST(InputsE2E, DuplicateIdsStopTheBatchBeforeWorkAndIdFieldPicksAnother) {
  const std::string dir = test::temp_dir("dup"), town = dir + "/town";
  make_town(town, 6, 5);
  const ParcelLayer all = read_parcels(town + "/parcels.gpkg", default_config().fields);
  // NIB of the fourth parcel set to the second's; a unique code in another field.
  translate(dir + "/dup.gpkg", town + "/parcels.gpkg",
            {"-dialect", "SQLite", "-sql",
             "SELECT CASE WHEN fid = 4 THEN '" + all.parcels[1].id + "' ELSE NIB END AS NIB, "
             "'K' || fid AS KODE, geom FROM parcels",
             "-nln", "parcels"});
  const std::string rest = " --cloud " + town + "/cloud.las --dtm " + town + "/dtm.tif --formats cityjson";
  std::string log;
  EXPECT_EQ(test::run_cli("batch --parcels " + dir + "/dup.gpkg --out " + dir + "/a" + rest, &log), 1);
  EXPECT_NE(log.find("dup.gpkg: parcel id '" + all.parcels[1].id + "' is held by features FID 2 and FID 4"),
            std::string::npos)
      << log;
  EXPECT_EQ(foreign_lines(log), 0) << log;
  EXPECT_FALSE(fs::exists(dir + "/a/summary.json"));
  ASSERT_EQ(test::run_cli("batch --parcels " + dir + "/dup.gpkg --id-field KODE --where \"fid IN (2, 4)\" --out " +
                              dir + "/b" + rest, &log) % 3, 0) << log;
  Sqlite db(dir + "/b/cadastre.gpkg");
  EXPECT_EQ(db.number("SELECT count(*) FROM la_spatialunit"), 2);
  EXPECT_EQ(db.text("SELECT group_concat(parcel_id) FROM (SELECT parcel_id FROM la_spatialunit ORDER BY 1)"), "K2,K4");
}

// Issue 35: GDAL printed 9-21 "ERROR 1:" lines before the tool's message, and a
// truncated .shp went on with its unread features skipped as "no geometry".
TEST(InputsE2E, ATruncatedShapefileIsOneLineNamingTheFeature) {
  C3D_REQUIRE_CIMAHI();
  const std::string dir = test::temp_dir("truncated"), c = test::cimahi_dir();
  for (const char* ext : {".shx", ".dbf", ".prj"}) fs::copy_file(c + "/parcels" + ext, dir + "/parcels" + ext);
  const std::string shp = read_file(c + "/parcels.shp");
  std::ofstream(dir + "/parcels.shp", std::ios::binary) << shp.substr(0, 3000);
  std::string log;
  EXPECT_EQ(test::run_cli("batch --cloud " + c + "/cimahi.las --dtm " + c + "/dtm.tif --parcels " + dir +
                              "/parcels.shp --out " + dir + "/out --quiet",
                          &log),
            1);
  EXPECT_EQ(foreign_lines(log), 0) << log;
  EXPECT_NE(log.find("parcels.shp: feature FID 13 (record 13) cannot be read: Error in fread()"), std::string::npos)
      << log;
}

// Issue 35: a per-parcel override for a parcel not in the layer was ignored.
TEST(InputsE2E, AnOverrideForAnUnknownParcelIsAnError) {
  const std::string dir = test::temp_dir("override"), town = dir + "/town";
  make_town(town, 3, 5);
  std::ofstream(dir + "/c.toml") << default_config_toml() << "\n[valuation.parcels.\"NO-SUCH-PARCEL\"]\nage_years = 10\n";
  std::string log;
  EXPECT_EQ(test::run_cli(batch_args(town, dir + "/out") + " --config " + dir + "/c.toml", &log), 1);
  EXPECT_NE(log.find("c.toml: [valuation.parcels] names parcel 'NO-SUCH-PARCEL', which is not in"), std::string::npos)
      << log;
}

// Issue 35: a Latin-1 id ended in json.exception.type_error.316 and a 0-byte
// summary.json; a NUL cut an id short without a word.
TEST(InputsE2E, NonUtf8AndNulIdsAreOneLineAndWriteNothing) {
  const std::string dir = test::temp_dir("text"), town = dir + "/town";
  make_town(town, 3, 5);
  const std::string rest = " --cloud " + town + "/cloud.las --dtm " + town + "/dtm.tif --formats cityjson";
  for (const std::string& id : {std::string("P\xE9") + "1", std::string("P\\u0000X")}) {
    fs::remove(dir + "/p.geojson");
    translate(dir + "/p.geojson", town + "/parcels.gpkg",
              {"-f", "GeoJSON", "-dialect", "SQLite", "-sql",
               "SELECT CASE WHEN fid = 2 THEN 'MARK' ELSE NIB END AS NIB, geom FROM parcels"});
    std::string text = read_file(dir + "/p.geojson");
    text.replace(text.find("MARK"), 4, id);
    std::ofstream(dir + "/p.geojson", std::ios::binary) << text;
    std::string log;
    fs::remove_all(dir + "/out");
    EXPECT_EQ(test::run_cli("batch --parcels " + dir + "/p.geojson --out " + dir + "/out" + rest, &log), 1) << log;
    EXPECT_EQ(foreign_lines(log), 0) << log;
    EXPECT_NE(log.find("p.geojson: "), std::string::npos) << log;
    EXPECT_TRUE(log.find("is not UTF-8") != std::string::npos || log.find("holds a NUL character") != std::string::npos)
        << log;
    EXPECT_FALSE(fs::exists(dir + "/out/summary.json"));
  }
}

// Issue 35: overlapping parcels valued one building twice, without a word.
TEST(InputsE2E, OverlappingParcelsAreReportedWithTheirArea) {
  const std::string dir = test::temp_dir("overlap"), town = dir + "/town";
  make_town(town, 3, 5);
  translate(dir + "/p.gpkg", town + "/parcels.gpkg",
            {"-dialect", "SQLite", "-sql",
             "SELECT NIB, CASE WHEN fid = 2 THEN ST_Buffer(geom, 3) ELSE geom END AS geom FROM parcels", "-nln", "p"});
  const ParcelLayer layer = read_parcels(dir + "/p.gpkg", default_config().fields);
  std::string log;
  const int rc = test::run_cli("batch --parcels " + dir + "/p.gpkg --cloud " + town + "/cloud.las --dtm " + town +
                                   "/dtm.tif --formats cityjson --out " + dir + "/out",
                               &log);
  ASSERT_EQ(rc % 3, 0) << log;
  EXPECT_NE(log.find("p.gpkg: parcels " + layer.parcels[0].id + " and " + layer.parcels[1].id + " overlap by "),
            std::string::npos)
      << log;
}

// Issue 37: two writers of disjoint --where halves share one store, so their
// layer indices collide. Each parcel is in the outputs once, and a writer's
// fit figures are its own layer's, whatever the other half left in the store.
TEST(InputsE2E, TwoWhereHalvesShareOneStore) {
  const std::string dir = test::temp_dir("halves"), town = dir + "/town";
  make_town(town, 12, 3, "--density 10 --wall-density 5");
  const std::string a = " --where \"NIB<='10280503000006'\"", b = " --where \"NIB>'10280503000006'\"";
  const std::string shared = batch_args(town, dir + "/shared") + " --formats cityjson --quiet";
  std::string log;
  ASSERT_EQ(test::run_cli(shared + a, &log) % 3, 0) << log;
  ASSERT_EQ(test::run_cli(shared + b + " --resume", &log) % 3, 0) << log;
  ASSERT_EQ(test::run_cli(batch_args(town, dir + "/alone") + " --formats cityjson --quiet" + b, &log) % 3, 0) << log;
  const json in_shared = json::parse(read_file(dir + "/shared/summary.json"));
  const json alone = json::parse(read_file(dir + "/alone/summary.json"));
  for (const char* fit : {"any_model_roof_deviation", "any_model_wall_deviation", "roof_ruler", "wall_ruler"})
    for (const char* figure : {"n", "max", "rmse"})
      EXPECT_NEAR(in_shared[fit][figure].get<double>(), alone[fit][figure].get<double>(), 1e-9) << fit << " " << figure;
  // The batch's outputs, `report` and `export` from the store: the 12 parcels once each.
  ASSERT_EQ(test::run_cli("report --store " + dir + "/shared/cadastre.gpkg --out " + dir + "/report", &log), 0) << log;
  ASSERT_EQ(test::run_cli("export --store " + dir + "/shared/cadastre.gpkg --out " + dir + "/export --formats cityjson",
                          &log), 0) << log;
  for (const std::string& csv : {dir + "/shared/report.csv", dir + "/report/report.csv"}) {
    std::map<std::string, int> parcels;
    for (const auto& row : test::parse_csv(read_file(csv)))
      if (row[0] == "parcel") ++parcels[row[1]];
    EXPECT_EQ(parcels.size(), 12u) << csv;
    for (const auto& [id, n] : parcels) EXPECT_EQ(n, 1) << id << " in " << csv;
  }
  EXPECT_EQ(in_shared["parcels"].size(), 12u);
  EXPECT_EQ(read_file(dir + "/export/buildings.city.json"), read_file(dir + "/shared/buildings.city.json"));
}

}  // namespace
}  // namespace e2e
