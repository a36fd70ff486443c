// The GPSTIME11, RGB12 and BYTE item decoders (compressor version 2) and the
// RGB predictor the layered RGB items share.
#include <memory>
#include <vector>

#include "core/io/laz/gps_time.h"
#include "core/io/laz/point10.h"
#include "core/io/laz/rgb.h"

namespace c3d::laz {

namespace {

// Green and blue's byte (low or high) predicted from red's change in that byte.
void decode_green_blue(Decoder& dec, RgbModels& m, uint32_t sym, const uint16_t last[3],
                       uint16_t out[3], bool low) {
  const int shift = low ? 0 : 8;
  const int bit_g = low ? 2 : 3, bit_b = low ? 4 : 5;
  const int32_t diff = byte_of(out[0], low) - byte_of(last[0], low);
  uint16_t g = byte_of(last[1], low), b = byte_of(last[2], low);
  if (sym & (1u << bit_g)) {
    const int32_t corr = int32_t(dec.decode_symbol(m.diff[bit_g]));
    g = fold_u8(corr + predict_green(diff, byte_of(last[1], low)));
  }
  if (sym & (1u << bit_b)) {
    const int32_t corr = int32_t(dec.decode_symbol(m.diff[bit_b]));
    b = fold_u8(corr + predict_blue(diff, g - byte_of(last[1], low), byte_of(last[2], low)));
  }
  out[1] = uint16_t(out[1] | (g << shift));
  out[2] = uint16_t(out[2] | (b << shift));
}

}  // namespace

void decode_rgb(Decoder& dec, RgbModels& m, const uint16_t last[3], uint16_t out[3]) {
  const uint32_t sym = dec.decode_symbol(m.byte_used);
  uint16_t red_low = last[0] & 0xFF, red_high = last[0] >> 8;
  if (sym & 1) red_low = fold_u8(int32_t(dec.decode_symbol(m.diff[0])) + red_low);
  if (sym & 2) red_high = fold_u8(int32_t(dec.decode_symbol(m.diff[1])) + red_high);
  out[0] = uint16_t(red_low | (red_high << 8));
  if (sym & (1u << 6)) {  // green and blue differ from red
    out[1] = out[2] = 0;
    decode_green_blue(dec, m, sym, last, out, true);
    decode_green_blue(dec, m, sym, last, out, false);
  } else {
    out[1] = out[2] = out[0];
  }
}

namespace {

class GpsTime11Reader : public ItemReader {
 public:
  explicit GpsTime11Reader(Decoder& dec) : dec_(dec) {}
  void init(const uint8_t* first, uint32_t&) override {
    uint64_t bits;
    std::memcpy(&bits, first, 8);
    gps_.init(bits);
  }
  void decode(uint8_t* out, uint32_t&) override {
    const uint64_t bits = gps_.decode(dec_);
    std::memcpy(out, &bits, 8);
  }

 private:
  Decoder& dec_;
  GpsTimeCoder gps_{false};
};

class Rgb12Reader : public ItemReader {
 public:
  explicit Rgb12Reader(Decoder& dec) : dec_(dec) {}
  void init(const uint8_t* first, uint32_t&) override { state_.start(first, 6); }
  void decode(uint8_t* out, uint32_t&) override {
    uint16_t rgb[3];
    decode_rgb(dec_, state_.rgb, state_.last, rgb);
    std::memcpy(out, rgb, 6);
    std::memcpy(state_.last, rgb, 6);
  }

 private:
  Decoder& dec_;
  RgbContext state_;
};

class ByteReader : public ItemReader {
 public:
  ByteReader(Decoder& dec, uint32_t count) : dec_(dec), count_(count) {}
  void init(const uint8_t* first, uint32_t&) override { state_.start(first, count_); }
  void decode(uint8_t* out, uint32_t&) override {
    uint8_t* last = state_.values();
    for (size_t i = 0; i < count_; ++i)
      out[i] = last[i] = fold_u8(last[i] + int32_t(dec_.decode_symbol(state_.models[i])));
  }

 private:
  Decoder& dec_;
  size_t count_;
  ByteContext state_;
};

}  // namespace

std::unique_ptr<ItemReader> make_gpstime11_v2(Decoder& dec) { return std::make_unique<GpsTime11Reader>(dec); }
std::unique_ptr<ItemReader> make_rgb12_v2(Decoder& dec) { return std::make_unique<Rgb12Reader>(dec); }
std::unique_ptr<ItemReader> make_byte_v2(Decoder& dec, uint32_t count) {
  return std::make_unique<ByteReader>(dec, count);
}

}  // namespace c3d::laz
