// Issue 35, "no crash": each reader refuses damaged or hostile input with an
// InputError naming the file and what it claims, before anything is allocated
// or handed to a library that would crash on it. The inputs are the findings
// (by hand and by tests/fuzz), minimized, as inline bytes.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <typeinfo>

#include <sys/resource.h>

#include "cadastre/parcels.h"
#include "core/config/config.h"
#include "core/error.h"
#include "core/io/crs.h"
#include "core/io/dtm_io.h"
#include "core/io/mesh_io.h"
#include "core/io/point_io.h"
#include "core/log.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

// The reader must throw InputError naming the file and saying `problem`;
// anything else (a return, bad_alloc, length_error) fails the test.
void expect_refused(const std::function<void()>& read, const std::string& file, const std::string& problem) {
  try {
    read();
    ADD_FAILURE() << file << ": read without an error; expected '" << problem << "'";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(file), std::string::npos) << "file not named: " << m;
    EXPECT_NE(m.find(problem), std::string::npos) << "expected '" << problem << "' in: " << m;
  } catch (const std::exception& e) {
    ADD_FAILURE() << file << ": " << typeid(e).name() << " '" << e.what() << "', not an InputError";
  }
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), {});
}

template <typename T>
std::string raw(T v) {
  return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}

// A LAS 1.4 file of 10 points at UTM coordinates.
std::string las_bytes(const std::string& dir) {
  PointCloud c;
  for (int i = 0; i < 10; ++i) c.points.emplace_back(781800 + i, 9240000 + i, 790);
  c.classes.assign(10, 6);
  write_las(dir + "/good.las", c, 6, 4);
  return read_bytes(dir + "/good.las");
}

TEST(ReaderLimits, LasZOffsetBeyondFloatRangeNamesThePoint) {
  const std::string dir = test::temp_dir("las_offset");
  // The header check (plausibility) refuses it first, the per-point check would next.
  std::string b = las_bytes(dir);
  const double offset = 1e308;
  std::memcpy(&b[155 + 16], &offset, 8);  // Z offset
  write_bytes(dir + "/zoff.las", b);
  expect_refused([&] { read_point_cloud(dir + "/zoff.las"); }, "zoff.las", "Z offset 1e+308");
}

