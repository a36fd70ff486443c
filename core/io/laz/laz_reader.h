#pragma once
// LAZ (LASzip-compressed LAS) point data: the LASzip VLR, the chunk table
// (fixed or variable chunk sizes; COPC files are LAZ with variable chunks)
// and the chunks, decoded into the raw point records a LAS file would hold,
// so the LAS reader parses them as it parses uncompressed points.
// Throws laz::FormatError on damaged or unsupported data.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace c3d::laz {

// The LASzip VLR (user id "laszip encoded", record id 22204).
constexpr uint16_t kLaszipRecordId = 22204;
constexpr const char* kLaszipUserId = "laszip encoded";

// LASzip's item types and compressors (what the VLR names), for reader and writer.
enum ItemType : uint16_t {
  kByte = 0, kPoint10 = 6, kGpsTime11 = 7, kRgb12 = 8, kWavePacket13 = 9,
  kPoint14 = 10, kRgb14 = 11, kRgbNir14 = 12, kWavePacket14 = 13, kByte14 = 14
};
constexpr uint16_t kCompressorPointwise = 1, kCompressorPointwiseChunked = 2, kCompressorLayered = 3;

struct Item {
  uint16_t type = 0, size = 0, version = 0;
};

struct LaszipVlr {
  uint16_t compressor = 0;  // 1 point-wise, 2 point-wise chunked, 3 layered chunked
  uint16_t coder = 0;       // 0 arithmetic
  uint32_t chunk_size = 0;  // points per chunk; 0xFFFFFFFF: variable (in the chunk table)
  std::vector<Item> items;
};

LaszipVlr parse_laszip_vlr(const uint8_t* data, size_t size);

// Where the compressed points lie and what they decode to.
struct PointData {
  const uint8_t* file = nullptr;
  size_t file_size = 0;
  size_t point_offset = 0;  // the header's offset to point data
  uint64_t count = 0;       // points the header announces
  uint32_t record_length = 0;
};

// All point records, count * record_length bytes, in file order.
std::vector<uint8_t> decode_points(const PointData& in, const LaszipVlr& vlr);

// The same records a LASzip chunk at a time, in file order: `chunk` gets
// each chunk's records (a buffer reused for the next), their count and the
// file offset the chunk's bytes end at (what a mapped file may now release),
// so a reader keeps one chunk decoded, never the whole file (a point-wise
// compressed file, compressor 1, is one chunk).
void decode_points_by_chunk(
    const PointData& in, const LaszipVlr& vlr,
    const std::function<void(const uint8_t* records, uint64_t count, uint64_t bytes_end)>& chunk);

// A LAZ's point records may be at most this many times its compressed
// bytes: LiDAR compresses 5-15 times, so a header claiming more is damaged
// (checked before the records are allocated).
constexpr uint64_t kMaxLazExpansion = 1000;

}  // namespace c3d::laz
