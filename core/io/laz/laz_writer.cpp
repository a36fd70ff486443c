// The LAZ writer (see the header).
#include "core/io/laz/laz_writer.h"

#include <cstring>
#include <memory>
#include <string>

#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_reader.h"
#include "core/io/laz/item_writer.h"

namespace c3d::laz {

namespace {

template <typename T>
void store(std::vector<uint8_t>& out, size_t at, T v) {
  std::memcpy(out.data() + at, &v, sizeof v);
}
template <typename T>
void append(std::vector<uint8_t>& out, T v) {
  out.resize(out.size() + sizeof v);
  store(out, out.size() - sizeof v, v);
}

using Items = RecordItems<Encoder, ItemWriter>;

std::unique_ptr<ItemWriter> make_writer(const Item& it, Encoder& enc) {
  switch (it.type) {
    case kPoint10: return make_point10_writer(enc);
    case kGpsTime11: return make_gpstime11_writer(enc);
    case kRgb12: return make_rgb12_writer(enc);
    case kByte: return make_byte_writer(enc, it.size);
    case kPoint14: return make_point14_writer();
    case kRgb14: return make_rgb14_writer(false);
    case kRgbNir14: return make_rgb14_writer(true);
    case kByte14: return make_byte14_writer(it.size);
    default: throw FormatError("cannot write LAZ item type " + std::to_string(it.type));
  }
}

std::unique_ptr<Items> make_items(const LaszipVlr& vlr, uint32_t record_length) {
  auto items = std::make_unique<Items>();
  items->add(vlr, record_length, [&](const Item& it) { return make_writer(it, items->stream); });
  return items;
}

// One chunk: its first record raw, then the rest compressed.
void encode_chunk(Items& items, const uint8_t* records, uint64_t points, uint32_t record_length,
                  std::vector<uint8_t>& out) {
  out.insert(out.end(), records, records + record_length);
  uint32_t context = 0;
  for (size_t i = 0; i < items.coders.size(); ++i) items.coders[i]->init(records + items.offsets[i], context);
  for (uint64_t p = 1; p < points; ++p) {
    const uint8_t* record = records + p * record_length;
    for (size_t i = 0; i < items.coders.size(); ++i) items.coders[i]->encode(record + items.offsets[i], context);
  }
  if (!items.layered) {
    const std::vector<uint8_t> bytes = items.stream.finish();
    out.insert(out.end(), bytes.begin(), bytes.end());
    return;
  }
  put_u32(out, uint32_t(points));
  for (auto& w : items.coders) w->finish_layers();
  for (auto& w : items.coders) w->write_layer_sizes(out);
  for (auto& w : items.coders) w->write_layers(out);
}

// Version 0, the chunk count, then each chunk's byte count coded against the last.
void write_chunk_table(const std::vector<uint32_t>& chunk_bytes, std::vector<uint8_t>& out) {
  put_u32(out, 0);
  put_u32(out, uint32_t(chunk_bytes.size()));
  if (chunk_bytes.empty()) return;
  Encoder enc;
  IntegerCoder ic(32, 2);
  int32_t last = 0;
  for (uint32_t bytes : chunk_bytes) {
    ic.compress(enc, last, int32_t(bytes), 1);
    last = int32_t(bytes);
  }
  const std::vector<uint8_t> table = enc.finish();
  out.insert(out.end(), table.begin(), table.end());
}

}  // namespace

LaszipVlr laszip_vlr_for(int point_format, uint32_t record_length, uint32_t chunk_size) {
  static const uint16_t kBaseSize[] = {20, 28, 26, 34, 57, 63, 30, 36, 38};
  if (point_format < 0 || point_format > 8 || point_format == 4 || point_format == 5)
    throw FormatError("point format " + std::to_string(point_format) +
                      " cannot be written as LAZ (0-3 and 6-8 can)");
  if (record_length < kBaseSize[point_format] || record_length > 0xFFFF)
    throw FormatError("record length " + std::to_string(record_length) + " does not fit point format " +
                      std::to_string(point_format));
  if (chunk_size == 0 || chunk_size == 0xFFFFFFFFu) throw FormatError("LAZ chunk size must be 1 to 2^32-2");
  LaszipVlr vlr;
  vlr.chunk_size = chunk_size;
  const uint16_t extra = uint16_t(record_length - kBaseSize[point_format]);
  if (point_format <= 3) {
    vlr.compressor = kCompressorPointwiseChunked;
    vlr.items.push_back({kPoint10, 20, 2});
    if (point_format == 1 || point_format == 3) vlr.items.push_back({kGpsTime11, 8, 2});
    if (point_format >= 2) vlr.items.push_back({kRgb12, 6, 2});
    if (extra) vlr.items.push_back({kByte, extra, 2});
  } else {
    vlr.compressor = kCompressorLayered;
    vlr.items.push_back({kPoint14, 30, 3});
    if (point_format == 7) vlr.items.push_back({kRgb14, 6, 3});
    if (point_format == 8) vlr.items.push_back({kRgbNir14, 8, 3});
    if (extra) vlr.items.push_back({kByte14, extra, 3});
  }
  return vlr;
}

std::vector<uint8_t> laszip_vlr_payload(const LaszipVlr& vlr) {
  std::vector<uint8_t> out;
  append<uint16_t>(out, vlr.compressor);
  append<uint16_t>(out, vlr.coder);
  const bool layered = vlr.compressor == kCompressorLayered;
  out.push_back(layered ? 3 : 2);  // LASzip version the items follow: 3.4 r3 or 2.2 r0
  out.push_back(layered ? 4 : 2);
  append<uint16_t>(out, layered ? 3 : 0);
  append<uint32_t>(out, 0);  // options
  append<uint32_t>(out, vlr.chunk_size);
  append<int64_t>(out, -1);  // no special EVLRs
  append<int64_t>(out, -1);
  append<uint16_t>(out, uint16_t(vlr.items.size()));
  for (const Item& it : vlr.items) {
    append<uint16_t>(out, it.type);
    append<uint16_t>(out, it.size);
    append<uint16_t>(out, it.version);
  }
  return out;
}

std::vector<uint8_t> encode_points(const uint8_t* records, uint64_t count, uint32_t record_length,
                                   const LaszipVlr& vlr, uint64_t data_offset) {
  auto items = make_items(vlr, record_length);
  std::vector<uint8_t> out(8, 0);  // the chunk table offset, known at the end
  std::vector<uint32_t> chunk_bytes;
  for (uint64_t done = 0; done < count;) {
    const uint64_t points = std::min<uint64_t>(vlr.chunk_size, count - done);
    const size_t begin = out.size();
    encode_chunk(*items, records + done * record_length, points, record_length, out);
    if (out.size() - begin > 0xFFFFFFFFu) throw FormatError("a LAZ chunk over 4 GB: use smaller chunks");
    chunk_bytes.push_back(uint32_t(out.size() - begin));
    done += points;
  }
  store<int64_t>(out, 0, int64_t(data_offset + out.size()));
  write_chunk_table(chunk_bytes, out);
  return out;
}

std::vector<uint8_t> compress_las(const std::vector<uint8_t>& las, uint32_t chunk_size) {
  if (las.size() < 227 || std::memcmp(las.data(), "LASF", 4) != 0) throw FormatError("not a LAS file");
  const uint8_t* p = las.data();
  const uint16_t header_size = load<uint16_t>(p + 94);
  const uint32_t point_offset = load<uint32_t>(p + 96), vlr_count = load<uint32_t>(p + 100);
  const uint8_t format = p[104];
  const uint16_t record_length = load<uint16_t>(p + 105);
  if (format & 0xC0) throw FormatError("the points are compressed already");
  const bool v14 = p[25] >= 4 && header_size >= 375;
  uint64_t count = load<uint32_t>(p + 107);
  if (v14 && load<uint64_t>(p + 247)) count = load<uint64_t>(p + 247);
  if (header_size < 227 || point_offset < header_size || point_offset > las.size() || record_length == 0 ||
      count > (las.size() - point_offset) / record_length)
    throw FormatError("truncated LAS file");
  size_t vlr_end = header_size;  // the LASzip VLR goes after the others
  for (uint32_t i = 0; i < vlr_count; ++i) {
    if (vlr_end + 54 > point_offset) throw FormatError("VLR " + std::to_string(i) + " runs into the points");
    vlr_end += 54 + load<uint16_t>(p + vlr_end + 20);
  }
  if (vlr_end > point_offset) throw FormatError("the VLRs run into the points");
  const LaszipVlr vlr = laszip_vlr_for(format, record_length, chunk_size);
  const std::vector<uint8_t> payload = laszip_vlr_payload(vlr);
  std::vector<uint8_t> out(p, p + vlr_end);
  std::vector<uint8_t> vlr_header(54, 0);
  std::memcpy(&vlr_header[2], kLaszipUserId, std::strlen(kLaszipUserId));
  store<uint16_t>(vlr_header, 18, kLaszipRecordId);
  store<uint16_t>(vlr_header, 20, uint16_t(payload.size()));
  std::memcpy(&vlr_header[22], "LAZ compression", 15);
  out.insert(out.end(), vlr_header.begin(), vlr_header.end());
  out.insert(out.end(), payload.begin(), payload.end());
  out.insert(out.end(), p + vlr_end, p + point_offset);  // any padding before the points
  store<uint32_t>(out, 96, uint32_t(out.size()));
  store<uint32_t>(out, 100, vlr_count + 1);
  out[104] = uint8_t(format | 0x80);  // LASzip's mark of compressed points
  const std::vector<uint8_t> data = encode_points(p + point_offset, count, record_length, vlr, out.size());
  out.insert(out.end(), data.begin(), data.end());
  const uint64_t points_end = point_offset + count * record_length;
  if (v14 && load<uint32_t>(p + 243) > 0 && load<uint64_t>(p + 235) >= points_end &&
      load<uint64_t>(p + 235) <= las.size()) {  // EVLRs follow the compressed points
    store<uint64_t>(out, 235, out.size());
    out.insert(out.end(), p + load<uint64_t>(p + 235), p + las.size());
  }
  return out;
}

}  // namespace c3d::laz
