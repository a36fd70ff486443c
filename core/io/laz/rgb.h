#pragma once
// The LAZ RGB predictor (RGB12 v2 and the RGB layer of RGB14/RGBNIR14): which
// bytes changed, then each byte as a difference to a prediction from red.
#include <cstdint>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/arithmetic_encoder.h"

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

// One byte of a 16-bit value: `low` selects the low or the high byte.
inline uint8_t byte_of(uint16_t v, bool low) { return uint8_t(low ? v & 0xFF : v >> 8); }

// Decodes the next colour (three 16-bit channels) from the last one.
void decode_rgb(Decoder& dec, RgbModels& m, const uint16_t last[3], uint16_t out[3]);
// The colour as decode_rgb reads it back, predicted from `last`.
void encode_rgb(Encoder& enc, RgbModels& m, const uint16_t last[3], const uint16_t rgb[3]);

}  // namespace c3d::laz
