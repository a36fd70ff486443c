// Point-to-model deviation, pooling, mesh IO and the evaluate command (the
// evaluate logic called as a library: evaluate_zones_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/io/mesh_io.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

Face quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) { return {{a, b, c, d}, {}}; }

// Offsets of the test points from the plane, and their exact statistics.
const std::vector<double> kOffsets{0.1, -0.2, 0.3, 0.4, -0.5};
constexpr double kMean = 0.3, kMeanSq = 0.11;

void expect_offsets_stats(const Deviation& d) {
  EXPECT_EQ(d.n, 5);
  EXPECT_NEAR(d.mean, kMean, 1e-9);
  EXPECT_NEAR(d.std, std::sqrt(kMeanSq - kMean * kMean), 1e-9);
  EXPECT_NEAR(d.rmse, std::sqrt(kMeanSq), 1e-9);
  EXPECT_NEAR(d.max, 0.5, 1e-9);
}

}  // namespace

TEST(Deviation, PointsAtKnownDistancesFromAPlane) {
  const Vec3 o(512345.0, 9241234.0, 712.0);  // UTM-sized: the index works locally
  std::vector<Face> plane{quad(o + Vec3(-10, -10, 0), o + Vec3(10, -10, 0), o + Vec3(10, 10, 0),
                               o + Vec3(-10, 10, 0))};
  std::vector<Vec3> pts;
  for (size_t i = 0; i < kOffsets.size(); ++i) pts.push_back(o + Vec3(-8 + 3.5 * double(i), 2 - double(i), kOffsets[i]));
  expect_offsets_stats(deviation_to_faces(pts, plane));
  expect_offsets_stats(deviation_to_faces(pts, plane, /*vertical=*/true));
  // A point beyond the plane's plan has no vertical distance but a 3D one.
  pts.push_back(o + Vec3(13, 0, 4));
  EXPECT_EQ(deviation_to_faces(pts, plane, true).n, 5);
  Deviation d3 = deviation_to_faces(pts, plane);
  EXPECT_EQ(d3.n, 6);
  EXPECT_NEAR(d3.max, 5, 1e-9);
}

TEST(Deviation, SplitByWhatTheModelHasOverEachPoint) {
  // 3D distances and vertical distances of six points: two on the model, two
  // under or over a roof 1-2 m off, two with no roof above or below.
  const std::vector<double> distance{0.1, 0.2, 0.9, 1.5, 3.0, 4.0};
  const std::vector<double> vertical{0.1, 0.25, 1.0, 2.0, kNaN, kNaN};
  const RoofCover c = split_by_cover(distance, vertical);
  EXPECT_EQ(c.on_model.n, 2);
  EXPECT_NEAR(c.on_model.rmse, std::sqrt((0.01 + 0.04) / 2), 1e-12);
  EXPECT_EQ(c.off_model.n, 2);
  EXPECT_NEAR(c.off_model.max, 1.5, 1e-12);
  EXPECT_EQ(c.uncovered.n, 2);
  EXPECT_NEAR(c.uncovered.mean, 3.5, 1e-12);
  // The three parts pool back to the whole.
  const Deviation all = pool({c.on_model, c.off_model, c.uncovered}), direct = deviation(distance);
  EXPECT_EQ(all.n, direct.n);
  EXPECT_NEAR(all.std, direct.std, 1e-12);
}

TEST(Deviation, DistancesToABox) {
  const auto faces = test::box_shell({0, 0, 0}, {2, 2, 2});
  FaceIndex index(faces);
  EXPECT_NEAR(index.nearest(Vec3(3, 1, 1)).distance, 1, 1e-12);
  EXPECT_NEAR(index.nearest(Vec3(3, 3, 1)).distance, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(index.nearest(Vec3(3, 3, 3)).distance, std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(index.nearest(Vec3(1, 1, 0.5)).distance, 0.5, 1e-12);  // inside
  EXPECT_TRUE(index.nearest(Vec3(3, 1, 1)).point.isApprox(Vec3(2, 1, 1)));
  // Vertical: nearest crossing in z (top or bottom), walls ignored.
  EXPECT_NEAR(index.vertical(Vec3(1, 1, 2.3)).distance, 0.3, 1e-12);
  EXPECT_NEAR(index.vertical(Vec3(1, 1, 0.4)).distance, 0.4, 1e-12);
  EXPECT_TRUE(std::isnan(index.vertical(Vec3(5, 1, 1)).distance));
}

TEST(Deviation, PoolingEqualsTheUnion) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.2, 0.3);
  std::vector<std::vector<double>> parts(4);
  std::vector<double> all;
  for (size_t k = 0; k < parts.size(); ++k)
    for (int i = 0; i < 100 * int(k + 1); ++i) {
      double v = g(rng) * (k + 1);
      parts[k].push_back(v);
      all.push_back(v);
    }
  std::vector<Deviation> devs;
  for (const auto& p : parts) devs.push_back(deviation(p));
  devs.push_back({});  // an empty part changes nothing
  const Deviation pooled = pool(devs), direct = deviation(all);
  EXPECT_EQ(pooled.n, direct.n);
  EXPECT_NEAR(pooled.mean, direct.mean, 1e-12);
  EXPECT_NEAR(pooled.std, direct.std, 1e-12);
  EXPECT_NEAR(pooled.rmse, direct.rmse, 1e-12);
  EXPECT_EQ(pooled.max, direct.max);
  EXPECT_EQ(pool({}).n, 0);
}

