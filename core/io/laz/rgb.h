#pragma once
// The LAZ RGB predictor (RGB12 v2 and the RGB layer of RGB14/RGBNIR14): which
// bytes changed, then each byte as a difference to a prediction from red.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/arithmetic_encoder.h"
#include "core/io/laz/item_reader.h"

namespace c3d::laz {

struct RgbModels {
  SymbolModel byte_used{128};
  SymbolModel diff[6] = {SymbolModel(256), SymbolModel(256), SymbolModel(256),
                         SymbolModel(256), SymbolModel(256), SymbolModel(256)};
  void reset() {
    byte_used.reset();
    for (SymbolModel& m : diff) m.reset();
  }
};

// The state of RGB12 and of a channel of RGB14 and RGBNIR14 (bytes: 6 or 8
// of the record; RGB12 leaves the NIR models unused).
struct RgbContext {
  using Value = uint16_t;
  bool unused = true;
  RgbModels rgb;
  SymbolModel nir_used{4};
  SymbolModel nir_diff[2] = {SymbolModel(256), SymbolModel(256)};
  uint16_t last[4] = {};
  void start(const void* from, size_t bytes) {
    rgb.reset(), nir_used.reset(), nir_diff[0].reset(), nir_diff[1].reset();
    std::memcpy(last, from, bytes);
    unused = false;
  }
  uint16_t* values() { return last; }
};

// One byte of a 16-bit value: `low` selects the low or the high byte.
inline uint8_t byte_of(uint16_t v, bool low) { return uint8_t(low ? v & 0xFF : v >> 8); }

// Green's byte (low or high) predicted from red's change in that byte; blue's
// from red's and green's changes.
inline int32_t predict_green(int32_t red_diff, uint8_t last_green) { return clamp_u8(red_diff + last_green); }
inline int32_t predict_blue(int32_t red_diff, int32_t green_diff, uint8_t last_blue) {
  return clamp_u8((red_diff + green_diff) / 2 + last_blue);
}

// Decodes the next colour (three 16-bit channels) from the last one.
void decode_rgb(Decoder& dec, RgbModels& m, const uint16_t last[3], uint16_t out[3]);
// The colour as decode_rgb reads it back, predicted from `last`.
void encode_rgb(Encoder& enc, RgbModels& m, const uint16_t last[3], const uint16_t rgb[3]);

}  // namespace c3d::laz
