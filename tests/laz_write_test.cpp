// The LAZ writer (core/io/laz/laz_writer.h): the encoder against the
// decoder symbol by symbol, and every LAZ of ../shared/data/laz decoded,
// written again and decoded to the same records (the README's hashes).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/error.h"
#include "core/io/laz/arithmetic_encoder.h"
#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_reader.h"
#include "core/io/laz/laz_writer.h"
#include "core/io/point_io.h"
#include "core/io/sha256.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

// Symbols, bits and raw bits of every width through one stream and back.
TEST(LazEncoder, SymbolsBitsAndRawBitsRoundTrip) {
  std::mt19937 rng(3);
  laz::SymbolModel small(5), large(300);
  laz::BitModel bit;
  laz::Encoder enc;
  std::vector<uint32_t> values;
  for (int i = 0; i < 20000; ++i) {
    const uint32_t s = rng() % 5, l = (rng() % 7 == 0) ? rng() % 300 : 17, b = rng() % 4 == 0;
    const uint32_t width = 1 + rng() % 32, raw = width == 32 ? rng() : rng() & ((1u << width) - 1);
    enc.encode_symbol(small, s);
    enc.encode_symbol(large, l);
    enc.encode_bit(bit, b);
    enc.write_bits(width, raw);
    values.insert(values.end(), {s, l, b, width, raw});
  }
  const std::vector<uint8_t> bytes = enc.finish();
  laz::SymbolModel small_d(5), large_d(300);
  laz::BitModel bit_d;
  laz::Decoder dec;
  dec.start(bytes.data(), bytes.data() + bytes.size());
  for (size_t i = 0; i < values.size(); i += 5) {
    ASSERT_EQ(dec.decode_symbol(small_d), values[i]) << i;
    ASSERT_EQ(dec.decode_symbol(large_d), values[i + 1]) << i;
    ASSERT_EQ(dec.decode_bit(bit_d), values[i + 2]) << i;
    ASSERT_EQ(dec.read_bits(values[i + 3]), values[i + 4]) << i;
  }
  EXPECT_EQ(dec.overrun(), 0u) << "the padding covers the decoder's read-ahead";
}

// Integers of 16 and 32 bits, including the extremes: -2^31 is the one
// corrector whose bit length (32) carries no further bits.
TEST(LazEncoder, IntegersRoundTripIncludingExtremes) {
  std::mt19937 rng(5);
  std::vector<std::pair<int32_t, int32_t>> pairs = {
      {0, INT32_MIN}, {INT32_MIN, 0}, {INT32_MAX, INT32_MIN}, {-1, INT32_MAX}, {5, 5}, {0, 1}, {1, 0}};
  for (int i = 0; i < 5000; ++i) pairs.push_back({int32_t(rng()), int32_t(rng() % 2000) - 1000});
  laz::IntegerCoder c32(32, 2), c16(16, 1);
  laz::Encoder enc;
  for (const auto& [pred, real] : pairs) {
    c32.compress(enc, pred, real, 1);
    c16.compress(enc, pred & 0xFFFF, real & 0xFFFF);
  }
  const std::vector<uint8_t> bytes = enc.finish();
  laz::IntegerCoder d32(32, 2), d16(16, 1);
  laz::Decoder dec;
  dec.start(bytes.data(), bytes.data() + bytes.size());
  for (const auto& [pred, real] : pairs) {
    ASSERT_EQ(d32.decompress(dec, pred, 1), real) << pred;
    ASSERT_EQ(d16.decompress(dec, pred & 0xFFFF), real & 0xFFFF) << pred;
  }
}

