// The POINT10, GPSTIME11, RGB12 and BYTE item encoders (compressor version
// 2): the inverses of point10.cpp and items_v2.cpp, over the same models.
#include <cstring>

#include "core/io/laz/gps_time.h"
#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_reader.h"
#include "core/io/laz/item_writer.h"

namespace c3d::laz {

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (8 * i)));
}

namespace {

uint8_t byte_of(uint16_t v, bool low) { return uint8_t(low ? v & 0xFF : v >> 8); }

// Green and blue's byte (low or high), predicted as decode_green_blue predicts it.
void encode_green_blue(Encoder& enc, RgbModels& m, uint32_t sym, const uint16_t last[3], const uint16_t rgb[3],
                       bool low) {
  const int bit_g = low ? 2 : 3, bit_b = low ? 4 : 5;
  int32_t diff = byte_of(rgb[0], low) - byte_of(last[0], low);
  if (sym & (1u << bit_g)) {
    const int32_t corr = byte_of(rgb[1], low) - clamp_u8(diff + byte_of(last[1], low));
    enc.encode_symbol(m.diff[bit_g], fold_u8(corr));
  }
  if (sym & (1u << bit_b)) {
    diff = (diff + (byte_of(rgb[1], low) - byte_of(last[1], low))) / 2;
    const int32_t corr = byte_of(rgb[2], low) - clamp_u8(diff + byte_of(last[2], low));
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

// Byte offsets in the 20-byte POINT10 record.
constexpr int kIntensity = 12, kFlags = 14, kClass = 15, kScanAngle = 16, kUserData = 17,
              kPointSource = 18;

uint16_t u16_at(const uint8_t* p, int at) {
  uint16_t v;
  std::memcpy(&v, p + at, 2);
  return v;
}
int32_t i32_at(const uint8_t* p, int at) {
  int32_t v;
  std::memcpy(&v, p + at, 4);
  return v;
}

class Point10Writer : public ItemWriter {
 public:
  explicit Point10Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override;
  void encode(const uint8_t* item, uint32_t&) override;

 private:
  void encode_attributes(const uint8_t* item, uint32_t changed, uint32_t m);
  void encode_xyz(const uint8_t* item, uint32_t n, uint32_t m, uint32_t l);

  Encoder& enc_;
  uint8_t last_[20] = {};
  uint16_t last_intensity_[16] = {};
  int32_t last_height_[8] = {};
  Median5 last_dx_[16], last_dy_[16];
  SymbolModel changed_values_{64};
  SymbolModel scan_angle_[2] = {SymbolModel(256), SymbolModel(256)};
  ModelBank flags_{256, 256}, classification_{256, 256}, user_data_{256, 256};
  IntegerCoder ic_intensity_{16, 4}, ic_point_source_{16}, ic_dx_{32, 2}, ic_dy_{32, 22}, ic_z_{32, 20};
};

void Point10Writer::init(const uint8_t* first, uint32_t&) {
  for (int i = 0; i < 16; ++i) last_dx_[i].reset(), last_dy_[i].reset(), last_intensity_[i] = 0;
  for (int32_t& h : last_height_) h = 0;
  changed_values_.reset();
  scan_angle_[0].reset(), scan_angle_[1].reset();
  flags_.reset(), classification_.reset(), user_data_.reset();
  for (IntegerCoder* ic : {&ic_intensity_, &ic_point_source_, &ic_dx_, &ic_dy_, &ic_z_}) ic->reset();
  std::memcpy(last_, first, 20);
}

void Point10Writer::encode_attributes(const uint8_t* item, uint32_t changed, uint32_t m) {
  if (changed & 32) enc_.encode_symbol(flags_[last_[kFlags]], item[kFlags]);
  if (changed & 16) {
    ic_intensity_.compress(enc_, last_intensity_[m], u16_at(item, kIntensity), m < 3 ? m : 3);
    last_intensity_[m] = u16_at(item, kIntensity);
  }
  if (changed & 8) enc_.encode_symbol(classification_[last_[kClass]], item[kClass]);
  if (changed & 4)
    enc_.encode_symbol(scan_angle_[(item[kFlags] >> 6) & 1], fold_u8(int32_t(item[kScanAngle]) - last_[kScanAngle]));
  if (changed & 2) enc_.encode_symbol(user_data_[last_[kUserData]], item[kUserData]);
  if (changed & 1) ic_point_source_.compress(enc_, u16_at(last_, kPointSource), u16_at(item, kPointSource));
}

void Point10Writer::encode_xyz(const uint8_t* item, uint32_t n, uint32_t m, uint32_t l) {
  const uint32_t single = n == 1;
  int32_t diff = int32_t(uint32_t(i32_at(item, 0)) - uint32_t(i32_at(last_, 0)));
  ic_dx_.compress(enc_, last_dx_[m].get(), diff, single);
  last_dx_[m].add(diff);
  uint32_t k_bits = ic_dx_.k();
  diff = int32_t(uint32_t(i32_at(item, 4)) - uint32_t(i32_at(last_, 4)));
  ic_dy_.compress(enc_, last_dy_[m].get(), diff, single + (k_bits < 20 ? k_bits & ~1u : 20));
  last_dy_[m].add(diff);
  k_bits = (ic_dx_.k() + ic_dy_.k()) / 2;
  ic_z_.compress(enc_, last_height_[l], i32_at(item, 8), single + (k_bits < 18 ? k_bits & ~1u : 18));
  last_height_[l] = i32_at(item, 8);
}

void Point10Writer::encode(const uint8_t* item, uint32_t&) {
  const uint32_t r = item[kFlags] & 7, n = (item[kFlags] >> 3) & 7;
  const uint32_t m = kReturnMap[n][r];
  const uint32_t changed = (uint32_t(last_[kFlags] != item[kFlags]) << 5) |
                           (uint32_t(last_intensity_[m] != u16_at(item, kIntensity)) << 4) |
                           (uint32_t(last_[kClass] != item[kClass]) << 3) |
                           (uint32_t(last_[kScanAngle] != item[kScanAngle]) << 2) |
                           (uint32_t(last_[kUserData] != item[kUserData]) << 1) |
                           uint32_t(u16_at(last_, kPointSource) != u16_at(item, kPointSource));
  enc_.encode_symbol(changed_values_, changed);
  encode_attributes(item, changed, m);
  encode_xyz(item, n, m, return_level(n, r, 7));
  std::memcpy(last_, item, 20);
}

class GpsTime11Writer : public ItemWriter {
 public:
  explicit GpsTime11Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override { gps_.init(load(first)); }
  void encode(const uint8_t* item, uint32_t&) override { gps_.encode(enc_, load(item)); }

 private:
  static uint64_t load(const uint8_t* p) {
    uint64_t bits;
    std::memcpy(&bits, p, 8);
    return bits;
  }
  Encoder& enc_;
  GpsTimeCoder gps_{false};
};

class Rgb12Writer : public ItemWriter {
 public:
  explicit Rgb12Writer(Encoder& enc) : enc_(enc) {}
  void init(const uint8_t* first, uint32_t&) override {
    models_.reset();
    std::memcpy(last_, first, 6);
  }
  void encode(const uint8_t* item, uint32_t&) override {
    uint16_t rgb[3];
    std::memcpy(rgb, item, 6);
    encode_rgb(enc_, models_, last_, rgb);
    std::memcpy(last_, rgb, 6);
  }

 private:
  Encoder& enc_;
  RgbModels models_;
  uint16_t last_[3] = {};
};

class ByteWriter : public ItemWriter {
 public:
  ByteWriter(Encoder& enc, uint32_t count) : enc_(enc), models_(count, SymbolModel(256)), last_(count) {}
  void init(const uint8_t* first, uint32_t&) override {
    for (SymbolModel& m : models_) m.reset();
    std::memcpy(last_.data(), first, last_.size());
  }
  void encode(const uint8_t* item, uint32_t&) override {
    for (size_t i = 0; i < last_.size(); ++i) {
      enc_.encode_symbol(models_[i], fold_u8(int32_t(item[i]) - last_[i]));
      last_[i] = item[i];
    }
  }

 private:
  Encoder& enc_;
  std::vector<SymbolModel> models_;
  std::vector<uint8_t> last_;
};

}  // namespace

std::unique_ptr<ItemWriter> make_point10_writer(Encoder& enc) { return std::make_unique<Point10Writer>(enc); }
std::unique_ptr<ItemWriter> make_gpstime11_writer(Encoder& enc) { return std::make_unique<GpsTime11Writer>(enc); }
std::unique_ptr<ItemWriter> make_rgb12_writer(Encoder& enc) { return std::make_unique<Rgb12Writer>(enc); }
std::unique_ptr<ItemWriter> make_byte_writer(Encoder& enc, uint32_t count) {
  return std::make_unique<ByteWriter>(enc, count);
}

}  // namespace c3d::laz