TEST(ReaderLimits, OnePointAtZ35e38IsRefusedInEveryFormat) {
  const std::string dir = test::temp_dir("huge_z");
  write_bytes(dir + "/p.xyz", "1 2 3\n4 5 3.5e38\n");
  expect_refused([&] { read_point_cloud(dir + "/p.xyz"); }, "p.xyz", "beyond +-1e17 at line 2 (z = 3.5e+38)");
  write_bytes(dir + "/p.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                              "property double z\nend_header\n1 2 3\n4 5 3.5e38\n");
  expect_refused([&] { read_point_cloud(dir + "/p.ply"); }, "p.ply", "beyond +-1e17 at point 1");
  write_bytes(dir + "/b.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
                              "property double y\nproperty double z\nend_header\n" +
                                  raw(1.0) + raw(2.0) + raw(3.5e38));
  expect_refused([&] { read_point_cloud(dir + "/b.ply"); }, "b.ply", "beyond +-1e17 at point 0");
  write_bytes(dir + "/p.pcd", "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nDATA ascii\n"
                              "1 2 3\n4 5 3.5e38\n");
  expect_refused([&] { read_point_cloud(dir + "/p.pcd"); }, "p.pcd", "beyond +-1e17 at point 1");
  write_bytes(dir + "/m.obj", "v 0 0 0\nv 1 0 3.5e38\nv 1 1 0\nf 1 2 3\n");
  expect_refused([&] { read_mesh_groups(dir + "/m.obj"); }, "m.obj", "beyond +-1e17 at line 2");
}

TEST(ReaderLimits, PlyCountsAreCheckedAgainstTheFileBeforeAllocating) {
  const std::string dir = test::temp_dir("ply_counts");
  const std::string head = "ply\nformat ascii 1.0\nelement vertex ";
  const std::string props = "\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
  write_bytes(dir + "/a.ply", head + "4294967295" + props);  // was std::bad_alloc
  expect_refused([&] { read_point_cloud(dir + "/a.ply"); }, "a.ply", "header claims 4294967295 'vertex' records");
  write_bytes(dir + "/n.ply", head + "-1" + props);  // was vector::_M_default_append
  expect_refused([&] { read_point_cloud(dir + "/n.ply"); }, "n.ply", "no valid count ('-1')");
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement face 4611686018427387904\nproperty int a\n"
                    "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  write_bytes(dir + "/b.ply", bin + std::string(12, '\0'));  // 2^62 x 4 bytes overflowed the skip
  expect_refused([&] { read_point_cloud(dir + "/b.ply"); }, "b.ply", "header claims 4611686018427387904 'face'");
}

TEST(ReaderLimits, PcdHeaderLineOutOfPlaceAndHugeWidth) {
  const std::string dir = test::temp_dir("pcd_header");
  // tests/fuzz, seed 1, iteration 3, minimized: PCL's reader crashed (SIGSEGV).
  write_bytes(dir + "/order.pcd", "7 8\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
                                  "DATA ascii\n1 2 3\n");
  expect_refused([&] { read_point_cloud(dir + "/order.pcd"); }, "order.pcd", "PCD header line '7'");
  write_bytes(dir + "/wide.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967295\nHEIGHT 1\n"
                                 "POINTS 4294967295\nDATA binary\n123456789012");  // was std::bad_alloc
  expect_refused([&] { read_point_cloud(dir + "/wide.pcd"); }, "wide.pcd", "header claims 4294967295 points");
  write_bytes(dir + "/lzf.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nDATA binary_compressed\n" +
                                    raw(uint32_t(4)) + raw(uint32_t(12)) + std::string("\xe0\xff\xff\x00", 4));
  expect_refused([&] { read_point_cloud(dir + "/lzf.pcd"); }, "lzf.pcd", "damaged (LZF)");
}

TEST(ReaderLimits, PcdCompressedRoundTripStillReads) {
  const std::string dir = test::temp_dir("pcd_lzf");
  // "binary_compressed" from PCL's writer: x y z float, label uint, 2 points; LZF literal runs.
  std::string soa = raw(1.5f) + raw(2.5f) + raw(3.0f) + raw(4.0f) + raw(10.0f) + raw(11.0f) +
                    raw(uint32_t(2)) + raw(uint32_t(6));
  std::string lzf = std::string(1, char(31)) + soa.substr(0, 32);  // one literal run of 32 bytes
  write_bytes(dir + "/c.pcd", "FIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 2\n"
                              "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary_compressed\n" +
                                  raw(uint32_t(lzf.size())) + raw(uint32_t(32)) + lzf);
  PointCloud c = read_point_cloud(dir + "/c.pcd");
  ASSERT_EQ(c.points.size(), 2u);
  EXPECT_EQ(c.points[1], Vec3(2.5, 4.0, 11.0));
  EXPECT_EQ(c.classes, (std::vector<uint8_t>{2, 6}));
}

TEST(ReaderLimits, LasEvlrOffsetNearTwoToThe64DoesNotWrapAround) {
  const std::string dir = test::temp_dir("las_evlr");
  std::string b = las_bytes(dir);
  const uint64_t offset = ~uint64_t(0) - 16;  // pos + 60 wrapped to 43: a read 2^64 bytes away
  const uint32_t count = 1;
  std::memcpy(&b[235], &offset, 8);
  std::memcpy(&b[243], &count, 4);
  write_bytes(dir + "/evlr.las", b);
  EXPECT_EQ(read_point_cloud(dir + "/evlr.las").points.size(), 10u);  // a damaged EVLR spoils no point
}

TEST(ReaderLimits, Dtm200000SquaredIsRefusedBeforeAllocating) {
  const std::string path = test::temp_dir("dtm_huge") + "/huge.tif";
  GDALAllRegister();
  const char* options[] = {"TILED=YES", "BLOCKXSIZE=4096", "BLOCKYSIZE=4096", "SPARSE_OK=TRUE", "BIGTIFF=YES", nullptr};
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
      path.c_str(), 200000, 200000, 1, GDT_Float32, const_cast<char**>(options));
  ASSERT_TRUE(ds);
  double gt[6] = {700000, 0.5, 0, 9300000, 0, -0.5};
  ds->SetGeoTransform(gt);
  GDALClose(ds);
  expect_refused([&] { read_dtm(path); }, "huge.tif", "raster of 200000 x 200000 cells, more than the");
}

