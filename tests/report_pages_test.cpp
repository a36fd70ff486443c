// The report as an officer reads it: totals that equal the store, an overview
// map by value class, detail pages linked both ways, a printable page per
// parcel, labelled charts, pages of bounded size.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "cadastre/report/report.h"
#include "cadastre/report/report_parts.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "tests/report_checks.h"
#include "tests/store_fixtures.h"
#include "tests/test_support.h"
#include "valuation/valuation.h"

using namespace c3d;
using namespace c3d::test;
namespace fs = std::filesystem;

namespace {

struct Sample {
  explicit Sample(int houses = 2) : model(sample_batch(houses)) {
    vals = value_batch(model, default_config().valuation);
  }
  BatchModel model;
  std::vector<ParcelValuation> vals;
};

std::map<std::string, std::string> files_by_path(const std::vector<ReportFile>& files) {
  std::map<std::string, std::string> m;
  for (const auto& f : files) m[f.path] = f.text;
  return m;
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(ReportPages, TotalsRowEqualsTheStoresSums) {
  Sample s(4);
  s.model.results[1].status = ParcelStatus::Suspect;  // counted apart, still in the total
  const std::string dir = temp_dir("report_totals");
  {
    Store store;
    store.open(dir + "/cadastre.gpkg", "", s.model.epsg);
    store.begin_run("{}", {}, s.model.frame);
    for (size_t i = 0; i < s.model.parcels.size(); ++i)
      store.write_parcel(s.model.parcels[i], s.model.results[i], s.vals[i], s.model.frame, "k");
    store.end_run();
  }
  std::string out;
  ASSERT_EQ(run_cli("report --store " + dir + "/cadastre.gpkg --out " + dir + "/out", &out), 0) << out;
  const std::string html = read(dir + "/out/report.html");
  const std::string db = dir + "/cadastre.gpkg";
  auto total = row_cells(html, "total");
  ASSERT_FALSE(total.empty()) << "no totals row";
  EXPECT_EQ(cell_number(total["parcels"]), sql_number(db, "SELECT count(*) FROM la_spatialunit"));
  EXPECT_EQ(cell_number(total["buildings"]), sql_number(db, "SELECT count(*) FROM building"));
  for (const char* type : {"roof", "wall", "party_wall", "ground", "outer_ceiling"})
    EXPECT_NEAR(cell_number(total[type]),
                sql_number(db, std::string("SELECT coalesce(sum(area),0) FROM building_element WHERE element_type='") +
                                type + "'"), 0.006) << type;
  for (const char* col : {"land_value", "building_value", "njop", "tax"})
    EXPECT_NEAR(cell_number(total[col]), sql_number(db, std::string("SELECT sum(") + col + ") FROM vm_valuation"), 0.51)
        << col;
  // By status: the suspect row holds that one parcel, the rows add up to the total.
  EXPECT_EQ(cell_number(row_cells(html, "status-suspect")["parcels"]), 1);
  double parcels = 0, njop = 0;
  for (const char* st : {"ok", "empty", "suspect", "failed"}) {
    parcels += cell_number(row_cells(html, std::string("status-") + st)["parcels"]);
    njop += cell_number(row_cells(html, std::string("status-") + st)["njop"]);
  }
  EXPECT_EQ(parcels, cell_number(total["parcels"]));
  EXPECT_NEAR(njop, cell_number(total["njop"]), 2.0);
  EXPECT_NE(html.find("EPSG:32748"), std::string::npos) << "the CRS of the areas";
}

TEST(ReportPages, MapHasOnePathPerParcelInItsValueClassColour) {
  Sample s(5);  // parcels 0-4 houses, 5 empty, 6 failed
  const double per_m2[] = {1e6, 2e6, 3e6, 4e6, 5e6, 1e6, 9e6};
  for (size_t i = 0; i < s.vals.size(); ++i) s.vals[i].njop = per_m2[i] * s.vals[i].land_area;
  s.model.results[4].status = ParcelStatus::Suspect;
  const std::string html = report_html(s.model, s.vals);
  const auto paths = tags_with(html, "path", "data-parcel");
  ASSERT_EQ(paths.size(), s.model.parcels.size());
  std::map<std::string, std::string> class_fill;  // legend: class -> swatch colour
  std::map<std::string, std::pair<double, double>> class_range;
  for (const auto& g : tags_with(html, "g", "data-lo")) {
    const size_t at = html.find(g), rect = html.find("<rect", at);
    class_fill[attr(g, "data-class")] = attr(html.substr(rect, html.find('>', rect) - rect), "fill");
    class_range[attr(g, "data-class")] = {std::stod(attr(g, "data-lo")), std::stod(attr(g, "data-hi"))};
  }
  ASSERT_GE(class_fill.size(), 3u);
  std::set<std::string> ids;
  for (size_t i = 0; i < paths.size(); ++i) {
    const std::string& p = paths[i];
    ids.insert(attr(p, "data-parcel"));
    const std::string status = attr(p, "data-status");
    if (status == "failed" || status == "suspect") {
      EXPECT_EQ(attr(p, "fill"), "url(#hatch-" + status + ")") << p;
      continue;
    }
    const std::string cls = attr(p, "data-class");
    ASSERT_TRUE(class_fill.count(cls)) << p;
    EXPECT_EQ(attr(p, "fill"), class_fill[cls]) << p;
    const double v = std::stod(attr(p, "data-value"));
    EXPECT_NEAR(v, per_m2[i], 1);
    EXPECT_GE(v, class_range[cls].first) << p;
    EXPECT_LT(v, class_range[cls].second) << p;
  }
  EXPECT_EQ(ids.size(), s.model.parcels.size());
  // Lowest value in the lightest colour, the highest valued house in the darkest of those used.
  EXPECT_EQ(attr(paths[0], "fill"), "#ffffb2");
  EXPECT_EQ(attr(paths[5], "stroke-dasharray"), "4 3") << "empty parcels drawn dashed";
  EXPECT_EQ(attr(paths[3], "fill"), class_fill[std::to_string(class_fill.size() - 1)]);
  // World coordinates: the map's origin plus a path's first point is the parcel's first vertex.
  const auto world = tags_with(html, "svg", "data-origin-x");
  ASSERT_EQ(world.size(), 1u);
  const Vec2 first = s.model.parcels[2].shape[0].outer[0];
  double x = 0, y = 0;
  ASSERT_EQ(std::sscanf(attr(paths[2], "d").c_str(), "M%lf %lf", &x, &y), 2);
  EXPECT_NEAR(std::stod(attr(world[0], "data-origin-x")) + x, first.x(), 0.006);
  EXPECT_NEAR(std::stod(attr(world[0], "data-origin-y")) - y, first.y(), 0.006);
  EXPECT_NE(html.find("class=\"scalebar\""), std::string::npos);
  EXPECT_NE(html.find("class=\"north\""), std::string::npos);
}

TEST(ReportPages, ValueClassesAreRoundedAndNoneIsEmpty) {
  using report_detail::value_classes;
  // Quintile breaks of 1..10 million; the range of 9 million rounds them to 100,000s.
  const auto even = value_classes({1e6, 2e6, 3e6, 4e6, 5e6, 6e6, 7e6, 8e6, 9e6, 10e6});
  EXPECT_EQ(even.breaks, (std::vector<double>{3e6, 5e6, 7e6, 9e6}));
  EXPECT_EQ(even.of(2.9e6), 0u);
  EXPECT_EQ(even.of(3e6), 1u);
  EXPECT_EQ(even.of(10e6), 4u);
  EXPECT_STREQ(even.colour(0), "#ffffb2");
  EXPECT_STREQ(even.colour(4), "#bd0026");
  EXPECT_EQ(even.label(1), "3,000,000 &ndash; &lt; 5,000,000");
  // The top value 4,436,195 would round up to a break of 4,440,000 above every value.
  const auto near = value_classes({4096000, 4096000, 4436195});
  ASSERT_EQ(near.breaks, (std::vector<double>{4100000}));
  EXPECT_EQ(near.of(4436195), 1u);
  EXPECT_EQ(value_classes({5e6, 5e6}).count(), 1u);
  EXPECT_EQ(value_classes({}).count(), 1u);
}

TEST(ReportPages, EveryPageLinksBothWaysAndEveryLinkResolves) {
  Sample s(118);  // 120 parcels: three detail pages of 50, 50 and 20
  const auto files = files_by_path(report_files(s.model, s.vals));
  ASSERT_EQ(files.size(), 1u + 3u + 120u + 1u);
  ASSERT_TRUE(files.count("report/parcels-003.html"));
  std::map<std::string, std::set<std::string>> links_to;  // target file -> files linking to it
  for (const auto& [path, text] : files) {
    if (path.size() < 5 || path.substr(path.size() - 5) != ".html") continue;
    for (const std::string& h : hrefs(text)) {
      const std::string target = resolve(path, h);
      const std::string file = target.substr(0, target.find('#'));
      ASSERT_TRUE(files.count(file)) << path << " links to missing " << h;
      if (target.find('#') != std::string::npos)
        EXPECT_NE(files.at(file).find("id=\"" + target.substr(target.find('#') + 1) + "\""), std::string::npos)
            << path << " -> " << h;
      links_to[file].insert(path);
    }
  }
  for (const auto& p : s.model.parcels) {
    const std::string page = "report/parcel/" + p.id + ".html";
    ASSERT_TRUE(files.count(page)) << page;
    EXPECT_TRUE(links_to[page].count("report.html")) << "map links " << page;
    EXPECT_TRUE(links_to[page].count("report/parcels-00" + std::to_string(p.index / 50 + 1) + ".html")) << page;
    EXPECT_TRUE(links_to["report/parcels-00" + std::to_string(p.index / 50 + 1) + ".html"].count(page)) << page;
    EXPECT_TRUE(links_to["report.html"].count(page)) << page << " links back to the summary";
  }
  for (const char* g : {"report/parcels-001.html", "report/parcels-002.html", "report/parcels-003.html"}) {
    EXPECT_TRUE(links_to[g].count("report.html")) << g;
    EXPECT_TRUE(links_to["report.html"].count(g)) << g;
  }
}

TEST(ReportPages, EachParcelHasAPrintableA4Page) {
  Sample s;
  const auto files = files_by_path(report_files(s.model, s.vals));
  const Parcel& p = s.model.parcels[0];
  const std::string page = files.at("report/parcel/" + p.id + ".html");
  EXPECT_NE(page.find("@page{size:A4"), std::string::npos);
  EXPECT_NE(page.find("@media print{nav"), std::string::npos) << "no navigation in print";
  EXPECT_NE(page.find("class=\"pic plan\""), std::string::npos) << "a plan";
  EXPECT_NE(page.find("class=\"scalebar\""), std::string::npos);
  const Element& roof = s.model.results[0].buildings[0].elements[0];
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f&nbsp;&plusmn;&nbsp;%.2f", roof.area, roof.sigma_area);
  EXPECT_NE(page.find(buf), std::string::npos) << buf;
  EXPECT_NE(page.find("NJOP"), std::string::npos);
  EXPECT_NE(page.find("PBB tax"), std::string::npos);
  // One page per parcel, failed ones too, and nothing else of the batch on it.
  EXPECT_EQ(page.find(s.model.parcels[1].id + " &mdash;"), std::string::npos);
  EXPECT_NE(files.at("report/parcel/" + s.model.parcels[3].id + ".html")
                .find("roof segmentation found no planar component"), std::string::npos);
  EXPECT_EQ(page.find("class=\"screen-only\""), std::string::npos) << "8 elements print one by one";

  // A building of 40 elements: its page prints totals by type, every row stays on screen.
  auto& elements = s.model.results[0].buildings[0].elements;
  const std::vector<Element> eight = elements;
  for (int k = 0; k < 4; ++k) elements.insert(elements.end(), eight.begin(), eight.end());
  double roof_total = 0;
  for (const Element& e : elements) roof_total += e.type == ElementType::Roof ? e.area : 0;
  const std::string big = files_by_path(report_files(s.model, s.vals)).at("report/parcel/" + p.id + ".html");
  const size_t screen = big.find("<div class=\"screen-only\">");
  ASSERT_NE(screen, std::string::npos);
  std::snprintf(buf, sizeof buf, "%.2f&nbsp;&plusmn;", roof_total);
  EXPECT_LT(big.find(buf), screen) << "roof total by type before the full table: " << buf;
  EXPECT_NE(big.find(".screen-only{display:none}"), std::string::npos);
  EXPECT_NE(big.find("The 40 elements one by one"), std::string::npos);
}

TEST(ReportPages, HistogramBinsAreLabelledAndHoldEveryParcel) {
  Sample s(98);  // 100 parcels: a histogram, not one bar each
  const std::string html = report_html(s.model, s.vals);
  const auto bins = tags_with(html, "rect", "data-count");
  ASSERT_GE(bins.size(), 2u);
  int counted = 0;
  for (const auto& b : bins) counted += std::stoi(attr(b, "data-count"));
  EXPECT_EQ(counted, int(s.vals.size()));
  for (const auto& v : s.vals) {
    int holding = 0;
    for (const auto& b : bins)
      holding += v.njop >= std::stod(attr(b, "data-lo")) && v.njop < std::stod(attr(b, "data-hi"));
    EXPECT_EQ(holding, 1) << v.parcel_id;
  }
  // Each bin's range under it, in millions, and the axes named with their unit.
  const double lo = std::stod(attr(bins[1], "data-lo")) / 1e6, hi = std::stod(attr(bins[1], "data-hi")) / 1e6;
  char label[64];
  std::snprintf(label, sizeof label, ">%g&ndash;%g</text>", lo, hi);
  EXPECT_NE(html.find(label), std::string::npos) << label;
  EXPECT_NE(html.find("NJOP per parcel (million IDR)"), std::string::npos);
  EXPECT_NE(html.find(">parcels</text>"), std::string::npos);
}

TEST(ReportPages, PagesStayBoundedFor800Parcels) {
  Sample s(798);
  size_t group_pages = 0, largest_group = 0, largest_parcel = 0;
  std::string summary;
  for (const auto& f : report_files(s.model, s.vals)) {
    if (f.path == "report.html") summary = f.text;
    if (f.path.rfind("report/parcels-", 0) == 0) ++group_pages, largest_group = std::max(largest_group, f.text.size());
    if (f.path.rfind("report/parcel/", 0) == 0) largest_parcel = std::max(largest_parcel, f.text.size());
  }
  EXPECT_EQ(group_pages, 16u);
  EXPECT_LT(summary.size(), 600'000u);
  EXPECT_LT(largest_group, 800'000u);
  EXPECT_LT(largest_parcel, 60'000u);
}

TEST(ReportPages, AReportWrittenAgainLeavesNoPageOfTheEarlierOne) {
  const std::string dir = temp_dir("report_again");
  Sample big(118), small;
  write_report(dir, big.model, big.vals);
  ASSERT_TRUE(fs::exists(dir + "/report/parcels-003.html"));
  write_report(dir, small.model, small.vals);
  size_t pages = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) pages += e.path().extension() == ".html";
  EXPECT_EQ(pages, 1u + 1u + small.model.parcels.size());
  EXPECT_FALSE(fs::exists(dir + "/report/parcels-002.html"));
}
