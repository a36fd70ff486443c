// The POINT10, GPSTIME11, RGB12 and BYTE item encoders (compressor version
// 2): the inverses of point10.cpp and items_v2.cpp, over the same models.
#include <cstring>

#include "core/io/laz/gps_time.h"
#include "core/io/laz/item_writer.h"
#include "core/io/laz/point10.h"
#include "core/io/laz/rgb.h"

namespace c3d::laz {

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

namespace {

// Green and blue's byte (low or high), predicted as decode_green_blue predicts it.
void encode_green_blue(Encoder& enc, RgbModels& m, uint32_t sym, const uint16_t last[3], const uint16_t rgb[3],
                       bool low) {
  const int bit_g = low ? 2 : 3, bit_b = low ? 4 : 5;
  const int32_t diff = byte_of(rgb[0], low) - byte_of(last[0], low);
  if (sym & (1u << bit_g)) {
    const int32_t corr = byte_of(rgb[1], low) - predict_green(diff, byte_of(last[1], low));
    enc.encode_symbol(m.diff[bit_g], fold_u8(corr));
  }
  if (sym & (1u << bit_b)) {
    const int32_t green_diff = byte_of(rgb[1], low) - byte_of(last[1], low);
    const int32_t corr = byte_of(rgb[2], low) - predict_blue(diff, green_diff, byte_of(last[2], low));
    enc.encode_symbol(m.diff[bit_b], fold_u8(corr));
  }
}

}  // namespace

void encode_rgb(Encoder& enc, RgbModels& m, const uint16_t last[3], const uint16_t rgb[3]) {
  uint32_t sym = 0;
  for (int c = 0; c < 3; ++c) {
    sym |= uint32_t(byte_of(last[c], true) != byte_of(rgb[c], true)) << (2 * c);
    sym |= uint32_t(byte_of(last[c], false) != byte_of(rgb[c], false)) << (2 * c + 1);
  }
  sym |= uint32_t(rgb[1] != rgb[0] || rgb[2] != rgb[0]) << 6;
  enc.encode_symbol(m.byte_used, sym);
  if (sym & 1) enc.encode_symbol(m.diff[0], fold_u8(byte_of(rgb[0], true) - byte_of(last[0], true)));
  if (sym & 2) enc.encode_symbol(m.diff[1], fold_u8(byte_of(rgb[0], false) - byte_of(last[0], false)));
  if (sym & (1u << 6)) {
    encode_green_blue(enc, m, sym, last, rgb, true);
    encode_green_blue(enc, m, sym, last, rgb, false);
  }
}

namespace {

class Point10Writer : public ItemWriter, Point10Context {
 public:
  explicit Point10Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override;
  void encode(const uint8_t* item, uint32_t&) override;

 private:
  void encode_attributes(const uint8_t* item, uint32_t changed, uint32_t m);
  void encode_xyz(const uint8_t* item, uint32_t n, uint32_t m, uint32_t l);

