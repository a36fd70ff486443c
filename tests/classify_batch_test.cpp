// batch --classify end to end on a real survey (issue 51): IGN's five labelled
// tiles joined into the town they are, parcels drawn around its labelled
// buildings, the batch run on the survey's own classes and on a copy with
// every class removed; the second must model the same roofs (within 3 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/io/point_io.h"
#include "tests/batch_e2e_support.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

constexpr double kCell = 1.0;       // m: the plan grid buildings are found on
constexpr int kMinCells = 100;      // a building: 100 m2 of labelled roof in plan (not a sliver the edge cut off)
constexpr double kMargin = 1.5;     // m around a building's plan box: its parcel
constexpr int kBuildingClass = 6;

// A parcel: a convex polygon, counter-clockwise.
struct Parcel4 {
  std::vector<Vec2> corner;
  bool holds(const Vec2& p) const {
    for (size_t k = 0; k < corner.size(); ++k) {
      const Vec2 e = corner[(k + 1) % corner.size()] - corner[k], d = p - corner[k];
      if (e.x() * d.y() - e.y() * d.x() < 0) return false;
    }
    return true;
  }
  // The part on the side of the line through a along n where (p - a).n >= 0 (Sutherland-Hodgman).
  void clip(const Vec2& a, const Vec2& n) {
    std::vector<Vec2> out;
    for (size_t k = 0; k < corner.size(); ++k) {
      const Vec2 &p = corner[k], &q = corner[(k + 1) % corner.size()];
      const double dp = (p - a).dot(n), dq = (q - a).dot(n);
      if (dp >= 0) out.push_back(p);
      if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
    }
    corner = out;
  }
};

// The connected groups of 1 m cells holding building points (4-neighbours).
std::vector<std::vector<Vec2>> building_groups(const PointCloud& town) {
  Vec3 lo = town.points.front(), hi = lo;
  for (const auto& p : town.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const int nx = int((hi.x() - lo.x()) / kCell) + 1, ny = int((hi.y() - lo.y()) / kCell) + 1;
  std::vector<char> building(size_t(nx) * size_t(ny), 0);
  for (size_t i = 0; i < town.points.size(); ++i)
    if (town.classes[i] == kBuildingClass)
      building[size_t(int((town.points[i].y() - lo.y()) / kCell)) * size_t(nx) +
               size_t(int((town.points[i].x() - lo.x()) / kCell))] = 1;
  std::vector<std::vector<Vec2>> groups;
  for (int start = 0; start < nx * ny; ++start) {
    if (!building[size_t(start)]) continue;
    std::vector<int> stack{start};
    building[size_t(start)] = 0;
    std::vector<Vec2> cells;
    while (!stack.empty()) {
      const int c = stack.back(), x = c % nx, y = c / nx;
      stack.pop_back();
      cells.emplace_back(lo.x() + (x + 0.5) * kCell, lo.y() + (y + 0.5) * kCell);
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= nx || v >= ny || !building[size_t(v * nx + u)]) continue;
        building[size_t(v * nx + u)] = 0;
        stack.push_back(v * nx + u);
      }
    }
    if (cells.size() >= size_t(kMinCells)) groups.push_back(cells);
  }
  return groups;
}