TEST(ReaderLimits, DtmGeotransformBeyondTheEarthIsRefused) {
  const std::string path = test::temp_dir("dtm_gt") + "/far.tif";
  GDALAllRegister();
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), 4, 4, 1, GDT_Float32,
                                                                            nullptr);
  double gt[6] = {1e300, 1e300, 0, 0, 0, -1};
  ds->SetGeoTransform(gt);
  GDALClose(ds);
  expect_refused([&] { read_dtm(path); }, "far.tif", "raster extent reaches");
}

// CPU seconds f takes, its child processes' included (the suite runs tests
// in parallel: the clock would measure the machine's load).
double cpu_seconds(const std::function<void()>& f) {
  const auto used = [] {
    double s = 0;
    for (int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
      rusage r{};
      getrusage(who, &r);
      s += double(r.ru_utime.tv_sec + r.ru_stime.tv_sec) + 1e-6 * double(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
    }
    return s;
  };
  const double before = used();
  f();
  return used() - before;
}

// A north-up GeoTIFF of nx x ny cells, NoData (-9999) but for `valid` (cell
// index, height) pairs.
std::string write_sparse_dtm(const std::string& path, int nx, int ny,
                             const std::vector<std::pair<size_t, float>>& valid) {
  GDALAllRegister();
  const char* options[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), nx, ny, 1, GDT_Float32,
                                                                            const_cast<char**>(options));
  double gt[6] = {781790, 1, 0, 9240010, 0, -1};
  ds->SetGeoTransform(gt);
  std::vector<float> z(size_t(nx) * ny, -9999.0f);
  for (const auto& [cell, h] : valid) z[cell] = h;
  ds->GetRasterBand(1)->SetNoDataValue(-9999);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, nx, ny, z.data(), nx, ny, GDT_Float32, 0, 0), CE_None);
  GDALClose(ds);
  return path;
}

