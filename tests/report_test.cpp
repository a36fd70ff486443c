#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cadastre/report/report.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "tests/store_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

using namespace c3d;
namespace fs = std::filesystem;

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

using c3d::test::parse_csv;

// Every page of the report as one text (the figures live on the detail pages).
std::string all_pages(const BatchModel& m, const std::vector<ParcelValuation>& v, const ReportInfo& info = {}) {
  std::string s;
  for (const auto& f : report_files(m, v, info)) s += f.text;
  return s;
}

struct Sample {
  BatchModel model = test::sample_batch(2);
  std::vector<ParcelValuation> vals = value_batch(model, default_config().valuation);
};

}  // namespace

TEST(Report, HtmlHasParcelsFiguresChartsAndIsOffline) {
  Sample s;
  std::string html = all_pages(s.model, s.vals, {"Test batch", "unit test", ""});
  for (const auto& p : s.model.parcels) EXPECT_NE(html.find(p.id), std::string::npos) << p.id;
  EXPECT_NE(html.find("Test batch"), std::string::npos);
  EXPECT_NE(html.find("roof segmentation found no planar component"), std::string::npos);
  // Figures as printed: a roof area with its sigma, a parcel NJOP.
  const Element& roof = s.model.results[0].buildings[0].elements[0];
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f&nbsp;&plusmn;&nbsp;%.2f", roof.area, roof.sigma_area);
  EXPECT_NE(html.find(buf), std::string::npos) << buf;
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("#a0522d"), std::string::npos);  // roof colour used
  EXPECT_NE(html.find("Party wall"), std::string::npos);
  // Offline: nothing fetched from anywhere.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  // Scripts: the report's own 3D view, a relative path in the report.
  size_t scripts = 0;
  for (size_t at = html.find("<script src=\""); at != std::string::npos; at = html.find("<script src=\"", at + 1)) {
    const std::string src = html.substr(at + 13, html.find('"', at + 13) - at - 13);
    EXPECT_TRUE(src == "report/lib/c3d-viewer.js" || src == "../lib/c3d-viewer.js") << src;
    ++scripts;
  }
  EXPECT_GT(scripts, 1u);  // the summary's and a parcel page's
}

TEST(Report, ParcelPictureSortsFacesFarToNear) {
  Sample s;
  std::string svg = parcel_svg(s.model.parcels[0], s.model.results[0], s.model.frame);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  // The ground (farthest: lowest) is painted before the roof (nearest: highest).
  size_t ground = svg.find("fill=\"#4");  // dark grey ground shades start with #4
  size_t roof = svg.rfind("fill=\"#");
  EXPECT_LT(ground, roof);
  std::string empty = parcel_svg(s.model.parcels[2], s.model.results[2], s.model.frame);
  EXPECT_NE(empty.find("stroke-dasharray"), std::string::npos);  // parcel outline still drawn
}

TEST(Report, CsvMatchesModelAndValuation) {
  Sample s;
  auto rows = parse_csv(report_csv(s.model, s.vals));
  ASSERT_GT(rows.size(), 1u);
  const auto& head = rows[0];
  auto col = [&](const std::string& name) {
    return size_t(std::find(head.begin(), head.end(), name) - head.begin());
  };
  size_t parcels = 0, elements = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), head.size()) << "row " << i;
    if (rows[i][0] == "parcel") {
      const ParcelValuation& v = s.vals[parcels];
      EXPECT_EQ(rows[i][col("parcel_id")], v.parcel_id);
      EXPECT_NEAR(std::stod(rows[i][col("njop")]), v.njop, 0.01);
      EXPECT_NEAR(std::stod(rows[i][col("tax")]), v.tax, 0.01);
      EXPECT_EQ(rows[i][col("status")], to_string(s.model.results[parcels].status));
      ++parcels;
    } else {
      EXPECT_EQ(rows[i][0], "element");
      const Element& e = s.model.results[0].buildings[0].elements[elements % 8];
      EXPECT_NEAR(std::stod(rows[i][col("area_m2")]), e.area, 1e-3);
      EXPECT_FALSE(rows[i][col("amount")].empty());
      ++elements;
    }
  }
  EXPECT_EQ(parcels, 4u);
  EXPECT_EQ(elements, 16u);
}

