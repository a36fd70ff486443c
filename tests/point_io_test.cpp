// Readers of every point format: LAS 0-10 via write_las round trips, PLY, PCD, XYZ/CSV.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/io/crs.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

// UTM-sized coordinates: float32 would lose centimetres here.
PointCloud sample_cloud(bool with_classes) {
  PointCloud c;
  const uint8_t codes[] = {2, 6, 64, 31, 200, 1};
  for (int i = 0; i < 600; ++i) {
    c.points.emplace_back(781810.123 + 0.25 * i, 9239979.456 + 0.125 * (i % 17), 781.5 + 0.001 * i);
    if (with_classes) c.classes.push_back(codes[i % 6]);
  }
  return c;
}

void expect_same_points(const PointCloud& a, const PointCloud& b, double tol) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i)
    ASSERT_LE((a.points[i] - b.points[i]).cwiseAbs().maxCoeff(), tol) << "point " << i;
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(PointIo, LasRoundTripEveryFormatAndVersion) {
  std::string dir = test::temp_dir("las_formats");
  PointCloud in = sample_cloud(true);
  in.crs_wkt = wkt_from_epsg(32748);
  for (size_t i = 0; i < in.points.size(); ++i) in.returns.push_back(pack_returns(1 + int(i % 3), 3));
  for (int format = 0; format <= 10; ++format) {
    int min_minor = format >= 6 ? 4 : format >= 4 ? 3 : format >= 2 ? 2 : 0;
    for (int minor = min_minor; minor <= 4; ++minor) {
      SCOPED_TRACE("format " + std::to_string(format) + ", LAS 1." + std::to_string(minor));
      std::string path = dir + "/f" + std::to_string(format) + "_" + std::to_string(minor) + ".las";
      write_las(path, in, format, minor);
      PointCloud out = read_point_cloud(path);
      EXPECT_EQ(out.source, path);
      expect_same_points(in, out, 0.0005);  // millimetre quantisation
      ASSERT_EQ(out.classes.size(), in.classes.size());
      for (size_t i = 0; i < in.classes.size(); ++i) {
        // 6-10 keep the full byte (64, 200 survive); 0-5 only the low 5 bits.
        uint8_t expected = format >= 6 ? in.classes[i] : in.classes[i] & 0x1F;
        ASSERT_EQ(out.classes[i], expected) << "point " << i;
      }
      EXPECT_EQ(out.returns, in.returns);  // return number and number of returns, every format
      EXPECT_EQ(epsg_of(out.crs_wkt), 32748);
    }
  }
}

TEST(PointIo, LasFormatSixKeepsClass64AndUses64BitCount) {
  std::string path = test::temp_dir("las_64") + "/c.las";
  PointCloud in = sample_cloud(true);
  write_las(path, in, 6, 4);
  std::ifstream f(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), {});
  uint32_t legacy;
  uint64_t count;
  std::memcpy(&legacy, &bytes[107], 4);
  std::memcpy(&count, &bytes[247], 8);
  EXPECT_EQ(legacy, 0u);  // format 6 in LAS 1.4: only the 64-bit count is set
  EXPECT_EQ(count, in.points.size());
  PointCloud out = read_point_cloud(path);
  EXPECT_EQ(out.points.size(), in.points.size());
  EXPECT_EQ(std::count(out.classes.begin(), out.classes.end(), 64), 100);
  EXPECT_TRUE(out.crs_wkt.empty());
}

// An uncompressed file's records fill its bytes exactly (docs/inputs.md): a
// count one too low, or a point data offset one byte early, read silently
// before (a point dropped; every record out of step).
TEST(PointIo, LasFieldsThatAreNotTheBytesAreRefused) {
  const std::string dir = test::temp_dir("las_fields");
  PointCloud in = sample_cloud(true);
  in.crs_wkt = wkt_from_epsg(32748);
  for (auto [format, minor] : {std::pair{1, 2}, {6, 4}}) {
    const std::string path = dir + "/f" + std::to_string(format) + ".las";
    write_las(path, in, format, minor);
    std::ifstream f(path, std::ios::binary);
    const std::string good((std::istreambuf_iterator<char>(f)), {});
    const size_t count_at = minor == 4 ? 247 : 107;
    std::string fewer = good, early = good;
    const uint32_t one_less = uint32_t(in.points.size() - 1);
    std::memcpy(&fewer[count_at], &one_less, 4);
    uint32_t offset;
    std::memcpy(&offset, &early[96], 4);
    --offset;
    std::memcpy(&early[96], &offset, 4);
    for (const auto& [name, bytes] : {std::pair{"fewer", fewer}, {"early", early}}) {
      const std::string bad = dir + "/" + name + std::to_string(format) + ".las";
      write_file(bad, bytes);
      try {
        read_point_cloud(bad);
        ADD_FAILURE() << name << ": read";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(bad), std::string::npos) << what;
        EXPECT_TRUE(what.find("not the file's") != std::string::npos) << what;
      }
    }
  }
}

