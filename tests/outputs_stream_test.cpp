// Outputs streamed from the store a page of parcels at a time (issue 37): the
// same bytes whatever the page size (1, 3, all), the same as the writers give
// from the whole model in memory, and nothing taken from BatchReport's model.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cadastre/batch/outputs.h"
#include "cadastre/report/report.h"
#include "cadastre/store/pages.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "ifc_citygml/export.h"
#include "tests/export_fixtures.h"
#include "tests/shared_store_checks.h"
#include "tests/test_support.h"

using namespace c3d;
using namespace c3d::test;
namespace fs = std::filesystem;

namespace {

// More parcels than two report pages (50 each) and than a small store page:
// attached houses whose shared wall's vertices sit on neighbouring parcels,
// grid houses whose building ids sort apart from the layer order ("G-10_b1"
// before "G-1_b1"), empty and failed parcels.
BatchModel town() {
  BatchModel m = fixture::sample_batch();
  const BatchModel grid = fixture::grid_batch(110);
  for (size_t i = 0; i < grid.parcels.size(); ++i) {
    Parcel p = grid.parcels[i];
    ParcelResult r = grid.results[i];
    p.index = r.parcel_index = int(m.parcels.size());
    for (auto& poly : p.shape)
      for (auto& v : poly.outer) v.y() += 100;
    for (auto& b : r.buildings) fixture::translate(b, {0, 100, 0});
    if (i % 7 == 3) r.buildings.clear(), r.status = ParcelStatus::Empty;
    if (i == 20) r.buildings.clear(), r.status = ParcelStatus::Failed, r.reason = "no roof points";
    m.parcels.push_back(p);
    m.results.push_back(r);
  }
  return m;
}

const std::string& town_store() {
  static const std::string path = write_store(temp_dir("town") + "/cadastre.gpkg", town());
  return path;
}

// Every file under dir (relative path -> bytes).
std::map<std::string, std::string> files_under(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) {
      std::ifstream f(e.path(), std::ios::binary);
      std::stringstream ss;
      ss << f.rdbuf();
      out[fs::relative(e.path(), dir).string()] = ss.str();
    }
  return out;
}

// The files of two folders are the same, byte for byte.
void expect_same_files(const std::string& a, const std::string& b) {
  const auto fa = files_under(a), fb = files_under(b);
  ASSERT_FALSE(fa.empty());
  ASSERT_EQ(fa.size(), fb.size()) << a << " vs " << b;
  for (const auto& [name, bytes] : fa) {
    ASSERT_TRUE(fb.count(name)) << name << " missing in " << b;
    EXPECT_TRUE(bytes == fb.at(name)) << name << " differs between " << a << " and " << b;
  }
}

const std::vector<std::string> kFormats = {"gml", "gml3", "cityjson", "cityjsonseq", "ifc", "obj"};
// And 3D Tiles, which carry the store's valuations: a model in memory has none.
const std::vector<std::string> kBatchFormats = {"gml", "gml3", "cityjson", "cityjsonseq", "ifc", "obj", "3dtiles"};

}  // namespace

TEST(OutputsStream, StoreHasMorePagesThanOne) {
  const StorePages pages(town_store(), 3);
  EXPECT_EQ(pages.parcel_count(), 114u);
  EXPECT_EQ(pages.page_count(), 38u);
  EXPECT_EQ(pages.page(1).parcels.size(), 3u);
  EXPECT_EQ(pages.page(37).parcels.size(), 3u);
  EXPECT_EQ(pages.page(1).parcels[1].id, "G-0");
  EXPECT_EQ(pages.header().epsg, 32748);
  EXPECT_TRUE(pages.header().parcels.empty());
}

TEST(OutputsStream, ExportsAreTheSameForEveryPageSizeAndAsFromTheWholeModel) {
  ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // IFC's time stamp
  const std::string whole = temp_dir("whole");
  export_formats(load_batch_model(town_store()), whole, kFormats);
  for (size_t size : {size_t(1), size_t(3), size_t(1000)}) {
    const std::string dir = temp_dir("pages" + std::to_string(size));
    size_t buildings = 0;
    const auto done = export_pages(StorePages(town_store(), size), dir, kFormats, &buildings);
    ASSERT_EQ(done.size(), kFormats.size());
    EXPECT_EQ(buildings, 4u + 110u - 16u - 1u);  // 16 of the grid empty, one failed
    expect_same_files(whole, dir);
  }
  // No spool stays behind.
  for (const auto& [name, bytes] : files_under(whole)) EXPECT_EQ(name.find(".part"), std::string::npos) << name;
}