template <typename T>
T load(const std::vector<uint8_t>& b, size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// The uncompressed LAS a LAZ stands for: header and VLRs without the LASzip
// VLR, the records our decoder gives, no EVLRs.
std::vector<uint8_t> decompressed(const std::string& laz_path) {
  const std::vector<uint8_t> laz = file_bytes(laz_path);
  std::vector<uint8_t> out(laz.begin(), laz.begin() + load<uint16_t>(laz, 94));
  uint32_t kept = 0;
  size_t pos = out.size();
  for (uint32_t i = 0; i < load<uint32_t>(laz, 100); ++i) {
    const size_t size = 54 + load<uint16_t>(laz, pos + 20);
    if (std::strncmp(reinterpret_cast<const char*>(&laz[pos + 2]), laz::kLaszipUserId, 16) != 0) {
      out.insert(out.end(), laz.begin() + pos, laz.begin() + pos + size);
      ++kept;
    }
    pos += size;
  }
  const uint32_t offset = uint32_t(out.size());
  std::memcpy(&out[96], &offset, 4);
  std::memcpy(&out[100], &kept, 4);
  out[104] &= 0x3F;
  if (out.size() >= 375 && out[25] >= 4) std::memset(&out[235], 0, 12);  // no EVLRs
  const std::vector<uint8_t> records = read_las_records(laz_path);
  out.insert(out.end(), records.begin(), records.end());
  return out;
}

std::string sha(const std::vector<uint8_t>& b) {
  Sha256 h;
  h.update(b.data(), b.size());
  return h.hex();
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& b) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// The compressed chunks (between the chunk table offset and the table) of two LAZ files.
bool same_chunks(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  auto chunks = [](const std::vector<uint8_t>& f) {
    const uint32_t at = load<uint32_t>(f, 96);
    return std::vector<uint8_t>(f.begin() + at + 8, f.begin() + load<int64_t>(f, at));
  };
  return chunks(a) == chunks(b);
}

// Every shared LAZ (formats 3, 7 and 8; v2 and layered; extra bytes):
// decoded, written by our encoder, decoded again to the same records, in a
// size close to the original's. Where LASzip wrote chunks of 50,000 points
// (all but the COPC file, whose chunks follow its octree) our chunks are
// byte for byte LASzip's.
TEST(LazWrite, SharedFilesRoundTripBitExact) {
  C3D_NEED(!test::laz_dir().empty(), "../shared/data/laz not found beside the checkout");
  const std::string out = test::temp_dir("laz");
  for (const auto& entry : std::filesystem::directory_iterator(test::laz_dir())) {
    if (entry.path().extension() != ".laz") continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const std::vector<uint8_t> records = read_las_records(entry.path().string());
    for (uint32_t chunk : {laz::kDefaultChunkSize, 1000u}) {
      const std::vector<uint8_t> laz = laz::compress_las(decompressed(entry.path().string()), chunk);
      const std::string path = out + "/" + std::to_string(chunk) + "_" + name;
      write_bytes(path, laz);
      EXPECT_EQ(sha(read_las_records(path)), sha(records)) << "chunks of " << chunk;
      const double ratio = double(laz.size()) / double(entry.file_size());
      std::cout << name << " chunks of " << chunk << ": " << laz.size() << " bytes, " << ratio
                << " x the original LAZ\n";
      if (chunk == laz::kDefaultChunkSize) EXPECT_LT(ratio, 1.15);
      if (chunk == laz::kDefaultChunkSize && name.find("copc") == std::string::npos)
        EXPECT_TRUE(same_chunks(file_bytes(entry.path().string()), laz)) << "LASzip wrote other chunk bytes";
    }
  }
}

// Not a test of its own (tests/CMakeLists.txt leaves ForScript_ out of
// ctest): tests/laz_perf_check.sh runs it to have the shared LAZ files written
// again by our encoder into $C3D_LAZ_OUT (chunks of 50,000 and 1,000 points),
// for laz-perf to decode.
TEST(LazWrite, ForScript_RewriteSharedFiles) {
  const char* out = std::getenv("C3D_LAZ_OUT");
  ASSERT_TRUE(out && !test::laz_dir().empty()) << "run by tests/laz_perf_check.sh, with ../shared/data/laz";
  std::filesystem::create_directories(out);
  for (const auto& entry : std::filesystem::directory_iterator(test::laz_dir())) {
    if (entry.path().extension() != ".laz") continue;
    for (uint32_t chunk : {laz::kDefaultChunkSize, 1000u})
      write_bytes(std::string(out) + "/" + std::to_string(chunk) + "_" + entry.path().filename().string(),
                  laz::compress_las(decompressed(entry.path().string()), chunk));
  }
}

// A cloud written as LAZ reads back as the same cloud as its LAS.
TEST(LazWrite, WriteLazReadsLikeWriteLas) {
  PointCloud cloud;
  std::mt19937 rng(9);
  for (int i = 0; i < 70000; ++i) {
    cloud.points.push_back(Vec3(500000 + (rng() % 100000) * 0.001, 9e6 + (rng() % 100000) * 0.001,
                                (rng() % 30000) * 0.001));
    cloud.classes.push_back(uint8_t(std::array<int, 4>{2, 6, 64, 5}[rng() % 4]));
  }
  const std::string dir = test::temp_dir("cloud");
  for (int format : {0, 1, 3, 6, 7, 8}) {
    SCOPED_TRACE(format);
    const int minor = format >= 6 ? 4 : 2;
    write_las(dir + "/c.las", cloud, format, minor);
    write_laz(dir + "/c.laz", cloud, format, minor);
    EXPECT_EQ(read_las_records(dir + "/c.las"), read_las_records(dir + "/c.laz"));
    const PointCloud back = read_point_cloud(dir + "/c.laz");
    EXPECT_EQ(back.points, read_point_cloud(dir + "/c.las").points);
    EXPECT_LT(std::filesystem::file_size(dir + "/c.laz"), std::filesystem::file_size(dir + "/c.las") / 2);
  }
}

// What cannot be written says why, naming the file.
TEST(LazWrite, BadArgumentsGiveClearErrors) {
  PointCloud cloud;
  cloud.points = {Vec3(1, 2, 3)};
  const std::string dir = test::temp_dir("bad");
  try {
    write_laz(dir + "/w.laz", cloud, 4, 3);
    FAIL() << "format 4 written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point format 4 cannot be written as LAZ"), std::string::npos) << e.what();
  }
  EXPECT_THROW(laz::laszip_vlr_for(3, 20), laz::FormatError);  // records shorter than the format
  EXPECT_THROW(laz::laszip_vlr_for(1, 28, 0), laz::FormatError);
  write_laz(dir + "/ok.laz", cloud, 6, 4);
  EXPECT_THROW(laz::compress_las(file_bytes(dir + "/ok.laz")), laz::FormatError);  // compressed already
  EXPECT_THROW(laz::compress_las(std::vector<uint8_t>(100, 0)), laz::FormatError);
  write_las(dir + "/v.las", cloud, 6, 4);
  std::vector<uint8_t> las = file_bytes(dir + "/v.las");
  const uint32_t one = 1;
  std::memcpy(&las[100], &one, 4);  // a VLR count the header has no room for
  EXPECT_THROW(laz::compress_las(las), laz::FormatError);
  EXPECT_EQ(read_point_cloud(dir + "/ok.laz").points, cloud.points);
}

}  // namespace
}  // namespace c3d