// The warnings read_dtm(path) logs, and the DTM; log lines go to stderr again after.
Dtm read_dtm_warnings(const std::string& path, std::vector<std::string>& warnings) {
  struct ToStderrAfter {
    ~ToStderrAfter() {
      log::set_sink([](log::Level, const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
    }
  } after;
  log::set_sink([&](log::Level l, const std::string& m) {
    if (l >= log::Level::Warn) warnings.push_back(m);
  });
  return read_dtm(path);
}

// tests/fuzz, seed 1, iteration 1085 (the deflate-tiled seed with its width
// set to 18192): a 2 KB GeoTIFF that is NoData but for a few cells kept
// GDALFillNodata busy for 26 s. It is filled in tiles now (1024 cells and the
// search at most 256 around); the tiles with no valid cell within that reach
// take the nearest terrain's mean height (FarTerrain), with one warning.
TEST(ReaderLimits, NoDataStripFillIsBounded) {
  std::vector<std::pair<size_t, float>> valid;
  for (int i = 0; i < 16; ++i) valid.push_back({size_t(i), 780.0f + float(i)});
  const std::string path = write_sparse_dtm(test::temp_dir("dtm_strip") + "/strip.tif", 18192, 12, valid);
  std::vector<std::string> warnings;
  const Dtm d = read_dtm_warnings(path, warnings);
  EXPECT_EQ(d.nx, 18192);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("strip.tif: cells 1024..2047 x 0..11 (and maybe others) have no valid height within "
                             "256 cells"), std::string::npos) << warnings[0];
  for (float v : d.z) ASSERT_TRUE(v >= 780.0f && v <= 795.0f);
  EXPECT_FLOAT_EQ(d.z.back(), 787.5f);  // the mean of the one block with terrain
}

// Fuzz.ReadersSanitized on a fresh machine (target dtm, seed input
// geotiff-strips, --seed 1, iteration 4948): 16 x 31,500 cells, NoData but
// for 186 in the first rows, its StripByteCounts tag broken. Each tile far
// from those rows doubled its margin until it reached them and filled all of
// that again (9.5 s without sanitizers, a hang with them). Its bytes:
const char* const kFuzzDtmHang =
    "49492a0008000000100000010300010000001000000001010300010000000c7b000002010300"
    "0100000020000000030103000100000001000000060103000100000001000000110104000100"
    "00007a01000015010300010000000100000016010300010000000c0000001701040001000000"
    "000300001c010300010000000100000053010300010000000300ffff0e830c0003000000ce00"
    "000082840c0006000000e6000000af8703002000000016010000b18702001e00000056010000"
    "81a40200060000007401000000000000000000000000f03f000000000000f03f000000000000"
    "000000000000000000000000000000000000000000000000000000000000bcdb274100000040"
    "b99f61410000000000000000017f010000000700000400000100010001040000010001000204"
    "b187160000000108b187070016000608000001008e23000c00000100ec7f040c000001002923"
    "574753203834202f2055544d207a6f6e65203438537c5747532038347c002d39393939000000"
    "434466064344cd0c4344331343449a194344003c1cc666264344cd2c4344333343449a394344"
    "0040434466464344cd4c4344335343449a594344006043440000434466064344cd0c43443313"
    "43449a1943440020434466264344cd2c4344333343449a3943440040434466464344cd4c4344"
    "335343449a594344006043440000434466064344cd0c4344331343449a194344002043446626"
    "4344cd2c4344333343449a394344003c1cc666464344cd4c4344335343449a59434400604344"
    "0000434466064344cd0c4344331343449a1943440020434466264344cd2c4344333343449a39"
    "43440040434466464344cd4c4344335343449a594344006043440000434466064344cd0c4344"
    "331343449a1943440020434466264344cd2c4344333343449a3943440040434466464344cd4c"
    "4344335343449a594344003c1cc60000434466064344cd0c4344331343449a19434400204344"
    "66264344cd2c4344333343449a3943440040434466464344cd4c4344335343449a5943440060"
    "43440000434466064344cd0c4344331343449a1943440020434466264344cd2c434433334344"
    "9a3943440040434466464344cd4c4344335343449a594344006043440000434466064344cd0c"
    "434433134344003c1cc60020434466264344cd2c4344333343449a3943440040434466464344"
    "cd4c4344335343449a594344006043440000434466064344cd0c4344331343449a1943440020"
    "434466264344cd2c4344333343449a3943440040434466464344cd4c4344335343449a594344"
    "006043440000434466064344cd0c4344331343449a1943440020434466264344cd2c43443333"
    "4344003c1cc60040434466464344cd4c4344335343449a594344006043440000434466064344"
    "cd0c4344331343449a1943440020434466264344cd2c4344333343449a394344004043446646"
    "4344cd4c4344335343449a594344006043440000434466064344cd0c4344331343449a194344"
    "0020434466264344cd2c4344333343449a3943440040434466464344cd4c434433534344003c"
    "1cc600604344";

std::string from_hex(const std::string& hex) {
  std::string bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) bytes.push_back(char(std::stoi(hex.substr(i, 2), nullptr, 16)));
  return bytes;
}

TEST(ReaderLimits, FuzzDtmHangReadsInUnderASecond) {
  const std::string path = test::temp_dir("fuzz_dtm_hang") + "/hang.tif";
  write_bytes(path, from_hex(kFuzzDtmHang));
  Dtm d;
  std::vector<std::string> warnings;
  EXPECT_LT(cpu_seconds([&] { d = read_dtm_warnings(path, warnings); }), 1.0);
  ASSERT_EQ(d.z.size(), size_t(16) * 31500);
  for (float v : d.z) ASSERT_TRUE(v >= 780.0f && v <= 782.0f) << v;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("hang.tif: cells 0..15 x 1024..2047"), std::string::npos) << warnings[0];
  // `info` describes the file as it is, filling nothing.
  std::string out;
  EXPECT_LT(cpu_seconds([&] { EXPECT_EQ(test::run_cli("info " + path, &out), 0) << out; }), 1.0);
  EXPECT_NE(out.find("16 x 31500"), std::string::npos) << out;
}

// 10^6 cells: all NoData is refused, nearly all NoData (a corner of terrain,
// as one tile and as a strip of tiles) filled, each in under a CPU-second.
TEST(ReaderLimits, MillionNoDataCellsFillInUnderASecond) {
  const std::string dir = test::temp_dir("dtm_million");
  const std::string none = write_sparse_dtm(dir + "/none.tif", 1000, 1000, {});
  EXPECT_LT(cpu_seconds([&] { expect_refused([&] { read_dtm(none); }, "none.tif", "all cells NoData"); }), 1.0);
  for (const auto& [nx, ny] : {std::pair{1000, 1000}, std::pair{16, 62500}}) {
    std::vector<std::pair<size_t, float>> corner;
    for (int v = 0; v < 4; ++v)
      for (int u = 0; u < 4; ++u) corner.push_back({size_t(v) * nx + u, 100.0f + float(u + v)});
    const std::string path = write_sparse_dtm(dir + "/corner.tif", nx, ny, corner);
    Dtm d;
    std::vector<std::string> warnings;
    EXPECT_LT(cpu_seconds([&] { d = read_dtm_warnings(path, warnings); }), 1.0) << nx << " x " << ny;
    ASSERT_EQ(d.z.size(), size_t(1000000));
    for (float v : d.z) ASSERT_TRUE(v >= 100.0f && v <= 106.0f) << v;
  }
}