// The default page size on a store that needs more than one page.
TEST(OutputsStream, DefaultPagesOfAStoreBiggerThanAPage) {
  const std::string store =
      write_store(temp_dir("big") + "/cadastre.gpkg", fixture::grid_batch(int(kOutputPageParcels) + 30));
  const StorePages pages(store);
  ASSERT_EQ(pages.page_count(), 2u);
  const std::string whole = temp_dir("whole"), paged = temp_dir("paged");
  export_formats(load_batch_model(store), whole, {"gml", "cityjson", "cityjsonseq"});
  export_pages(pages, paged, {"gml", "cityjson", "cityjsonseq"});
  expect_same_files(whole, paged);
}

TEST(OutputsStream, CityJsonObjectsInIdOrderWithSharedVertices) {
  const std::string dir = temp_dir("cj");
  export_pages(StorePages(town_store(), 1), dir, {"cityjson"});
  std::ifstream f(dir + "/buildings.city.json");
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["CityObjects"].size(), 97u);
  // The attached houses (two pages apart at a page size of 1) share their
  // party wall's vertices: one list, each vertex once.
  std::set<std::vector<long long>> seen;
  for (const auto& v : j["vertices"]) EXPECT_TRUE(seen.insert(v.get<std::vector<long long>>()).second);
  EXPECT_EQ(j["transform"]["translate"][0].get<double>(), 789012.0);
}

TEST(OutputsStream, ReportIsTheSameForEveryPageSizeAndAsFromTheWholeModel) {
  const Config cfg = default_config();
  const std::string whole = temp_dir("whole");
  write_report(whole, load_batch_model(town_store()), load_valuations(town_store()),
               store_report_info(town_store(), cfg, false, false));
  for (size_t size : {size_t(1), size_t(3), size_t(1000)}) {
    const std::string dir = temp_dir("pages" + std::to_string(size));
    write_report_from_store(StorePages(town_store(), size), dir, cfg);
    expect_same_files(whole, dir);
  }
  EXPECT_TRUE(fs::exists(whole + "/report/parcels-003.html"));
}

TEST(OutputsStream, RevaluedReportIsTheSameForEveryPageSize) {
  Config cfg = default_config();
  cfg.valuation.tax_rate *= 2;
  const std::string one = temp_dir("one"), all = temp_dir("all");
  write_report_from_store(StorePages(town_store(), 1), one, cfg, true);
  write_report_from_store(StorePages(town_store(), 1000), all, cfg, true);
  expect_same_files(one, all);
}

// write_outputs reads the store, not BatchReport's model: a report whose
// model is empty still gives every parcel's outputs.
TEST(OutputsStream, BatchOutputsComeFromTheStoreAndAreTheSameForEveryPageSize) {
  ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
  BatchReport report;
  report.parcels = 114;
  report.timings.ingest_s = 1.5;
  std::vector<std::string> dirs;
  for (size_t size : {size_t(1), size_t(3), size_t(1000)}) {
    dirs.push_back(temp_dir("out" + std::to_string(size)));
    const auto written =
        write_outputs(report, StorePages(town_store(), size), dirs.back(), default_config(), kBatchFormats);
    // one file per format (3dtiles: tileset.json, view.html and its script), an OBJ per parcel
    EXPECT_EQ(written.exports.size(), 6u + 2u + 97u);
  }
  expect_same_files(dirs[0], dirs[1]);
  expect_same_files(dirs[0], dirs[2]);
  for (const auto& [name, bytes] : files_under(dirs[0]))  // no spool published
    EXPECT_EQ(name.find(".part"), std::string::npos) << name;
  std::ifstream f(dirs[0] + "/summary.json");
  const auto s = nlohmann::json::parse(f);
  EXPECT_EQ(s["parcels_total"], 114);
  EXPECT_EQ(s["parcels_failed"], 1);
  EXPECT_EQ(s["parcels"].size(), 114u);
  EXPECT_EQ(s["parcels"][5]["parcel_id"], "G-1");
  EXPECT_EQ(s["parcels"][5]["parcel_index"], 5);
  EXPECT_EQ(s["crs_epsg"], 32748);
  EXPECT_EQ(files_under(dirs[0] + "/preview").size(), 97u);
  EXPECT_TRUE(fs::exists(dirs[0] + "/report/parcel/G-109.html"));
}

// summary.json's text is what one dump of the whole document gives (the
// streamed parcels spliced in at the same indentation).
TEST(OutputsStream, SummaryIsOneJsonDocumentAsDumped) {
  BatchReport report;
  const std::string dir = temp_dir("s");
  write_outputs(report, StorePages(town_store(), 7), dir, default_config(), {});
  std::ifstream f(dir + "/summary.json", std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  EXPECT_EQ(ss.str(), nlohmann::json::parse(ss.str()).dump(2) + "\n");
}

// Two writers of different --where selections share one GeoPackage (issue
// 37): their layer indices collide, the pages go by parcel id.
TEST(OutputsStream, PagesOfASharedStoreHoldTheCountedParcelsOnce) {
  const std::string dir = temp_dir("shared");
  expect_pages_fixed_once(dir + "/cadastre.gpkg", dir + "/report");
}
