// Names and cells made from the data (issue 35): a parcel id never writes a
// file outside OUT, never loses its file and never shares one; CSV text cells
// cannot be run as formulas while numbers stay numbers; GDAL's DTM fill leaves
// no work file in the current directory.
#include <cpl_conv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/inotify.h>

#include <set>

#include "cadastre/report/report.h"
#include "core/config/config.h"
#include "core/io/dtm_io.h"
#include "tests/batch_e2e_support.h"
#include "tests/store_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

using namespace c3d;
using namespace e2e;

namespace {

// A sample town whose parcel ids are replaced by `ids` (in layer order), as GeoJSON.
std::string town_with_ids(const std::string& dir, const std::vector<std::string>& ids) {
  make_town(dir, int(ids.size()) + 2, 5, "--format geojson");
  std::string text = read_file(dir + "/parcels.geojson");
  for (size_t i = 0; i < ids.size(); ++i) {
    char sample_id[32];
    std::snprintf(sample_id, sizeof sample_id, "\"10280503%06zu\"", i + 1);
    const size_t at = text.find(sample_id);
    EXPECT_NE(at, std::string::npos) << sample_id;
    text.replace(at, std::string(sample_id).size(), nlohmann::json(ids[i]).dump());
  }
  std::ofstream(dir + "/parcels.geojson") << text;
  return "batch --cloud " + dir + "/cloud.las --parcels " + dir + "/parcels.geojson --dtm " + dir + "/dtm.tif";
}

std::set<std::string> files_under(const std::string& dir) {
  std::set<std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) s.insert(e.path().string());
  return s;
}

// Parcels of summary.json with at least one building: each has a preview and an OBJ.
size_t parcels_with_buildings(const std::string& out) {
  size_t n = 0;
  const nlohmann::json summary = nlohmann::json::parse(read_file(out + "/summary.json"));
  for (const auto& p : summary["parcels"])
    n += !p["buildings"].empty();
  return n;
}

// The batch on parcels named `ids` into dir/run/out; the files written outside OUT.
std::set<std::string> batch_with_ids(const std::string& dir, const std::vector<std::string>& ids) {
  const std::string cmd = town_with_ids(dir + "/town", ids);
  const std::string out = dir + "/run/out";
  fs::create_directories(out);
  const std::set<std::string> before = files_under(dir);
  std::string log;
  EXPECT_EQ(test::run_cli(cmd + " --out " + out + " --formats obj --quiet", &log), 0) << log;
  std::set<std::string> outside;
  for (const auto& f : files_under(dir))
    if (!before.count(f) && f.rfind(out + "/", 0) != 0) outside.insert(f);
  return outside;
}

void expect_one_file_per_parcel(const std::string& out) {
  const size_t want = parcels_with_buildings(out);
  EXPECT_GT(want, 0u);
  EXPECT_EQ(files_under(out + "/preview").size(), want) << "one preview per parcel with buildings";
  size_t objs = 0;  // each with its offset file (and .prj) beside it
  for (const auto& f : files_under(out + "/obj")) {
    if (fs::path(f).extension() != ".obj") continue;
    ++objs;
    EXPECT_TRUE(fs::exists(fs::path(f).replace_extension(".offset.json"))) << f;
  }
  EXPECT_EQ(objs, want) << "one OBJ per parcel with buildings";
}

}  // namespace

TEST(SafeNames, ARelativeIdCannotWriteOutsideOut) {
  const std::string dir = test::temp_dir("relative");
  const std::set<std::string> outside = batch_with_ids(dir, {"../../../x", "../../y", "..", "."});
  EXPECT_TRUE(outside.empty()) << *outside.begin();
  EXPECT_FALSE(fs::exists(fs::path(dir).parent_path() / "x.svg"));
  expect_one_file_per_parcel(dir + "/run/out");
}

TEST(SafeNames, AnAbsoluteIdCannotWriteAnywhere) {
  const std::string dir = test::temp_dir("absolute");
  const std::string target = dir + "/elsewhere/abs";
  fs::create_directories(dir + "/elsewhere");
  const std::set<std::string> outside = batch_with_ids(dir, {target});
  EXPECT_TRUE(outside.empty()) << *outside.begin();
  EXPECT_FALSE(fs::exists(target + ".svg"));
  expect_one_file_per_parcel(dir + "/run/out");
}