TEST(ReaderLimits, ParcelVertexBeyondRangeNamesTheParcel) {
  const std::string path = test::temp_dir("parcel_far") + "/far.geojson";
  write_bytes(path, R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"NIB": "A-1"},
 "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 1e300], [0, 0]]]}}]})");
  expect_refused([&] { read_parcels(path, parcel_fields("NIB")); }, "parcel A-1", "beyond +-1e17 at vertex 2");
}

// tests/fuzz against the old readers, seed 1: a class of 793 (UBSan: outside
// the range of unsigned char) and a parcel vertex of NaN (GEOS threw
// IllegalArgumentException, not an InputError).
TEST(ReaderLimits, ClassBeyondAByteAndNaNParcelVertexAreInputErrors) {
  const std::string dir = test::temp_dir("fuzz_found");
  write_bytes(dir + "/c.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                              "property float z\nproperty uchar classification\nend_header\n1 2 3 793\n");
  expect_refused([&] { read_point_cloud(dir + "/c.ply"); }, "c.ply", "point 0: class value 793.000000 is not");
  write_bytes(dir + "/nan.geojson", R"({"type": "FeatureCollection", "features": [{"type": "Feature",
 "properties": {"NIB": "B-2"}, "geometry": {"type": "Polygon",
 "coordinates": [[[0, 0], [10, 0], [10, 10], [0, -1e400], [0, 0]]]}}]})");
  expect_refused([&] { read_parcels(dir + "/nan.geojson", parcel_fields("NIB")); }, "parcel B-2",
                 "NaN/inf coordinate at vertex 3 (y = -inf)");
}

TEST(ReaderLimits, ConfigIntegerBeyond32BitsIsAnError) {
  const std::string path = test::temp_dir("config_int") + "/c.toml";
  std::string text = default_config_toml();
  const std::string key = "outlier_neighbours = ";
  const size_t at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  text.replace(at + key.size(), text.find('\n', at) - at - key.size(), "9223372036854775807");
  write_bytes(path, text);  // int(9.2e18) was undefined behaviour and came out negative
  expect_refused([&] { load_config(path); }, "c.toml", "integer 9223372036854775807 is beyond the 32-bit range");
}

TEST(ReaderLimits, MeshPlyFloatListCountAndNaNIndexAreRefused) {
  const std::string dir = test::temp_dir("mesh_ply");
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list float int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n";
  write_bytes(dir + "/count.ply", head + "1e300 0 1 2\n");  // long(1e300) was undefined behaviour
  expect_refused([&] { read_mesh_groups(dir + "/count.ply"); }, "count.ply", "bad list length");
  write_bytes(dir + "/spin.ply", "ply\nformat ascii 1.0\nelement nothing 9223372036854775807\nend_header\n");
  EXPECT_NO_THROW(read_mesh_groups(dir + "/spin.ply"));  // records without properties: nothing to read
}

TEST(ReaderLimits, ADirectoryOrAnOverlongNameIsAnInputError) {
  const std::string dir = test::temp_dir("not_a_file");
  std::filesystem::create_directories(dir + "/d.las");  // was std::bad_alloc (ext4 reports 2^63 bytes)
  expect_refused([&] { read_point_cloud(dir + "/d.las"); }, "d.las", "not a regular file");
  std::filesystem::create_directories(dir + "/d.obj");
  expect_refused([&] { read_mesh_groups(dir + "/d.obj"); }, "d.obj", "not a regular file");
  const std::string longname = dir + "/" + std::string(300, 'a') + ".xyz";  // was filesystem_error
  expect_refused([&] { read_point_cloud(longname); }, std::string(300, 'a'), "cannot read (File name too long)");
}

}  // namespace
}  // namespace c3d
