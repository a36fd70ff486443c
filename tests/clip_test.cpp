// Points per parcel with the overhang buffer (GEOS STRtree + prepared geometries).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <unordered_set>

#include "cadastre/clip.h"
#include "cadastre/parcels.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

// Two 10 m squares side by side sharing the boundary x = 10.
ParcelLayer two_squares() {
  ParcelLayer layer;
  layer.source = "test";
  for (int k = 0; k < 2; ++k) {
    Parcel p;
    p.index = k;
    p.id = "P" + std::to_string(k);
    double x0 = 10.0 * k;
    p.shape = {{{{x0, 0}, {x0 + 10, 0}, {x0 + 10, 10}, {x0, 10}}, {}}};
    layer.parcels.push_back(p);
  }
  return layer;
}

bool contains(const std::vector<size_t>& v, size_t i) {
  return std::find(v.begin(), v.end(), i) != v.end();
}

TEST(Clip, BufferSharesPointsNearTheBoundary) {
  ParcelClipper clipper(two_squares());  // default buffer 1.6 m
  EXPECT_DOUBLE_EQ(clipper.buffer_m(), 1.6);
  std::vector<Vec3> pts = {
      {5, 5, 0},      // 0: inside P0 only
      {10.5, 5, 0},   // 1: inside P1, within P0's buffer
      {-1.5, 5, 0},   // 2: P0's buffer only
      {-1.7, 5, 0},   // 3: nowhere
      {25, 5, 0},     // 4: nowhere
      {10, 5, 0},     // 5: on the shared boundary
      {-1.1, -1.1, 0} // 6: P0 corner buffer (distance 1.556 m)
  };
  auto lists = clipper.clip(pts);
  ASSERT_EQ(lists.size(), 2u);
  EXPECT_EQ(lists[0], (std::vector<size_t>{0, 1, 2, 5, 6}));
  EXPECT_EQ(lists[1], (std::vector<size_t>{1, 5}));
  EXPECT_TRUE(clipper.inside(0, 5, 5));
  EXPECT_FALSE(clipper.inside(0, 10.5, 5));
  EXPECT_FALSE(clipper.inside(0, 10, 5));  // boundary is not strictly inside
  EXPECT_TRUE(clipper.inside(1, 10.5, 5));
}

TEST(Clip, ZeroBufferIsTheParcelItself) {
  ClipParams params;
  params.overhang_buffer_m = 0;
  ParcelClipper clipper(two_squares(), params);
  auto lists = clipper.clip(std::vector<Vec3>{{5, 5, 0}, {-0.01, 5, 0}, {10.5, 5, 0}});
  EXPECT_EQ(lists[0], (std::vector<size_t>{0}));
  EXPECT_EQ(lists[1], (std::vector<size_t>{2}));
}

TEST(Clip, ChunkedFeedingEqualsWholeCloud) {
  ParcelClipper clipper(two_squares());
  std::vector<Vec3> pts;
  for (int i = 0; i < 5000; ++i)
    pts.emplace_back(-3 + 26.0 * ((i * 7919) % 5000) / 5000.0, -3 + 16.0 * ((i * 104729) % 5000) / 5000.0, 0);
  auto whole = clipper.clip(pts);
  ParcelClipper::IndexLists chunked;
  for (size_t start = 0; start < pts.size(); start += 777)
    clipper.clip(pts.data() + start, std::min<size_t>(777, pts.size() - start), chunked, start);
  EXPECT_EQ(whole, chunked);
  EXPECT_GT(whole[0].size(), 1000u);
}

TEST(Clip, ASubsetOfParcelsClipsItsPointsAsTheWholeLayer) {
  ParcelLayer layer = two_squares();  // and a third square far east
  Parcel far = layer.parcels[1];
  far.index = 2, far.id = "P2";
  for (auto& v : far.shape[0].outer) v.x() += 100;
  layer.parcels.push_back(far);
  const ParcelClipper whole(layer), first_two(layer, {}, {0, 1}), only_far(layer, {}, {2});
  std::vector<Vec3> near, away;
  for (int i = 0; i < 3000; ++i) {
    near.emplace_back(-3 + 26.0 * ((i * 7919) % 3000) / 3000.0, -3 + 16.0 * ((i * 104729) % 3000) / 3000.0, 0);
    away.emplace_back(near.back().x() + 100, near.back().y(), 0);
  }
  EXPECT_EQ(first_two.clip(near), whole.clip(near));  // every parcel a point can be in is in the subset
  EXPECT_EQ(only_far.clip(away), whole.clip(away));
  EXPECT_EQ(first_two.parcel_count(), 3u);
  EXPECT_TRUE(first_two.clip(away)[2].empty()) << "a parcel outside the subset holds no point";
  EXPECT_TRUE(first_two.inside(1, 15, 5));
  EXPECT_THROW(first_two.inside(2, 115, 5), std::logic_error);
}

