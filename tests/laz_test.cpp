// The LAZ decoder (core/io/laz): hand-checked arithmetic decoding, and the
// LAS/LAZ pairs of ../shared/data/laz decoded bit for bit (SHA-256 of the
// point records as the README lists them) and read into identical clouds.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "core/error.h"
#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/point_io.h"
#include "core/io/sha256.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

using laz::Decoder;

// Raw bits read straight through: value 0x12345678 over length 2^32 - 1
// gives 0x12 as the top 8 bits; the remainder 0x34568A (after renormalising
// with the fifth byte) gives 0x34.
TEST(ArithmeticDecoder, RawBitsReadThrough) {
  const uint8_t bytes[] = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC};
  Decoder dec;
  dec.start(bytes, bytes + sizeof bytes);
  EXPECT_EQ(dec.read_bits(8), 0x12u);
  EXPECT_EQ(dec.read_bits(8), 0x34u);
  EXPECT_EQ(dec.overrun(), 0u);
}

// A fresh bit model splits the interval at 4096 * ((2^32 - 1) >> 13) = 0x7FFFF000;
// a fresh two-symbol model at 16384 * ((2^32 - 1) >> 15) = 0x7FFFC000.
TEST(ArithmeticDecoder, FreshModelsSplitInHalf) {
  const uint8_t low[] = {0x7F, 0xFF, 0xBF, 0xFF}, high[] = {0x7F, 0xFF, 0xF0, 0x00};
  for (int symbol_model = 0; symbol_model < 2; ++symbol_model) {
    Decoder a, b;
    a.start(low, low + 4);
    b.start(high, high + 4);
    laz::BitModel bit_a, bit_b;
    laz::SymbolModel sym_a(2), sym_b(2);
    const uint32_t va = symbol_model ? a.decode_symbol(sym_a) : a.decode_bit(bit_a);
    const uint32_t vb = symbol_model ? b.decode_symbol(sym_b) : b.decode_bit(bit_b);
    EXPECT_EQ(va, 0u) << "value 0x7FFFBFFF lies below both splits";
    EXPECT_EQ(vb, 1u) << "value 0x7FFFF000 lies on or above both splits";
  }
}

// Bytes past the end read as zero and are counted, never read.
TEST(ArithmeticDecoder, PastTheEndReadsZero) {
  const uint8_t bytes[] = {0xAB};
  Decoder dec;
  dec.start(bytes, bytes + 1);
  EXPECT_EQ(dec.read_bits(8), 0xABu);
  EXPECT_GE(dec.overrun(), 3u);
}

std::string records_sha(const std::string& path) {
  const std::vector<uint8_t> r = read_las_records(path);
  Sha256 h;
  h.update(r.data(), r.size());
  return h.hex();
}

#define C3D_REQUIRE_LAZ() C3D_NEED(!test::laz_dir().empty(), "../shared/data/laz not found beside the checkout")

// The README's hashes: every LAZ there, and the uncompressed twins.
TEST(LazDecode, RecordsMatchKnownHashes) {
  C3D_REQUIRE_LAZ();
  const std::vector<std::pair<std::string, std::string>> known = {
      {"simple.laz", "0717948a72e6bf719db8d96ded1e76b760d73fb683347ebe3dd603832e3d5015"},
      {"liblas-generated.laz", "0717948a72e6bf719db8d96ded1e76b760d73fb683347ebe3dd603832e3d5015"},
      {"simple.las", "0717948a72e6bf719db8d96ded1e76b760d73fb683347ebe3dd603832e3d5015"},
      {"autzen_trim.laz", "f4eb6d80bf1fa507ffdcdaa73606d09041982659a50ee3895957e0b2b347f54b"},
      {"autzen_trim.las", "f4eb6d80bf1fa507ffdcdaa73606d09041982659a50ee3895957e0b2b347f54b"},
      {"1.2-with-color.copc.laz", "361eda6829430490b1bba3a2665408642d16211f6c349b2f11edf451c8164422"},
      {"las_with_several_extra_byte_bloc.laz",
       "c19b99bc99062598ede4bed3bc6648832211f51b80ac22c8095cb547d8836406"}};
  for (const auto& [file, sha] : known) EXPECT_EQ(records_sha(test::laz_dir() + "/" + file), sha) << file;
}