TEST(SafeNames, AnIdWithASlashKeepsItsPreviewAndNoTwoIdsShareAFile) {
  const std::string dir = test::temp_dir("slash");
  // "a/b", "a_b" and "a:b" would all become a_b by replacing characters.
  const std::set<std::string> outside = batch_with_ids(dir, {"a/b", "a_b", "a:b", "sub/dir/c"});
  EXPECT_TRUE(outside.empty()) << *outside.begin();
  expect_one_file_per_parcel(dir + "/run/out");
  for (const auto& f : files_under(dir + "/run/out/preview"))
    EXPECT_EQ(fs::path(f).parent_path(), fs::path(dir + "/run/out/preview")) << f;
}

TEST(SafeNames, CsvTextCellsCannotRunAsFormulasAndNumbersStayNumbers) {
  BatchModel m = test::sample_batch(1);  // parcels: ok, empty, failed
  const std::vector<std::string> ids = {"=1+1", "+SUM(A1)", "@cmd"};
  for (size_t i = 0; i < ids.size(); ++i) m.parcels[i].id = m.results[i].parcel_id = ids[i];
  m.results[2].reason = "-2+3, with a comma";
  m.results[1].reason = "\tTAB";
  m.parcels[0].right_type = "\rCR";
  m.results[0].buildings[0].elements[0].azimuth_deg = -3.5;
  const std::vector<ParcelValuation> vals = value_batch(m, default_config().valuation);
  const auto rows = test::parse_csv(report_csv(m, vals));
  ASSERT_GE(rows.size(), 5u);
  const auto& header = rows[0];
  auto col = [&](const char* name) { return size_t(std::find(header.begin(), header.end(), name) - header.begin()); };
  std::map<std::string, std::vector<std::string>> parcel_rows;
  const std::vector<std::string>* element = nullptr;
  for (const auto& r : rows) {
    if (r[col("record")] == "parcel") parcel_rows[r[col("parcel_id")]] = r;
    if (r[col("record")] == "element" && !element) element = &r;
  }
  for (const auto& id : ids) ASSERT_EQ(parcel_rows.count("'" + id), 1u) << id << " written raw";
  EXPECT_EQ(parcel_rows["'@cmd"][col("reason")], "'-2+3, with a comma");
  EXPECT_EQ(parcel_rows["'+SUM(A1)"][col("reason")], "'\tTAB");
  EXPECT_EQ(parcel_rows["'=1+1"][col("right_type")], "'\rCR");
  ASSERT_NE(element, nullptr);
  EXPECT_EQ((*element)[col("parcel_id")], "'=1+1");
  EXPECT_EQ((*element)[col("azimuth_deg")], "-3.50") << "a number keeps its sign, unquoted";
}

TEST(SafeNames, TheDtmFillLeavesNoWorkFileInTheTemporaryOrCurrentDirectory) {
  const std::string dir = test::temp_dir("fill");
  // GDAL names its work files in CPL_TMPDIR (else the current directory).
  CPLSetConfigOption("CPL_TMPDIR", dir.c_str());
  const int fd = inotify_init1(IN_NONBLOCK);
  ASSERT_GE(fd, 0);
  ASSERT_GE(inotify_add_watch(fd, dir.c_str(), IN_CREATE), 0);
  std::vector<Vec3> ground;  // a 60 m square of ground with a 20 m hole to fill
  for (int x = 0; x < 60; ++x)
    for (int y = 0; y < 60; ++y)
      if (x < 20 || x >= 40 || y < 20 || y >= 40) ground.emplace_back(x + 0.5, y + 0.5, 100 + 0.01 * x);
  const Dtm dtm = dtm_from_points(ground, "", 1.0);
  CPLSetConfigOption("CPL_TMPDIR", nullptr);
  char buf[4096];
  const ssize_t n = read(fd, buf, sizeof buf);
  close(fd);
  EXPECT_LE(n, 0) << "a work file was created in " << dir;
  EXPECT_GT(dtm.nodata_share, 0.05);
  for (float z : dtm.z) EXPECT_TRUE(std::isfinite(z));
}
