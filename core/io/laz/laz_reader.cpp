// LAZ point data: LASzip VLR, chunk table, chunks (see the header).
#include "core/io/laz/laz_reader.h"

#include <algorithm>
#include <cstdlib>
#include <memory>

#include "core/io/laz/integer_coder.h"
#include "core/io/laz/layered.h"
#include "core/io/laz/point10.h"

namespace c3d::laz {

namespace {

constexpr uint32_t kVariableChunks = 0xFFFFFFFFu;
// Extra bytes a record may carry: each has its own models (up to 4 sets of
// 2.3 kB), so a damaged item size must not reach 65535 of them. No survey
// stores more than a few dozen.
constexpr uint16_t kMaxExtraBytes = 4096;
// Items of a record: a point, GPS time, colour and extra bytes make four.
constexpr uint16_t kMaxItems = 16;

std::string item_name(const Item& it) {
  return "item type " + std::to_string(it.type) + " version " + std::to_string(it.version);
}

using Items = RecordItems<Decoder, ItemReader>;

std::unique_ptr<ItemReader> make_v2(const Item& it, Decoder& dec) {
  if (it.version != 2)
    throw FormatError(item_name(it) + " is not supported (LASzip 1.x files use version 1; "
                      "re-compress with a current laszip)");
  switch (it.type) {
    case kPoint10: if (it.size == 20) return make_point10_v2(dec); break;
    case kGpsTime11: if (it.size == 8) return make_gpstime11_v2(dec); break;
    case kRgb12: if (it.size == 6) return make_rgb12_v2(dec); break;
    case kByte: if (it.size > 0) return make_byte_v2(dec, it.size); break;
    default: break;
  }
  throw FormatError("unsupported " + item_name(it) + " of " + std::to_string(it.size) + " bytes");
}

std::unique_ptr<ItemReader> make_layered(const Item& it) {
  if (it.version != 3 && it.version != 4) throw FormatError(item_name(it) + " is not supported");
  switch (it.type) {
    case kPoint14: if (it.size == 30) return make_point14(it.version); break;
    case kRgb14: if (it.size == 6) return make_rgb14(it.version, false); break;
    case kRgbNir14: if (it.size == 8) return make_rgb14(it.version, true); break;
    case kByte14: if (it.size > 0) return make_byte14(it.version, it.size); break;
    default: break;
  }
  throw FormatError("unsupported " + item_name(it) + " of " + std::to_string(it.size) + " bytes");
}

std::unique_ptr<Items> make_items(const LaszipVlr& vlr, uint32_t record_length) {
  auto items = std::make_unique<Items>();
  items->add(vlr, record_length, [&](const Item& it) {
    if ((it.type == kByte || it.type == kByte14) && it.size > kMaxExtraBytes)
      throw FormatError(std::to_string(it.size) + " extra bytes per point (at most " +
                        std::to_string(kMaxExtraBytes) + " are read)");
    return vlr.compressor == kCompressorLayered ? make_layered(it) : make_v2(it, items->stream);
  });
  if (items->coders.empty() || (vlr.items[0].type == kPoint14) != items->layered)
    throw FormatError("compressor " + std::to_string(vlr.compressor) + " does not fit the items");
  return items;
}

struct Chunk {
  uint64_t begin = 0, end = 0, points = 0;
  size_t index = 0, of = 1;  // its place in the chunk table, and the table's length
  bool bounded = true;       // ends where its data does (a point-wise file's one chunk may not)
};

// The chunk table's position: after the chunks, named by the 8 bytes before
// them (or, when those are -1, by the file's last 8 bytes).
uint64_t chunk_table_offset(const PointData& in) {
  if (in.file_size - in.point_offset < 8) throw FormatError("no chunk table offset");
  int64_t at = load<int64_t>(in.file + in.point_offset);
  if (at == -1) at = load<int64_t>(in.file + in.file_size - 8);
  const uint64_t chunks_start = in.point_offset + 8;
  if (at < 0 || uint64_t(at) < chunks_start || uint64_t(at) > in.file_size - 8)
    throw FormatError("chunk table offset " + std::to_string(at) + " lies outside the point data");
  return uint64_t(at);
}

std::vector<Chunk> read_chunk_table(const PointData& in, uint32_t chunk_size) {
  const uint64_t table = chunk_table_offset(in), chunks_start = in.point_offset + 8;
  if (load<uint32_t>(in.file + table) != 0) throw FormatError("unknown chunk table version");
  const uint32_t n = load<uint32_t>(in.file + table + 4);
  if (n > (table - chunks_start) / in.record_length)  // every chunk starts with a raw record
    throw FormatError("chunk table lists " + std::to_string(n) + " chunks, more than the data holds");
  Decoder dec;
  dec.start(in.file + table + 8, in.file + in.file_size);
  IntegerCoder ic(32, 2);
  std::vector<Chunk> chunks(n);
  int32_t points = 0, bytes = 0;
  uint64_t pos = chunks_start;
  for (Chunk& c : chunks) {
    c.index = size_t(&c - chunks.data()), c.of = n;
    if (chunk_size == kVariableChunks) points = ic.decompress(dec, points, 0);
    bytes = ic.decompress(dec, bytes, 1);
    c.points = chunk_size == kVariableChunks ? uint32_t(points) : chunk_size;
    c.begin = pos;
    c.end = pos += uint32_t(bytes);
    if (c.end > in.file_size) throw FormatError("chunk table lists chunks past the end of the file");
  }
  return chunks;
}

// Starts the items on a chunk's first record; returns the scanner channel
// (POINT14's context) the next records start in.
uint32_t start_chunk(Items& items, ByteCursor& in, const uint8_t* first) {
  uint32_t context = 0;
  if (items.layered) {
    in.u32("point count");
    for (auto& r : items.coders) r->read_layer_sizes(in);
    for (auto& r : items.coders) r->load_layers(in);
  }
  for (size_t i = 0; i < items.coders.size(); ++i) items.coders[i]->init(first + items.offsets[i], context);
  if (!items.layered) items.stream.start(in.pos, in.end);
  return context;
}

// The bytes of a chunk its streams left unread or read past their ends.
long chunk_slack(const Items& items, const ByteCursor& after_start) {
  if (!items.layered) return std::labs(items.stream.slack());
  long s = long(after_start.end - after_start.pos);  // bytes no layer holds
  for (const auto& r : items.coders) s += r->layer_slack();
  return s;
}

// Decodes `points` records of one chunk into out. Its streams must end
// where its bytes do: LAZ has no checksum, but a damaged byte, or a point
// count or chunk size that is not the data's, leaves the arithmetic decoder
// out of step with the encoder's padding.
void decode_chunk_records(Items& items, const PointData& in, const Chunk& chunk, uint64_t points, uint8_t* out) {
  ByteCursor cursor{in.file + chunk.begin, in.file + chunk.end};
  const uint8_t* first = cursor.take(in.record_length, "first point");
  std::memcpy(out, first, in.record_length);
  uint32_t context = start_chunk(items, cursor, first);
  const size_t n_items = items.coders.size();
  for (uint64_t p = 1; p < points; ++p) {
    uint8_t* record = out + p * in.record_length;
    for (size_t i = 0; i < n_items; ++i) items.coders[i]->decode(record + items.offsets[i], context);
  }
  if (!chunk.bounded || points < 2) return;
  if (const long off = chunk_slack(items, cursor))
    throw FormatError("its " + std::to_string(points) + " points decode " + std::to_string(off) +
                      " bytes out of step with its data: the points are damaged, or the header's point count "
                      "or the LASzip chunk size is not the file's");
}

// decode_chunk_records, its errors naming the chunk.
void decode_chunk(Items& items, const PointData& in, const Chunk& chunk, uint64_t points, uint8_t* out) {
  try {
    decode_chunk_records(items, in, chunk, points, out);
  } catch (const FormatError& e) {
    throw FormatError("chunk " + std::to_string(chunk.index + 1) + " of " + std::to_string(chunk.of) + ": " +
                      e.what());
  }
}

}  // namespace

LaszipVlr parse_laszip_vlr(const uint8_t* data, size_t size) {
  if (size < 34) throw FormatError("LASzip VLR of " + std::to_string(size) + " bytes is too short");
  LaszipVlr vlr;
  vlr.compressor = load<uint16_t>(data);
  vlr.coder = load<uint16_t>(data + 2);
  vlr.chunk_size = load<uint32_t>(data + 12);
  const uint16_t n = load<uint16_t>(data + 32);
  if (n > kMaxItems) throw FormatError("LASzip VLR lists " + std::to_string(n) + " items");
  if (size < 34 + 6 * size_t(n)) throw FormatError("LASzip VLR lists more items than it holds");
  for (uint16_t i = 0; i < n; ++i) {
    const uint8_t* p = data + 34 + 6 * i;
    vlr.items.push_back({load<uint16_t>(p), load<uint16_t>(p + 2), load<uint16_t>(p + 4)});
  }
  if (vlr.coder != 0) throw FormatError("unknown LASzip coder " + std::to_string(vlr.coder));
  if (vlr.compressor < kCompressorPointwise || vlr.compressor > kCompressorLayered)
    throw FormatError("unknown LASzip compressor " + std::to_string(vlr.compressor));
  if (vlr.compressor != kCompressorPointwise && vlr.chunk_size == 0) throw FormatError("LASzip chunk size 0");
  return vlr;
}

namespace {

std::vector<Chunk> chunks_of(const PointData& in, const LaszipVlr& vlr) {
  const uint64_t compressed = in.file_size - in.point_offset;
  if (in.count > compressed * kMaxLazExpansion / in.record_length)
    throw FormatError("header claims " + std::to_string(in.count) + " points, more than " +
                      std::to_string(kMaxLazExpansion) + " times the " + std::to_string(compressed) +
                      " compressed bytes can hold");
  if (vlr.compressor == kCompressorPointwise) return {{in.point_offset, in.file_size, in.count, 0, 1, false}};
  std::vector<Chunk> chunks = read_chunk_table(in, vlr.chunk_size);
  uint64_t held = 0;
  for (const Chunk& c : chunks) {
    if (held >= in.count && c.points > 0)
      throw FormatError("the header says " + std::to_string(in.count) + " points, too few to fill the chunk table's " +
                        std::to_string(chunks.size()) + " chunks");
    held += c.points;
  }
  return chunks;
}

}  // namespace

void decode_points_by_chunk(const PointData& in, const LaszipVlr& vlr,
                            const std::function<void(const uint8_t*, uint64_t, uint64_t)>& chunk_out) {
  auto items = make_items(vlr, in.record_length);
  std::vector<uint8_t> records;
  uint64_t done = 0;
  for (const Chunk& chunk : chunks_of(in, vlr)) {
    const uint64_t points = std::min(chunk.points, in.count - done);
    if (points == 0) continue;
    records.resize(points * in.record_length);
    decode_chunk(*items, in, chunk, points, records.data());
    done += points;
    chunk_out(records.data(), points, chunk.end);
  }
  if (done < in.count)
    throw FormatError("the chunks hold " + std::to_string(done) + " points, the header says " +
                      std::to_string(in.count));
}

std::vector<uint8_t> decode_points(const PointData& in, const LaszipVlr& vlr) {
  auto items = make_items(vlr, in.record_length);
  const std::vector<Chunk> chunks = chunks_of(in, vlr);
  std::vector<uint8_t> records(in.count * in.record_length);
  uint64_t done = 0;
  for (const Chunk& chunk : chunks) {
    const uint64_t points = std::min(chunk.points, in.count - done);
    if (points == 0) continue;
    decode_chunk(*items, in, chunk, points, records.data() + done * in.record_length);
    done += points;
  }
  if (done < in.count)
    throw FormatError("the chunks hold " + std::to_string(done) + " points, the header says " +
                      std::to_string(in.count));
  return records;
}

}  // namespace c3d::laz
