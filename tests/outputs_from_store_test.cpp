// What a batch writes after modelling comes from the store, not from
// BatchReport's model (issue 37: the model is no longer held): a report whose
// model is empty still gives every stored parcel's summary, report and exports.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cadastre/batch/outputs.h"
#include "core/config/config.h"
#include "tests/export_fixtures.h"
#include "tests/test_support.h"

using namespace c3d;
using namespace c3d::test;
namespace fs = std::filesystem;

TEST(OutputsFromStore, EverythingComesFromTheStoreNotFromTheReportsModel) {
  const BatchModel m = fixture::grid_batch(60);
  const std::string store = write_store(temp_dir("store") + "/cadastre.gpkg", m);
  BatchReport report;  // counts and timings only: no model
  report.parcels = m.parcels.size();
  const std::string out = temp_dir("out");
  const auto written = write_outputs(report, store, out, default_config(), {"cityjson", "obj"});
  std::ifstream f(out + "/summary.json");
  const auto s = nlohmann::json::parse(f);
  EXPECT_EQ(s["parcels_total"], 60);
  EXPECT_EQ(s["parcels"].size(), 60u);
  EXPECT_EQ(s["crs_epsg"], 32748);
  EXPECT_EQ(written.exports.size(), 1u + 60u);
  std::ifstream cj(out + "/buildings.city.json");
  EXPECT_EQ(nlohmann::json::parse(cj)["CityObjects"].size(), 60u);
  EXPECT_TRUE(fs::exists(out + "/report/parcels-002.html"));
  EXPECT_TRUE(fs::exists(out + "/preview/G-59.svg"));
}