// A rectangle along the group's principal axes holding its cells, grown by kMargin.
Parcel4 oriented_parcel(const std::vector<Vec2>& cells) {
  Vec2 mean = Vec2::Zero();
  for (const auto& c : cells) mean += c;
  mean /= double(cells.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& c : cells) cov += (c - mean) * (c - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Vec2 u = es.eigenvectors().col(1), v(-u.y(), u.x());
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (const auto& c : cells) {
    const double a = (c - mean).dot(u), b = (c - mean).dot(v);
    u0 = std::min(u0, a), u1 = std::max(u1, a), v0 = std::min(v0, b), v1 = std::max(v1, b);
  }
  const double g = kMargin + kCell / 2;
  u0 -= g, u1 += g, v0 -= g, v1 += g;
  return {{mean + u0 * u + v0 * v, mean + u1 * u + v0 * v, mean + u1 * u + v1 * v, mean + u0 * u + v1 * v}};
}

// Within the survey's plan box less a metre (the batch's terrain covers it).
void clip_to_survey(Parcel4& p, const PointCloud& town) {
  Vec3 lo = town.points.front(), hi = lo;
  for (const auto& q : town.points) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  p.clip(Vec2(lo.x() + 1, 0), Vec2(1, 0));
  p.clip(Vec2(hi.x() - 1, 0), Vec2(-1, 0));
  p.clip(Vec2(0, lo.y() + 1), Vec2(0, 1));
  p.clip(Vec2(0, hi.y() - 1), Vec2(0, -1));
}

// Parcels around the labelled buildings: those holding no other building's
// cells and no corner of another parcel (so no two overlap). A building cut
// by the edge of the data is kept: both runs see the same points of it.
std::vector<Parcel4> building_parcels(const PointCloud& town) {
  const auto groups = building_groups(town);
  std::vector<Parcel4> all;
  for (const auto& g : groups) all.push_back(oriented_parcel(g));
  std::vector<Parcel4> kept;
  for (size_t i = 0; i < all.size(); ++i) {
    bool alone = true;
    for (size_t j = 0; j < all.size() && alone; ++j) {
      if (i == j) continue;
      for (const auto& c : groups[j]) alone = alone && !all[i].holds(c);
      for (const auto& c : all[j].corner) alone = alone && !all[i].holds(c);
      for (const auto& c : all[i].corner) alone = alone && !all[j].holds(c);
    }
    if (alone) kept.push_back(all[i]);
  }
  for (auto& p : kept) clip_to_survey(p, town);
  return kept;
}

void write_parcels(const std::vector<Parcel4>& parcels, const std::string& path) {
  std::ofstream f(path);
  f << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::2154"}},)"
    << R"("features":[)";
  char xy[64];
  for (size_t i = 0; i < parcels.size(); ++i) {
    std::string ring;
    const auto& c = parcels[i].corner;
    for (size_t k = 0; k <= c.size(); ++k) {
      std::snprintf(xy, sizeof xy, "%s[%.2f,%.2f]", k ? "," : "", c[k % c.size()].x(), c[k % c.size()].y());
      ring += xy;
    }
    f << (i ? "," : "") << R"({"type":"Feature","properties":{"NIB":"B)" << i
      << R"(","TIPEHAK":"HM"},"geometry":{"type":"Polygon","coordinates":[[)" << ring << "]]}}";
  }
  f << "]}\n";
}

std::map<std::string, double> roof_areas(const std::string& store) {
  e2e::Sqlite db(store);
  std::map<std::string, double> out;
  for (const auto& r : db.rows("SELECT s.parcel_id, sum(b.roof_area) FROM building b "
                               "JOIN la_spatialunit s ON b.spatialunit_id = s.fid GROUP BY s.parcel_id"))
    out[r[0].s] = r[1].d;
  return out;
}

TEST(ClassifyBatch, UnclassifiedSurveyModelsTheRoofsItsOwnClassesDo) {
  const fs::path dir = fs::path(C3D_SOURCE_DIR) / "../shared/data/labelled";
  C3D_NEED(fs::is_directory(dir), "../shared/data/labelled missing");
  PointCloud town;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".laz") continue;
    const PointCloud t = read_point_cloud(e.path().string());
    town.crs_wkt = t.crs_wkt;
    town.points.insert(town.points.end(), t.points.begin(), t.points.end());
    town.classes.insert(town.classes.end(), t.classes.begin(), t.classes.end());
    town.returns.insert(town.returns.end(), t.returns.begin(), t.returns.end());
  }
  ASSERT_GT(town.points.size(), 300000u);
  const std::vector<Parcel4> parcels = building_parcels(town);
  ASSERT_GE(parcels.size(), 3u) << "buildings to compare";
  const std::string out = test::temp_dir("classify_batch");
  write_parcels(parcels, out + "/parcels.geojson");
  write_las(out + "/labelled.las", town);
  PointCloud plain = town;
  std::fill(plain.classes.begin(), plain.classes.end(), std::uint8_t(1));  // ASPRS "unclassified"
  write_las(out + "/plain.las", plain);

  std::string log;
  const std::string common = " --quiet --parcels " + out + "/parcels.geojson --formats obj";
  const int own = test::run_cli("batch --cloud " + out + "/labelled.las --out " + out + "/own" + common, &log);
  ASSERT_TRUE(own == 0 || own == 3) << log;
  const int classified =
      test::run_cli("batch --classify --cloud " + out + "/plain.las --out " + out + "/classified" + common, &log);
  ASSERT_TRUE(classified == 0 || classified == 3) << log;

  const auto truth = roof_areas(out + "/own/cadastre.gpkg");
  const auto found = roof_areas(out + "/classified/cadastre.gpkg");
  ASSERT_GE(truth.size(), 3u);
  for (const auto& [parcel, area] : truth) {
    ASSERT_TRUE(found.count(parcel)) << parcel << ": modelled on its own classes, not after --classify";
    std::printf("%s: roof %.1f m2 on the survey's classes, %.1f m2 classified (%+.2f %%)\n", parcel.c_str(), area,
                found.at(parcel), 100 * (found.at(parcel) / area - 1));
    EXPECT_NEAR(found.at(parcel), area, 0.03 * area) << parcel;
  }
  EXPECT_EQ(found.size(), truth.size());
}

}  // namespace
}  // namespace c3d