TEST(Report, CliWritesReportFromStoreAndChromiumRendersIt) {
  Sample s;
  std::string dir = test::temp_dir("report_cli");
  {
    Store store;
    store.open(dir + "/cadastre.gpkg", "", s.model.epsg);
    store.begin_run("{}", {}, s.model.frame);
    for (size_t i = 0; i < s.model.parcels.size(); ++i)
      store.write_parcel(s.model.parcels[i], s.model.results[i], s.vals[i], s.model.frame, "k");
    store.end_run();
  }
  std::string out;
  ASSERT_EQ(test::run_cli("report --store " + dir + "/cadastre.gpkg --out " + dir + "/out", &out), 0)
      << out;
  std::string html = read(dir + "/out/report.html");
  std::string csv = read(dir + "/out/report.csv");
  EXPECT_NE(html.find(s.model.parcels[1].id), std::string::npos);
  // The report from the store equals the one from memory (figures survive the round trip).
  EXPECT_EQ(csv, report_csv(load_batch_model(dir + "/cadastre.gpkg"), s.vals));

  EXPECT_NE(test::run_cli("report --store " + dir + "/missing.gpkg --out " + dir, &out), 0);
  EXPECT_NE(test::run_cli("report --store " + dir + "/cadastre.gpkg --out " + dir +
                          "/o2 --config " + std::string(C3D_SOURCE_DIR) + "/config/cadastre3d.toml",
                          &out), 1) << out;

  // Rendering check with a real browser: runs wherever chromium is installed
  // (scripts/setup.sh installs it), skips elsewhere.
  const std::string chromium = test::chromium();
  C3D_NEED(!chromium.empty(), "no chromium for the rendering check");
  std::string png = dir + "/report.png";
  std::string cmd = "timeout 90 " + chromium + " --headless --no-sandbox --disable-gpu "
                    "--disable-dev-shm-usage --hide-scrollbars "
                    "--disable-background-networking --disable-component-update --disable-sync "
                    "--no-first-run --user-data-dir=" + dir + "/chrome --screenshot=" + png +
                    " --window-size=1280,2000 file://" + dir + "/out/report.html >/dev/null 2>&1";
  int rc = std::system(cmd.c_str());
  ASSERT_TRUE(fs::exists(png)) << "chromium rc " << rc;
  EXPECT_GT(fs::file_size(png), 50000u);  // a blank page is a few kB
}

TEST(Report, SaysWhichBuildingIsAnLod12PrismAndWhy) {
  // An officer must see that a building's areas come from the LoD 1.2 prism.
  Sample s;
  Building& b = s.model.results[0].buildings[0];
  b.lod = Lod::Lod12;
  b.lod_note = "LoD 2.2 invalid (not_closed): LoD 1.2 prism at the 70th percentile of its roof points";
  const std::string html = all_pages(s.model, s.vals);
  EXPECT_NE(html.find(b.id + ": LoD 1.2 (LoD 2.2 invalid (not_closed)"), std::string::npos);
  EXPECT_NE(html.find(s.model.results[1].buildings[0].id + ": LoD 2.2,"), std::string::npos);
  const auto rows = parse_csv(report_csv(s.model, s.vals));
  const size_t lod = size_t(std::find(rows[0].begin(), rows[0].end(), "lod") - rows[0].begin());
  ASSERT_LT(lod, rows[0].size());
  const size_t building = size_t(std::find(rows[0].begin(), rows[0].end(), "building_id") - rows[0].begin());
  int prisms = 0;
  for (size_t i = 1; i < rows.size(); ++i)
    if (rows[i][0] == "element") {
      EXPECT_EQ(rows[i][lod], rows[i][building] == b.id ? "1.2" : "2.2");
      prisms += rows[i][lod] == "1.2";
    }
  EXPECT_EQ(prisms, int(b.elements.size()));
}