TEST(PointIo, LasWithoutClassesWritesUnclassified) {
  std::string path = test::temp_dir("las_nocls") + "/c.las";
  write_las(path, sample_cloud(false), 1, 2);
  PointCloud out = read_point_cloud(path);
  ASSERT_EQ(out.classes.size(), 600u);
  EXPECT_EQ(out.classes[0], 1);
}

std::string ply_header(const std::string& format, const std::string& type, size_t n, bool cls,
                       const std::string& cls_name = "class") {
  std::string h = "ply\nformat " + format + " 1.0\ncomment test\nelement vertex " +
                  std::to_string(n) + "\nproperty " + type + " x\nproperty " + type +
                  " y\nproperty " + type + " z\n";
  if (cls) h += "property uchar " + cls_name + "\n";
  return h + "element face 0\nproperty list uchar int vertex_indices\nend_header\n";
}

template <typename T>
std::string ply_binary(const PointCloud& c, bool big_endian) {
  std::string out;
  auto put = [&](const void* p, size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (big_endian) std::reverse(b.begin(), b.end());
    out += b;
  };
  for (size_t i = 0; i < c.points.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      T v = T(c.points[i][k]);
      put(&v, sizeof v);
    }
    if (!c.classes.empty()) out += char(c.classes[i]);
  }
  return out;
}

TEST(PointIo, PlyBinaryDoubleAndFloatBothEndians) {
  std::string dir = test::temp_dir("ply_bin");
  PointCloud in = sample_cloud(true);
  for (bool big : {false, true}) {
    std::string fmt = big ? "binary_big_endian" : "binary_little_endian";
    write_file(dir + "/d.ply", ply_header(fmt, "double", 600, true, "scalar_Classification") +
                                   ply_binary<double>(in, big));
    PointCloud d = read_point_cloud(dir + "/d.ply");
    expect_same_points(in, d, 1e-9);
    EXPECT_EQ(d.classes, in.classes);

    PointCloud small = in;  // float is only exact for small local coordinates
    small.classes.clear();
    for (Vec3& p : small.points) p -= Vec3(781800, 9239900, 700);
    write_file(dir + "/f.ply", ply_header(fmt, "float", 600, false) + ply_binary<float>(small, big));
    PointCloud f = read_point_cloud(dir + "/f.ply");
    expect_same_points(small, f, 1e-4);
    EXPECT_TRUE(f.classes.empty());
  }
}

TEST(PointIo, PlyAscii) {
  std::string path = test::temp_dir("ply_ascii") + "/a.ply";
  write_file(path, ply_header("ascii", "double", 3, true, "classification") +
                       "781810.123 9239979.456 781.5 6\n1 2 3 64\n-1.5 2.5e1 0 2\n");
  PointCloud c = read_point_cloud(path);
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_DOUBLE_EQ(c.points[0].y(), 9239979.456);
  EXPECT_DOUBLE_EQ(c.points[2].y(), 25.0);
  EXPECT_EQ(c.classes, (std::vector<uint8_t>{6, 64, 2}));
}