TEST(Deviation, EvaluateBuildingsAssignsPointsToTheNearestBuilding) {
  std::vector<Building> bs(2);
  for (int k = 0; k < 2; ++k) {
    auto faces = test::box_shell({20.0 * k, 0, 0}, {20.0 * k + 10, 10, 5});
    bs[k].elements.push_back({ElementType::Roof, {faces[1]}});
    bs[k].elements.push_back({ElementType::Wall, {faces[2], faces[3], faces[4], faces[5]}});
  }
  std::vector<Vec3> roof{{5, 5, 5.2}, {2, 3, 4.9}, {25, 5, 5.1}}, wall{{-0.3, 5, 2}, {30.4, 5, 1}};
  evaluate_buildings(bs, roof, wall);
  EXPECT_EQ(bs[0].roof_deviation.n, 2);
  EXPECT_NEAR(bs[0].roof_deviation.mean, 0.15, 1e-12);
  EXPECT_EQ(bs[1].roof_deviation.n, 1);
  EXPECT_NEAR(bs[1].roof_deviation.max, 0.1, 1e-12);
  EXPECT_EQ(bs[0].wall_deviation.n, 1);
  EXPECT_NEAR(bs[0].wall_deviation.rmse, 0.3, 1e-12);
  EXPECT_NEAR(bs[1].wall_deviation.rmse, 0.4, 1e-12);
}

TEST(Deviation, QuerySpeed) {
  // A 40 x 40 grid of small houses (10 k triangles), 1 M points near the roofs.
  std::vector<Face> faces;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      auto b = test::box_shell({15.0 * i, 15.0 * j, 0}, {15.0 * i + 10, 15.0 * j + 10, 3 + 0.1 * j});
      faces.insert(faces.end(), b.begin(), b.end());
    }
  // Points as LiDAR gives them: on the roofs, 0.3 m noise.
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> house(0, 39);
  std::uniform_real_distribution<double> u(0, 10);
  std::normal_distribution<double> noise(0, 0.3);
  std::vector<Vec3> pts(1000000);
  for (auto& p : pts) {
    const int i = house(rng), j = house(rng);
    p = Vec3(15.0 * i + u(rng), 15.0 * j + u(rng), 3 + 0.1 * j + noise(rng));
  }
  auto t0 = std::chrono::steady_clock::now();
  FaceIndex index(faces);
  auto t1 = std::chrono::steady_clock::now();
  auto near = index.nearest(pts);
  auto t2 = std::chrono::steady_clock::now();
  auto vert = index.vertical(pts);
  auto t3 = std::chrono::steady_clock::now();
  auto s = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("index %.3f s; 1M nearest %.3f s (%.2f M/s); 1M vertical %.3f s (%.2f M/s)\n",
              s(t0, t1), s(t1, t2), 1 / s(t1, t2), s(t2, t3), 1 / s(t2, t3));
  EXPECT_EQ(near.size(), pts.size());
  EXPECT_LT(s(t1, t2), 30.0);  // generous: shared CI machines
}