  Encoder& enc_;
};

void Point10Writer::init(const uint8_t* first, uint32_t&) { Point10Context::init(first); }

void Point10Writer::encode_attributes(const uint8_t* item, uint32_t changed, uint32_t m) {
  if (changed & 32) enc_.encode_symbol(flags[last[kFlags]], item[kFlags]);
  if (changed & 16) {
    ic_intensity.compress(enc_, last_intensity[m], load<uint16_t>(item, kIntensity), intensity_context(m));
    last_intensity[m] = load<uint16_t>(item, kIntensity);
  }
  if (changed & 8) enc_.encode_symbol(classification[last[kClass]], item[kClass]);
  if (changed & 4)
    enc_.encode_symbol(scan_angle[(item[kFlags] >> 6) & 1], fold_u8(int32_t(item[kScanAngle]) - last[kScanAngle]));
  if (changed & 2) enc_.encode_symbol(user_data[last[kUserData]], item[kUserData]);
  if (changed & 1) ic_point_source.compress(enc_, field<uint16_t>(kPointSource), load<uint16_t>(item, kPointSource));
}

void Point10Writer::encode_xyz(const uint8_t* item, uint32_t n, uint32_t m, uint32_t l) {
  const uint32_t single = n == 1;
  int32_t diff = int32_t(uint32_t(load<int32_t>(item, 0)) - uint32_t(field<int32_t>(0)));
  ic_dx.compress(enc_, last_dx[m].get(), diff, single);
  last_dx[m].add(diff);
  diff = int32_t(uint32_t(load<int32_t>(item, 4)) - uint32_t(field<int32_t>(4)));
  ic_dy.compress(enc_, last_dy[m].get(), diff, y_context(single, ic_dx.k()));
  last_dy[m].add(diff);
  ic_z.compress(enc_, last_height[l], load<int32_t>(item, 8), z_context(single, ic_dx.k(), ic_dy.k()));
  last_height[l] = load<int32_t>(item, 8);
}

void Point10Writer::encode(const uint8_t* item, uint32_t&) {
  const uint32_t r = item[kFlags] & 7, n = (item[kFlags] >> 3) & 7;
  const uint32_t m = return_map(item[kFlags]);
  const uint32_t changed = (uint32_t(last[kFlags] != item[kFlags]) << 5) |
                           (uint32_t(last_intensity[m] != load<uint16_t>(item, kIntensity)) << 4) |
                           (uint32_t(last[kClass] != item[kClass]) << 3) |
                           (uint32_t(last[kScanAngle] != item[kScanAngle]) << 2) |
                           (uint32_t(last[kUserData] != item[kUserData]) << 1) |
                           uint32_t(field<uint16_t>(kPointSource) != load<uint16_t>(item, kPointSource));
  enc_.encode_symbol(changed_values, changed);
  encode_attributes(item, changed, m);
  encode_xyz(item, n, m, return_level(n, r, 7));
  std::memcpy(last, item, 20);
}

class GpsTime11Writer : public ItemWriter {
 public:
  explicit GpsTime11Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override { gps_.init(load<uint64_t>(first)); }
  void encode(const uint8_t* item, uint32_t&) override { gps_.encode(enc_, load<uint64_t>(item)); }

 private:
  Encoder& enc_;
  GpsTimeCoder gps_{false};
};

class Rgb12Writer : public ItemWriter {
 public:
  explicit Rgb12Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override { state_.start(first, 6); }
  void encode(const uint8_t* item, uint32_t&) override {
    uint16_t rgb[3];
    std::memcpy(rgb, item, 6);
    encode_rgb(enc_, state_.rgb, state_.last, rgb);
    std::memcpy(state_.last, rgb, 6);
  }

 private:
  Encoder& enc_;
  RgbContext state_;
};

class ByteWriter : public ItemWriter {
 public:
  ByteWriter(Encoder& enc, uint32_t count) : enc_(enc), count_(count) {}
  void init(const uint8_t* first, uint32_t&) override { state_.start(first, count_); }
  void encode(const uint8_t* item, uint32_t&) override {
    uint8_t* last = state_.values();
    for (size_t i = 0; i < count_; ++i) {
      enc_.encode_symbol(state_.models[i], fold_u8(int32_t(item[i]) - last[i]));
      last[i] = item[i];
    }
  }

 private:
  Encoder& enc_;
  size_t count_;
  ByteContext state_;
};

}  // namespace

std::unique_ptr<ItemWriter> make_point10_writer(Encoder& enc) { return std::make_unique<Point10Writer>(enc); }
std::unique_ptr<ItemWriter> make_gpstime11_writer(Encoder& enc) { return std::make_unique<GpsTime11Writer>(enc); }
std::unique_ptr<ItemWriter> make_rgb12_writer(Encoder& enc) { return std::make_unique<Rgb12Writer>(enc); }
std::unique_ptr<ItemWriter> make_byte_writer(Encoder& enc, uint32_t count) {
  return std::make_unique<ByteWriter>(enc, count);
}

}  // namespace c3d::laz
