// The report of a sample town batch, read as files: every link resolves, the
// totals equal the store, the pages stay small, and headless Chromium renders
// the summary and prints a parcel's page on one A4 sheet, draws the 3D views
// and shows the store's area of an element clicked in one.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "tests/report_checks.h"
#include "tests/test_support.h"

using namespace c3d::test;
namespace fs = std::filesystem;

namespace {

// Parcels of the town: two detail pages, small enough for the test suite
// (scripts/report_town.sh does 800 parcels).
constexpr int kParcels = 60;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// PDF page objects ("/Type /Page", not "/Pages").
int pdf_pages(const std::string& pdf) {
  static const std::regex re("/Type\\s*/Page[^s]");
  return int(std::distance(std::sregex_iterator(pdf.begin(), pdf.end(), re), std::sregex_iterator()));
}

struct Town {
  std::string dir, out;
  int rc = -1;
  std::string log;
};

const Town& town() {
  static Town t = [] {
    Town t;
    t.dir = temp_dir("report_town");
    t.out = t.dir + "/out";
    if (run_cli("sample --out " + t.dir + "/town --parcels " + std::to_string(kParcels) + " --seed 5", &t.log) != 0)
      return t;
    t.rc = run_cli("batch --quiet --cloud " + t.dir + "/town/cloud.las --parcels " + t.dir +
                   "/town/parcels.gpkg --dtm " + t.dir + "/town/dtm.tif --out " + t.out + " --formats obj",
                   &t.log);
    return t;
  }();
  return t;
}

// The parcel page of the most table rows.
std::string page_of_most_rows(const Town& t) {
  std::string page;
  size_t most = 0;
  for (const auto& e : fs::directory_iterator(t.out + "/report/parcel")) {
    const std::string html = read(e.path());
    size_t rows = 0;
    for (size_t at = html.find("<tr>"); at != std::string::npos; at = html.find("<tr>", at + 1)) ++rows;
    if (rows > most) most = rows, page = e.path().string();
  }
  return page;
}

}  // namespace

TEST(ReportTown, EveryLinkOfEveryPageResolves) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  std::set<std::string> pages;
  for (const auto& e : fs::recursive_directory_iterator(t.out))
    if (e.path().extension() == ".html") pages.insert(fs::relative(e.path(), t.out).generic_string());
  EXPECT_EQ(pages.size(), 1u + 2u + size_t(kParcels));
  size_t links = 0;
  for (const std::string& page : pages) {
    const std::string html = read(fs::path(t.out) / page);
    EXPECT_LT(html.size(), page == "report.html" ? 600'000u : 800'000u) << page;
    for (const std::string& h : hrefs(html)) {
      const std::string target = resolve(page, h);
      EXPECT_TRUE(pages.count(target.substr(0, target.find('#')))) << page << " -> " << h;
      ++links;
    }
  }
  EXPECT_GT(links, 4u * kParcels);  // map, table, page, neighbours
  EXPECT_TRUE(fs::exists(t.out + "/report.csv"));
}

// The run's line names its inputs by role, as the store's run_input has them.
TEST(ReportTown, NamesTheRunsInputsByRole) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  const std::string html = read(t.out + "/report.html");
  EXPECT_NE(html.find("inputs cloud cloud.las, parcels parcels.gpkg, dtm dtm.tif, each with its SHA-256"),
            std::string::npos);
}

TEST(ReportTown, TotalsEqualTheStore) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  const std::string db = t.out + "/cadastre.gpkg";
  auto total = row_cells(read(t.out + "/report.html"), "total");
  EXPECT_EQ(c3d::test::cell_number(total["parcels"]), kParcels);
  EXPECT_EQ(cell_number(total["buildings"]), sql_number(db, "SELECT count(*) FROM building"));
  EXPECT_NEAR(cell_number(total["roof"]),
              sql_number(db, "SELECT sum(area) FROM building_element WHERE element_type='roof'"), 0.006);
  EXPECT_NEAR(cell_number(total["wall"]),
              sql_number(db, "SELECT sum(area) FROM building_element WHERE element_type='wall'"), 0.006);
  for (const char* col : {"land_value", "building_value", "njop", "tax"})
    EXPECT_NEAR(cell_number(total[col]), sql_number(db, std::string("SELECT sum(") + col + ") FROM vm_valuation"),
                0.51) << col;
}

TEST(ReportTown, ChromiumRendersTheSummaryAndPrintsAParcelOnOneA4Page) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  const std::string browser = chromium();
  C3D_NEED(!browser.empty(), "no chromium for the rendering check");
  const std::string flags = " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --hide-scrollbars "
                            "--disable-background-networking --disable-component-update --disable-sync "
                            "--no-first-run --user-data-dir=" + t.dir + "/chrome";
  const std::string png = t.dir + "/summary.png", pdf = t.dir + "/parcel.pdf";
  std::system(("timeout 120 " + browser + flags + " --screenshot=" + png + " --window-size=1400,2400 file://" +
               t.out + "/report.html >/dev/null 2>&1").c_str());
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 80000u);  // a blank page is a few kB
  // The parcel page of the most table rows: on one A4 sheet.
  const std::string page = page_of_most_rows(t);
  ASSERT_FALSE(page.empty()) << "no parcel page";
  std::system(("timeout 120 " + browser + flags + " --no-pdf-header-footer --print-to-pdf=" + pdf + " file://" +
               page + " >/dev/null 2>&1").c_str());
  ASSERT_TRUE(fs::exists(pdf)) << page;
  const std::string bytes = read(pdf);
  EXPECT_EQ(pdf_pages(bytes), 1) << page;
  // A4 is 210 x 297 mm, 595.3 x 841.9 points.
  double w = 0, h = 0;
  const size_t box = bytes.find("/MediaBox [0 0 ");
  ASSERT_NE(box, std::string::npos);
  ASSERT_EQ(std::sscanf(bytes.c_str() + box, "/MediaBox [0 0 %lf %lf", &w, &h), 2);
  EXPECT_NEAR(w, 595.3, 1.0);
  EXPECT_NEAR(h, 841.9, 1.0);
}