TEST(MeshIo, ObjRoundTripKeepsGroupsAndCoordinates) {
  const std::string dir = test::temp_dir("mesh_io");
  const Vec3 o(512345.25, 9241234.5, 700);
  auto b = test::box_shell(o, o + Vec3(10, 8, 3));
  Face holed{{o, o + Vec3(4, 0, 0), o + Vec3(4, 4, 0), o + Vec3(0, 4, 0)},
             {{o + Vec3(1, 1, 0), o + Vec3(1, 2, 0), o + Vec3(2, 2, 0), o + Vec3(2, 1, 0)}}};
  std::vector<MeshGroup> groups{{"p1_b1_roof", "roof", {b[1]}},
                                {"p1_b1_wall", "wall", {b[2], b[3], b[4], b[5]}},
                                {"p1_b1_ground", "", {b[0]}},
                                {"holed", "", {holed}}};
  const std::string path = dir + "/m.obj";
  write_obj(path, groups, o);
  auto back = read_mesh_groups(path);
  ASSERT_EQ(back.size(), 4u);
  EXPECT_EQ(back[0].name, "p1_b1_roof");
  EXPECT_EQ(back[0].material, "roof");
  EXPECT_EQ(back[1].faces.size(), 4u);
  for (size_t g = 0; g < 3; ++g)
    for (size_t f = 0; f < groups[g].faces.size(); ++f)
      for (size_t k = 0; k < 4; ++k)  // written relative to o, read back in world coordinates
        EXPECT_NEAR((back[g].faces[f].ring[k] - groups[g].faces[f].ring[k]).norm(), 0, 1e-6);
  double a = 0;
  for (const auto& f : back[3].faces) a += plan_area(f);
  EXPECT_NEAR(a, 15, 1e-9);  // the hole was written as triangles
}

TEST(MeshIo, PlyAsciiAndBinary) {
  const std::string dir = test::temp_dir("mesh_io_ply");
  {
    std::ofstream a(dir + "/a.ply");
    a << "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
         "property double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
         "500000.5 9000000.25 10\n500001.5 9000000.25 10\n500001.5 9000001.25 10\n500000.5 9000001.25 10\n"
         "3 0 1 2\n3 0 2 3\n";
  }
  {
    std::ofstream b(dir + "/b.ply", std::ios::binary);
    b << "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nelement face 1\nproperty list uchar uint vertex_indices\n"
         "end_header\n";
    const float v[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (auto& p : v) {
      b.write(reinterpret_cast<const char*>(p), sizeof p);
      b.put(char(255));
    }
    b.put(3);
    const unsigned idx[3] = {0, 1, 2};
    b.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  auto a = read_mesh_faces(dir + "/a.ply");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].ring[1], Vec3(500001.5, 9000000.25, 10));
  auto b = read_mesh_faces(dir + "/b.ply");
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].ring[2], Vec3(0, 1, 0));
  EXPECT_THROW(read_mesh_groups(dir + "/missing.obj"), std::runtime_error);
}