// The COPC file (layered chunks, variable chunk table) against its points as
// an independent decoder wrote them uncompressed.
TEST(LazDecode, CopcMatchesIndependentDecode) {
  C3D_REQUIRE_LAZ();
  const std::string dir = test::laz_dir();
  EXPECT_TRUE(read_las_records(dir + "/1.2-with-color.copc.laz") ==
              read_las_records(dir + "/1.2-with-color.copc.decoded.las"));
}

void expect_same_cloud(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_EQ(a.classes, b.classes);
  for (size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points[i], b.points[i]) << "point " << i;
  EXPECT_EQ(a.crs_wkt, b.crs_wkt);
}

// A LAZ feeds the LAS record parsing: the same cloud as its LAS twin.
TEST(LazDecode, SameCloudAsLasTwin) {
  C3D_REQUIRE_LAZ();
  const std::string dir = test::laz_dir();
  for (const char* stem : {"simple", "autzen_trim"}) {
    SCOPED_TRACE(stem);
    const PointCloud las = read_point_cloud(dir + "/" + stem + ".las");
    const PointCloud laz = read_point_cloud(dir + "/" + stem + ".laz");
    EXPECT_GT(las.points.size(), 1000u);
    expect_same_cloud(las, laz);
  }
}

// LAS 1.4 point format 7, uncompressed: the same survey as format 3.
TEST(LazDecode, Format7ReadsLikeFormat3) {
  C3D_REQUIRE_LAZ();
  const std::string dir = test::laz_dir();
  const PointCloud f3 = read_point_cloud(dir + "/autzen_trim.las");
  const PointCloud f7 = read_point_cloud(dir + "/autzen_trim_7.las");
  ASSERT_EQ(f3.points.size(), f7.points.size());
  EXPECT_EQ(f3.classes, f7.classes);
  for (size_t i = 0; i < f3.points.size(); ++i) ASSERT_LT((f3.points[i] - f7.points[i]).norm(), 1e-6) << i;
}