// The parcel page's 3D view: the elements drawn in the legend's colours, and a
// click where its largest roof is drawn shows that roof, with the store's area.
TEST(ReportTown, ParcelViewShowsTheStoresAreaOfAClickedElement) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  C3D_NEED(view_tools(), "node, tests/js/node_modules (puppeteer-core; scripts/setup.sh) or chromium missing");
  const std::string page = page_of_most_rows(t);
  const auto view = viewed(page, t.dir + "/parcel_view.png", "--unlit --click largest 0 --colours '#a0522d,#d8d8d8'");
  ASSERT_EQ(view.value("state", ""), "ready") << view.dump();
  EXPECT_TRUE(view["errors"].empty()) << view["errors"].dump();
  EXPECT_GT(view["pixels"][0].get<int>(), 500) << "roof pixels";
  EXPECT_GT(view["pixels"][1].get<int>(), 500) << "wall pixels";
  const auto& pick = view["pick"];
  ASSERT_TRUE(pick["building"].is_string()) << view.dump();
  EXPECT_EQ(pick["element"], view["clicked"]["element"]) << pick.dump();
  const std::string db = t.out + "/cadastre.gpkg";
  const std::string where = " FROM building_element e JOIN building b ON b.fid = e.building_fid WHERE b.building_id = '" +
                            pick["building"].get<std::string>() + "' AND e.element_index = " +
                            std::to_string(pick["element"].get<int>());
  EXPECT_EQ(sql_number(db, "SELECT e.element_type = 'roof'" + where), 1) << pick.dump();
  const double area = sql_number(db, "SELECT e.area" + where);
  EXPECT_DOUBLE_EQ(pick["area"].get<double>(), area);
  EXPECT_NEAR(std::stod(pick["shown"].get<std::string>()), area, 0.0051) << pick["text"];
}

// The summary's 3D view: every cell of a small town loaded, the buildings in
// the overview map's value colours, a click naming a building's parcel and
// value; without WebGL it says so and the page keeps its pictures.
TEST(ReportTown, SummaryViewDrawsTheParcelsByValue) {
  const Town& t = town();
  ASSERT_TRUE(t.rc == 0 || t.rc == 3) << t.log;
  C3D_NEED(view_tools(), "node, tests/js/node_modules (puppeteer-core; scripts/setup.sh) or chromium missing");
  std::string index = read(t.out + "/report/3d/index.js");
  index = index.substr(index.find(',') + 1);
  const auto classes = nlohmann::json::parse(index.substr(0, index.rfind(')')));
  std::string colours;
  for (const auto& c : classes["colours"]) colours += (colours.empty() ? "" : ",") + c.get<std::string>();
  const auto view = viewed(t.out + "/report.html", t.dir + "/summary_view.png",
                          "--unlit --click top --colours '" + colours + "'");
  ASSERT_EQ(view.value("state", ""), "ready") << view.dump();
  EXPECT_TRUE(view["errors"].empty()) << view["errors"].dump();
  EXPECT_EQ(view["cells"].size(), classes["cells"].size());
  for (const auto& c : view["cells"]) EXPECT_TRUE(c["far"].get<bool>()) << c.dump();
  int drawn = 0, classes_seen = 0;
  for (const auto& n : view["pixels"]) drawn += n.get<int>(), classes_seen += n.get<int>() > 100;
  EXPECT_GT(drawn, 5000);
  EXPECT_GE(classes_seen, 2) << view["pixels"].dump();
  // A click on a building names its parcel, with the store's NJOP per m2 of land.
  const auto& pick = view["pick"];
  ASSERT_TRUE(pick["parcel"].is_string()) << view.dump();
  EXPECT_NEAR(pick["value"].get<double>(),
              sql_number(t.out + "/cadastre.gpkg", "SELECT v.njop / u.land_area FROM vm_valuation v JOIN "
                         "vm_valuationunit u ON u.fid = v.valuationunit_id WHERE u.parcel_id = '" +
                         pick["parcel"].get<std::string>() + "'"), 0.01) << pick.dump();
  const auto blind = viewed(page_of_most_rows(t), t.dir + "/no_webgl.png", "--no-webgl");
  EXPECT_EQ(blind.value("state", ""), "unavailable") << blind.dump();
  EXPECT_NE(blind.value("note", "").find("pictures"), std::string::npos);
  EXPECT_GE(blind.value("pictures", 0), 2);
}