namespace {

// A GeoJSON layer of parcels (id, x0, x1), each from o.y - 1 to o.y + 9, ids in NIB.
void write_parcels(const std::string& path, const Vec3& o,
                   const std::vector<std::tuple<std::string, double, double>>& parcels) {
  std::ofstream g(path);
  g << R"({"type":"FeatureCollection","features":[)";
  for (size_t i = 0; i < parcels.size(); ++i) {
    const auto& [id, x0, x1] = parcels[i];
    std::ostringstream s;
    s.precision(12);
    const double y0 = o.y() - 1, y1 = o.y() + 9;
    s << (i ? "," : "") << R"({"type":"Feature","properties":{"NIB":")" << id
      << R"("},"geometry":{"type":"Polygon","coordinates":[[[)" << o.x() + x0 << "," << y0 << "],["
      << o.x() + x1 << "," << y0 << "],[" << o.x() + x1 << "," << y1 << "],[" << o.x() + x0 << "," << y1
      << "],[" << o.x() + x0 << "," << y0 << "]]]}}";
    g << s.str();
  }
  g << "]}";
}

// P1's 10 x 8 x 3 m house as model.obj; cloud.las: five roof points at kOffsets
// over its roof, two wall points 0.2 m off its walls, and a roof point in
// parcel P2, which has no model; parcels.geojson: P1 and P2. Returns the dir.
std::string write_house_inputs(const std::string& name) {
  const std::string dir = test::temp_dir(name);
  const Vec3 o(512300.0, 9241200.0, 700.0);
  auto b = test::box_shell(o, o + Vec3(10, 8, 3));
  write_obj(dir + "/model.obj", {{"P1_b1_roof", "", {b[1]}}, {"P1_b1_wall", "", {b[2], b[3], b[4], b[5]}},
                                 {"P1_b1_ground", "", {b[0]}}});
  PointCloud cloud;
  for (size_t i = 0; i < kOffsets.size(); ++i) {
    cloud.points.push_back(o + Vec3(1 + 1.5 * double(i), 2 + double(i), 3 + kOffsets[i]));
    cloud.classes.push_back(6);
  }
  cloud.points.push_back(o + Vec3(-0.2, 4, 1.5));  // 0.2 m off the west wall
  cloud.points.push_back(o + Vec3(5, 8.2, 1));      // 0.2 m off the north wall
  cloud.classes.insert(cloud.classes.end(), {64, 64});
  cloud.points.push_back(o + Vec3(25, 4, 3));  // a roof point in parcel P2, which has no model
  cloud.classes.push_back(6);
  write_las(dir + "/cloud.las", cloud);
  write_parcels(dir + "/parcels.geojson", o, {{"P1", -1, 11}, {"P2", 20, 30}});
  return dir;
}

// Runs `evaluate` on the house inputs with the extra arguments; the JSON it wrote.
nlohmann::json evaluate_house(const std::string& dir, const std::string& args, std::string* out) {
  const std::string json = dir + "/e.json";
  EXPECT_EQ(test::run_cli("evaluate --mesh " + dir + "/model.obj --cloud " + dir + "/cloud.las --json " + json +
                              " " + args,
                          out),
            0)
      << *out;
  return nlohmann::json::parse(std::ifstream(json));
}

}  // namespace

TEST(EvaluateCli, PooledWithoutParcels) {
  const std::string dir = write_house_inputs("evaluate_cli");
  std::string out;
  const nlohmann::json j = evaluate_house(dir, "", &out);
  EXPECT_EQ(j["pooled"]["roof"]["n"], 6);  // without parcels the P2 point counts too
  // ... with no roof over it, 20 m off the model; the others lie on the roof's plan.
  const auto& cover = j["pooled"]["roof_cover"];
  EXPECT_EQ(cover["uncovered"]["n"], 1);
  EXPECT_NEAR(cover["uncovered"]["rmse"].get<double>(), 15.0, 1e-6);  // to the roof's east edge
  EXPECT_EQ(cover["on_model"]["n"].get<long>() + cover["off_model"]["n"].get<long>(), 5);
  EXPECT_NEAR(j["pooled"]["wall"]["rmse"].get<double>(), 0.2, 1e-6);
}

TEST(EvaluateCli, PerParcelDeviation) {
  const std::string dir = write_house_inputs("evaluate_cli");
  std::string out;
  nlohmann::json j = evaluate_house(dir, "--parcels " + dir + "/parcels.geojson --id-field NIB", &out);
  EXPECT_NE(out.find("pooled"), std::string::npos) << out;
  const auto& p1 = j["parcels"][0];
  EXPECT_EQ(p1["id"], "P1");
  EXPECT_EQ(p1["roof"]["n"], 5);
  EXPECT_NEAR(p1["roof"]["mean"].get<double>(), kMean, 1e-6);
  EXPECT_NEAR(p1["roof"]["rmse"].get<double>(), std::sqrt(kMeanSq), 1e-6);
  EXPECT_NEAR(p1["roof_vertical"]["rmse"].get<double>(), std::sqrt(kMeanSq), 1e-6);
  EXPECT_EQ(p1["wall"]["n"], 2);
  EXPECT_EQ(j["parcels"][1]["unmodelled_roof_points"], 1);
  EXPECT_EQ(j["pooled"]["roof"]["n"], 5);
  // Without --id-field the parcels are named as the batch names them (NIB
  // where the layer has it), so the batch's OBJ groups find their parcel by
  // name, not by the land under them (on Cimahi the feature ids gave 0.268 m
  // for the batch's 0.281 m).
  j = evaluate_house(dir, "--parcels " + dir + "/parcels.geojson", &out);
  EXPECT_EQ(j["parcels"][0]["id"], "P1");
  EXPECT_EQ(j["parcels"][1]["id"], "P2");
}

TEST(EvaluateCli, NamesAMissingOrBrokenModel) {
  const std::string dir = write_house_inputs("evaluate_cli");
  std::string out;
  EXPECT_NE(test::run_cli("evaluate --mesh " + dir + "/missing.obj --cloud " + dir + "/cloud.las", &out), 0);
  EXPECT_NE(out.find("missing.obj"), std::string::npos) << out;
  // A CityJSON model that is not there or not JSON: one error naming the file.
  EXPECT_NE(test::run_cli("evaluate --mesh " + dir + "/missing.city.json --cloud " + dir + "/cloud.las", &out), 0);
  EXPECT_NE(out.find("missing.city.json: cannot open"), std::string::npos) << out;
  std::ofstream(dir + "/cut.city.json") << R"({"type": "CityJSON", "CityObjects": {)";
  EXPECT_NE(test::run_cli("evaluate --mesh " + dir + "/cut.city.json --cloud " + dir + "/cloud.las", &out), 0);
  EXPECT_NE(out.find("cut.city.json: "), std::string::npos) << out;
}

TEST(Deviation, WallPointsSplitByWhereTheyStand) {
  // Distances to the parcel's walls, vertical distances to its own roof and to
  // another parcel's (NaN: none above or below).
  const std::vector<double> distance{0.1, 2.0, 3.0, 4.0, 0.25};
  const std::vector<double> own{1.0, 1.5, kNaN, kNaN, kNaN}, other{kNaN, 0.5, 2.0, kNaN, kNaN};
  const WallCover c = split_wall_cover(distance, own, other);
  EXPECT_EQ(c.on_wall.n, 2);  // near a wall wins, whatever roof is over it
  EXPECT_EQ(c.under_own_roof.n, 1);
  EXPECT_NEAR(c.under_own_roof.mean, 2.0, 1e-12);  // own roof wins over another's
  EXPECT_EQ(c.under_other_roof.n, 1);
  EXPECT_EQ(c.under_no_roof.n, 1);
  EXPECT_NEAR(c.under_no_roof.max, 4.0, 1e-12);
  const Deviation all = pool(c.parts()), direct = deviation(distance);
  EXPECT_EQ(all.n, direct.n);
  EXPECT_NEAR(all.rmse, direct.rmse, 1e-12);
}

TEST(EvaluateCli, WallSplitAndResidualsPerPoint) {
  const std::string dir = test::temp_dir("evaluate_walls");
  const Vec3 o(512300.0, 9241200.0, 700.0);
  auto shell = [&](const std::string& id, double x0, double x1) {
    auto b = test::box_shell(o + Vec3(x0, 0, 0), o + Vec3(x1, 8, 3));
    return std::vector<MeshGroup>{{id + "_b1_roof", "", {b[1]}}, {id + "_b1_wall", "", {b[2], b[3], b[4], b[5]}},
                                  {id + "_b1_ground", "", {b[0]}}};
  };
  auto groups = shell("P1", 0, 10), second = shell("P2", 12, 20);
  groups.insert(groups.end(), second.begin(), second.end());
  write_obj(dir + "/model.obj", groups);
  PointCloud cloud;
  auto add = [&](Vec3 offset, int cls) {
    cloud.points.push_back(o + offset);
    cloud.classes.push_back(cls);
  };
  add({5, 4, 3.1}, 6);    // P1: on its roof
  add({10.8, 4, 3}, 6);   // P1: on its land, no roof over it, 0.8 m off the roof's edge
  add({-0.2, 4, 1.5}, 64);  // P1: 0.2 m off its west wall
  add({5, 4, 1}, 64);       // P1: under its roof, 4 m from every wall
  add({12.5, 4, 1}, 64);    // under P2's roof: 2.5 m from P1's east wall, 0.5 m from P2's west wall
  add({5, 10, 1}, 64);      // 1 m off P1's land, under no roof, 2 m from P1's north wall
  write_las(dir + "/cloud.las", cloud);
  write_parcels(dir + "/parcels.geojson", o, {{"P1", -1, 11}, {"P2", 11.5, 21}});
  std::string out;
  ASSERT_EQ(test::run_cli("evaluate --mesh " + dir + "/model.obj --cloud " + dir + "/cloud.las --parcels " + dir +
                              "/parcels.geojson --id-field NIB --json " + dir + "/e.json --residuals " + dir +
                              "/residuals.csv",
                          &out),
            0)
      << out;
  EXPECT_NE(out.find("under another's roof"), std::string::npos) << out;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/e.json"));
  const auto& p1 = j["parcels"][0]["wall_cover"];
  EXPECT_EQ(p1["on_wall"]["n"], 1);
  EXPECT_NEAR(p1["on_wall"]["max"].get<double>(), 0.2, 1e-6);
  EXPECT_EQ(p1["under_own_roof"]["n"], 1);
  EXPECT_NEAR(p1["under_own_roof"]["max"].get<double>(), 4.0, 1e-6);
  EXPECT_EQ(p1["under_other_roof"]["n"], 1);
  EXPECT_NEAR(p1["under_other_roof"]["max"].get<double>(), 2.5, 1e-6);
  EXPECT_EQ(p1["under_no_roof"]["n"], 1);
  EXPECT_NEAR(p1["under_no_roof"]["max"].get<double>(), 2.0, 1e-6);
  const auto& p2 = j["parcels"][1]["wall_cover"];
  EXPECT_EQ(p2["under_own_roof"]["n"], 1);  // the point under its roof, 0.5 m inside its wall
  EXPECT_EQ(j["pooled"]["wall_cover"]["under_own_roof"]["n"], 2);
  EXPECT_EQ(j["pooled"]["roof_cover"]["uncovered"]["n"], 1);

  // One row per measured point, world coordinates kept to the millimetre.
  std::ifstream csv(dir + "/residuals.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "parcel,kind,x,y,z,distance_m,vertical_m,part");
  std::vector<std::string> rows;
  while (std::getline(csv, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 7u);  // P1: 2 roof + 4 wall points; P2: 1 wall point
  auto has = [&](const std::string& row) { return std::find(rows.begin(), rows.end(), row) != rows.end(); };
  EXPECT_TRUE(has("P1,roof,512310.800,9241204.000,703.000,0.8000,,uncovered"));
  EXPECT_TRUE(has("P1,roof,512305.000,9241204.000,703.100,0.1000,0.1000,on_model"));
  EXPECT_TRUE(has("P1,wall,512305.000,9241210.000,701.000,2.0000,,under_no_roof"));
  EXPECT_TRUE(has("P2,wall,512312.500,9241204.000,701.000,0.5000,,under_own_roof"));
}

// The sample town writes its exact buildings as the batch writes its models
// (truth_obj/<parcel>.obj), so the batch's ruler can be put to the perfect
// model. With no outliers and no clutter every roof point is a surface point
// blurred by 3 cm per axis: its distance to the true plane is |N(0, 0.03)|,
// mean 0.03 sqrt(2/pi) = 0.0239 m, std 0.03 sqrt(1 - 2/pi) = 0.0181 m; wall
// points within 0.3 m of their own parcel's walls lie at the 2 cm wall noise.
// The wall ruler also counts every neighbour's facade within 2 m of the parcel,
// so even the exact model reads far above the 2 cm there.
TEST(EvaluateCli, TheExactModelByTheBatchsRuler) {
  const std::string dir = test::temp_dir("evaluate_truth");
  std::string out;
  ASSERT_EQ(test::run_cli("sample --out " + dir + " --parcels 10 --seed 11 --outliers 0 --clutter 0", &out), 0)
      << out;
  ASSERT_EQ(test::run_cli("evaluate --mesh " + dir + "/truth_obj/*.obj --cloud " + dir + "/cloud.las --parcels " +
                              dir + "/parcels.gpkg --json " + dir + "/truth.eval.json",
                          &out),
            0)
      << out;
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/truth.eval.json"));
  const auto& roof = j["pooled"]["roof"];
  EXPECT_GT(roof["n"].get<long>(), 10000);
  EXPECT_NEAR(roof["mean"].get<double>(), 0.0239, 0.0015);
  EXPECT_NEAR(roof["std"].get<double>(), 0.0181, 0.0015);
  // Only points the noise carried past an eave in plan have no roof over them.
  const auto& uncovered = j["pooled"]["roof_cover"]["uncovered"];
  EXPECT_LT(uncovered["n"].get<double>(), 0.01 * roof["n"].get<double>());
  EXPECT_LT(uncovered["max"].get<double>(), 0.15);

  const auto& wall = j["pooled"]["wall"];
  const auto& own_walls = j["pooled"]["wall_cover"]["on_wall"];
  const auto& facades = j["pooled"]["wall_cover"]["under_other_roof"];
  EXPECT_GT(own_walls["n"].get<long>(), 10000);
  EXPECT_LT(own_walls["rmse"].get<double>(), 0.03);
  // The perfect model misses the issue's 0.15 m wall target by its own ruler:
  // nearly all the squared distance is neighbours' facades under their roofs.
  EXPECT_GT(wall["std"].get<double>(), 0.15);
  auto squared = [](const nlohmann::json& d) { return d["n"].get<double>() * std::pow(d["rmse"].get<double>(), 2); };
  EXPECT_GT(squared(facades), 0.99 * squared(wall));
}