TEST(PointIo, PcdAsciiDoubleWithLabelAndBinaryFloat) {
  std::string dir = test::temp_dir("pcd");
  write_file(dir + "/a.pcd",
             "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z label\nSIZE 8 8 8 4\nTYPE F F F U\n"
             "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
             "781810.123 9239979.456 781.5 6\n781811.5 9239980.25 790 64\n");
  PointCloud a = read_point_cloud(dir + "/a.pcd");
  ASSERT_EQ(a.points.size(), 2u);
  EXPECT_NEAR(a.points[0].x(), 781810.123, 1e-9);
  EXPECT_NEAR(a.points[1].y(), 9239980.25, 1e-9);
  EXPECT_EQ(a.classes, (std::vector<uint8_t>{6, 64}));

  std::string blob;
  const float xyz[] = {1.5f, 2.5f, 3.5f, -4.0f, 5.0f, 6.25f};
  blob.assign(reinterpret_cast<const char*>(xyz), sizeof xyz);
  write_file(dir + "/b.pcd",
             "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
             "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n" + blob);
  PointCloud b = read_point_cloud(dir + "/b.pcd");
  ASSERT_EQ(b.points.size(), 2u);
  EXPECT_EQ(b.points[1], Vec3(-4.0, 5.0, 6.25));
  EXPECT_TRUE(b.classes.empty());
}

TEST(PointIo, XyzWhitespaceAndCsvWithHeader) {
  std::string dir = test::temp_dir("xyz");
  write_file(dir + "/a.xyz", "# comment\n781810.123 9239979.456 781.5\n\n1\t2\t3\n");
  PointCloud a = read_point_cloud(dir + "/a.xyz");
  ASSERT_EQ(a.points.size(), 2u);
  EXPECT_DOUBLE_EQ(a.points[0].x(), 781810.123);
  EXPECT_EQ(a.points[1], Vec3(1, 2, 3));
  EXPECT_TRUE(a.classes.empty());

  write_file(dir + "/b.csv", "x,y,z,class\r\n1.5,2.5,3.5,6\r\n4,5,6,64\r\n");
  PointCloud b = read_point_cloud(dir + "/b.csv");
  ASSERT_EQ(b.points.size(), 2u);
  EXPECT_EQ(b.points[0], Vec3(1.5, 2.5, 3.5));
  EXPECT_EQ(b.classes, (std::vector<uint8_t>{6, 64}));

  write_file(dir + "/c.txt", "10 20 30 2\n11 21 31 6\n");
  PointCloud c = read_point_cloud(dir + "/c.txt");
  EXPECT_EQ(c.classes, (std::vector<uint8_t>{2, 6}));
}

TEST(PointIo, CimahiLasCountsAndCrs) {
  C3D_REQUIRE_CIMAHI();
  PointCloud c = read_point_cloud(test::cimahi_dir() + "/cimahi.las");
  EXPECT_EQ(c.points.size(), 244685u);
  EXPECT_EQ(std::count(c.classes.begin(), c.classes.end(), 6), 200179);
  EXPECT_EQ(std::count(c.classes.begin(), c.classes.end(), 64), 44506);
  EXPECT_EQ(epsg_of(c.crs_wkt), 32748);
  // The LAS holds the same roof points as roof.ply (double precision PLY).
  PointCloud roof = read_point_cloud(test::cimahi_dir() + "/roof.ply");
  EXPECT_EQ(roof.points.size(), 200179u);
}

TEST(PointIo, InfoCommandOnCimahi) {
  C3D_REQUIRE_CIMAHI();
  std::string out;
  ASSERT_EQ(test::run_cli("info " + test::cimahi_dir() + "/cimahi.las", &out), 0) << out;
  EXPECT_NE(out.find("244,685"), std::string::npos) << out;
  EXPECT_NE(out.find("class 6: 200,179"), std::string::npos) << out;
  EXPECT_NE(out.find("class 64: 44,506"), std::string::npos) << out;
  EXPECT_NE(out.find("EPSG:32748"), std::string::npos) << out;
}

TEST(PointIo, InfoCommandOnLayerAndRaster) {
  C3D_REQUIRE_CIMAHI();
  std::string out;
  ASSERT_EQ(test::run_cli("info " + test::cimahi_dir() + "/parcels.shp " + test::cimahi_dir() +
                              "/dtm.tif",
                          &out),
            0)
      << out;
  EXPECT_NE(out.find("parcels:  30"), std::string::npos) << out;
  EXPECT_NE(out.find("NIB"), std::string::npos) << out;
  EXPECT_NE(out.find("497 x 483"), std::string::npos) << out;
  EXPECT_NE(out.find("NoData:"), std::string::npos) << out;
}

}  // namespace
}  // namespace c3d