std::string file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void expect_laz_error(const std::string& path, const std::string& problem) {
  try {
    read_point_cloud(path);
    ADD_FAILURE() << path << ": read without error, expected " << problem;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// The LASzip bits of the format byte without a LASzip VLR: a one-line error.
TEST(LazDecode, CompressedWithoutLaszipVlr) {
  const std::string path = test::temp_dir("laz_novlr") + "/c.laz";
  PointCloud c;
  c.points = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  write_las(path, c, 1, 2);
  std::string bytes = file_bytes(path);
  bytes[104] = char(uint8_t(bytes[104]) | 0x80);
  write_bytes(path, bytes);
  expect_laz_error(path, "LAZ: compressed points but no LASzip VLR");
}

// The LASzip VLR's payload in a LAZ file's bytes (0: none).
size_t laszip_vlr(const std::string& file) {
  uint32_t point_offset;
  std::memcpy(&point_offset, file.data() + 96, 4);
  uint16_t header_size;
  std::memcpy(&header_size, file.data() + 94, 2);
  for (size_t pos = header_size; pos + 54 < point_offset;
       pos += 54 + uint8_t(file[pos + 20]) + 256 * uint8_t(file[pos + 21]))
    if (file.compare(pos + 2, 14, "laszip encoded") == 0) return pos + 54;
  return 0;
}

// Each change of `good` written to DIR/NAME<i>.laz and read: a one-line
// error naming the file and saying what its case expects.
using Damage = std::vector<std::pair<std::function<void(std::string&)>, std::string>>;
void expect_each_refused(const std::string& good, const std::string& dir, const std::string& name,
                         const Damage& cases) {
  for (size_t i = 0; i < cases.size(); ++i) {
    std::string bytes = good;
    cases[i].first(bytes);
    const std::string path = dir + "/" + name + std::to_string(i) + ".laz";
    write_bytes(path, bytes);
    expect_laz_error(path, cases[i].second);
  }
}

// Damaged LAZ files: each a one-line InputError, never a crash.
TEST(LazDecode, DamagedFilesAreInputErrors) {
  C3D_REQUIRE_LAZ();
  const std::string good = file_bytes(test::laz_dir() + "/simple.laz");
  const std::string dir = test::temp_dir("laz_damaged");
  uint32_t point_offset;
  std::memcpy(&point_offset, good.data() + 96, 4);
  const size_t vlr = laszip_vlr(good);
  ASSERT_NE(vlr, 0u) << "no LASzip VLR in simple.laz";
  expect_each_refused(good, dir, "damaged", {
      {[](std::string& b) { b.resize(b.size() - 100); }, "chunk table offset"},
      {[&](std::string& b) { b.resize(point_offset + 4); }, "the 4 compressed bytes"},
      {[&](std::string& b) { b[vlr] = 9; }, "unknown LASzip compressor 9"},
      {[&](std::string& b) { b[vlr + 34 + 4] = 7; }, "item type 6 version 7"},
      {[](std::string& b) { std::memset(&b[107], 0x7F, 4); }, "times the"},
  });
}

void expect_flips_caught(const std::string& path, size_t step);

// What the header and the LASzip VLR claim, against the data: a point count
// 1,000 too low or one too high, a chunk size one short. Each is an error
// naming the chunk, never fewer points or a phantom one (autzen_trim.laz:
// 110,000 points in chunks of 50,000).
TEST(LazDecode, ClaimsThatAreNotTheDataAreErrors) {
  C3D_REQUIRE_LAZ();
  const std::string good = file_bytes(test::laz_dir() + "/autzen_trim.laz");
  const size_t vlr = laszip_vlr(good);
  ASSERT_NE(vlr, 0u);
  uint32_t count, chunk;
  std::memcpy(&count, good.data() + 107, 4);
  std::memcpy(&chunk, good.data() + vlr + 12, 4);
  ASSERT_EQ(count, 110000u);
  ASSERT_EQ(chunk, 50000u);
  const auto set = [](std::string& b, size_t at, uint32_t v) { std::memcpy(&b[at], &v, 4); };
  expect_each_refused(good, test::temp_dir("laz_claims"), "claim", {
      {[&](std::string& b) { set(b, 107, count - 1000); }, "chunk 3 of 3"},
      {[&](std::string& b) { set(b, 107, count + 1); }, "chunk 3 of 3"},
      {[&](std::string& b) { set(b, 107, 99000); }, "too few to fill the chunk table's 3 chunks"},
      {[&](std::string& b) { set(b, vlr + 12, chunk - 1); }, "chunk 1 of 3"},
  });
}

// Where in a LAZ's point data a byte lies: its chunk table's chunks, from
// the 8-byte table offset after the point data's start.
struct ChunkBytes {
  size_t begin = 0, end = 0;  // the compressed points, table excluded
};

ChunkBytes point_bytes(const std::string& file) {
  uint32_t point_offset;
  std::memcpy(&point_offset, file.data() + 96, 4);
  int64_t table;
  std::memcpy(&table, file.data() + point_offset, 8);
  return {size_t(point_offset) + 8, size_t(table)};
}

// One byte of a LAZ's compressed points changed, anywhere: the read fails
// naming the chunk, or its records are the original's. LAZ has no checksum:
// what catches a damaged byte is that a chunk's arithmetic streams must end
// where its bytes do. A change the decoder absorbs and still ends in step
// cannot be seen: 2 of 2,546 bytes of simple.laz (other points, by at most
// 4 cm); every 97th byte of autzen_trim.laz, 6,198 of them, all errors.
// Here every 7th byte of simple.laz and every 4999th of autzen_trim.laz,
// each xor 0x10: one change in a thousand at most goes unseen.
TEST(LazDecode, ADamagedByteIsAnErrorNamingItsChunk) {
  C3D_REQUIRE_LAZ();
  for (const auto& [name, step] : {std::pair<std::string, size_t>{"simple.laz", 7}, {"autzen_trim.laz", 4999}})
    expect_flips_caught(test::laz_dir() + "/" + name, step);
}

void expect_flips_caught(const std::string& path, size_t step) {
  const std::string good = file_bytes(path);
  const std::vector<uint8_t> records = read_las_records(path);
  const std::string dir = test::temp_dir("laz_flipped");
  const ChunkBytes pts = point_bytes(good);
  int errors = 0, same = 0, unseen = 0;
  for (size_t at = pts.begin + 40; at < pts.end; at += step) {
    std::string bytes = good;
    bytes[at] = char(bytes[at] ^ 0x10);
    const std::string damaged = dir + "/flipped.laz";
    write_bytes(damaged, bytes);
    try {
      if (read_las_records(damaged) == records) ++same;
      else ++unseen;
    } catch (const InputError& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find("chunk"), std::string::npos) << e.what();
    }
  }
  std::printf("%s: %d errors, %d reads unchanged, %d changed unseen\n", path.c_str(), errors, same, unseen);
  EXPECT_LE(unseen * 1000, errors + same + unseen) << path;
  EXPECT_GT(errors, 0.9 * (errors + same + unseen)) << path;
}

}  // namespace
}  // namespace c3d