// Key of a point at millimetre resolution (the LAS stores millimetres).
struct MmKey {
  long long x, y, z;
  bool operator==(const MmKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct MmHash {
  size_t operator()(const MmKey& k) const {
    return std::hash<long long>()(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};
MmKey key(const Vec3& p, int dx = 0, int dy = 0, int dz = 0) {
  return {std::llround(p.x() * 1000) + dx, std::llround(p.y() * 1000) + dy,
          std::llround(p.z() * 1000) + dz};
}

// Acceptance: every point of the paper's per-parcel roof files
// (reference/roofs/pcdroof_persil_<i>_roof_*.ply) is in the clip of parcel record i.
TEST(Clip, CimahiReferenceRoofsLieInTheirParcelsClip) {
  C3D_REQUIRE_CIMAHI();
  namespace fs = std::filesystem;
  const std::string dir = test::cimahi_dir();
  ParcelLayer layer = read_parcels(dir + "/parcels.shp");
  PointCloud cloud = read_point_cloud(dir + "/cimahi.las");
  ParcelClipper clipper(layer);
  auto lists = clipper.clip(cloud.points);
  ASSERT_EQ(lists.size(), 30u);

  const std::regex name(R"(pcdroof_persil_(\d+)_roof_\d+\.ply)");
  int files = 0;
  long checked = 0;
  std::vector<std::unordered_set<MmKey, MmHash>> clipped(lists.size());
  for (const auto& entry : fs::directory_iterator(dir + "/reference/roofs")) {
    std::smatch m;
    std::string file = entry.path().filename().string();
    if (!std::regex_match(file, m, name)) continue;
    size_t parcel = std::stoul(m[1]);
    ASSERT_LT(parcel, lists.size()) << file;
    auto& set = clipped[parcel];
    if (set.empty())
      for (size_t i : lists[parcel]) set.insert(key(cloud.points[i]));
    PointCloud roof = read_point_cloud(entry.path().string());
    ++files;
    long missing = 0;
    for (const Vec3& p : roof.points) {
      ++checked;
      bool found = false;  // +-1 mm: the PLY is double, the LAS rounded to mm
      for (int dx = -1; dx <= 1 && !found; ++dx)
        for (int dy = -1; dy <= 1 && !found; ++dy)
          for (int dz = -1; dz <= 1 && !found; ++dz) found = set.count(key(p, dx, dy, dz)) > 0;
      missing += !found;
    }
    EXPECT_EQ(missing, 0) << file << ": " << missing << " of " << roof.points.size()
                          << " roof points are not in the clip of parcel record " << parcel;
  }
  EXPECT_EQ(files, 47);
  EXPECT_GT(checked, 100000);
}

TEST(Clip, ClipCommandTableAndCsv) {
  C3D_REQUIRE_CIMAHI();
  const std::string dir = test::cimahi_dir();
  const std::string csv = test::temp_dir("clip_cli") + "/clip.csv";
  std::string out;
  ASSERT_EQ(test::run_cli("clip --cloud " + dir + "/cimahi.las --parcels " + dir +
                              "/parcels.shp --id-field NIB --csv " + csv,
                          &out),
            0)
      << out;
  EXPECT_NE(out.find("in_parcel"), std::string::npos) << out;
  EXPECT_NE(out.find("05764"), std::string::npos) << out;
  EXPECT_NE(out.find("244685 points"), std::string::npos) << out;
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "parcel_index,parcel_id,in_parcel,in_buffer,roof,wall");
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 30);
  EXPECT_EQ(test::run_cli("clip --help", &out), 0);
  EXPECT_NE(out.find("--buffer"), std::string::npos) << out;
}

}  // namespace
}  // namespace c3d
