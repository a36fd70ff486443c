#pragma once
// The GPS time predictor of LAZ (GPSTIME11 v2 and POINT14's gps_time layer):
// four interleaved sequences, each predicting the next time as a multiple of
// its last integer difference of the double's bit pattern.
#include <cstdint>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/arithmetic_encoder.h"
#include "core/io/laz/integer_compressor.h"
#include "core/io/laz/integer_decompressor.h"

namespace c3d::laz {

// Codes of the multiplier model (version 2 numbering; the layered variant
// has no kGpsUnchanged and so numbers the last codes one lower).
constexpr int32_t kGpsMulti = 500, kGpsMultiMinus = -10;
constexpr int32_t kGpsUnchanged = kGpsMulti - kGpsMultiMinus + 1;  // 511
constexpr int32_t kGpsCodeFull = kGpsMulti - kGpsMultiMinus + 2;   // 512
constexpr int32_t kGpsMultiTotal = kGpsMulti - kGpsMultiMinus + 6; // 516 symbols

class GpsTimeDecoder {
 public:
  // layered: POINT14's variant, whose codes lack the "unchanged" symbol.
  explicit GpsTimeDecoder(bool layered);
  void init(uint64_t first_bits);
  uint64_t decode(Decoder& dec);  // the next time's bit pattern

 private:
  bool decode_after_zero_diff(Decoder& dec);
  bool decode_after_diff(Decoder& dec);
  void decode_full(Decoder& dec);
  int32_t diff_for_multiplier(Decoder& dec, int32_t multi);

  bool layered_;
  uint32_t last_ = 0, next_ = 0;
  uint64_t time_[4] = {};
  int32_t diff_[4] = {};
  int32_t extreme_[4] = {};
  SymbolModel multi_, zero_diff_;
  IntegerDecompressor ic_{32, 9};
};

// The encoder of the same predictor: the codes GpsTimeDecoder reads.
class GpsTimeEncoder {
 public:
  explicit GpsTimeEncoder(bool layered);
  void init(uint64_t first_bits);
  void encode(Encoder& enc, uint64_t bits);  // layered: only times that changed

 private:
  void encode_code(Encoder& enc, SymbolModel& m, int32_t code, bool after_zero);
  bool switch_sequence(Encoder& enc, int64_t time, bool after_zero);
  void encode_full(Encoder& enc, uint64_t bits, bool after_zero);
  void encode_after_diff(Encoder& enc, int32_t diff);
  void count_extreme(int32_t diff);

  bool layered_;
  uint32_t last_ = 0, next_ = 0;
  uint64_t time_[4] = {};
  int32_t diff_[4] = {};
  int32_t extreme_[4] = {};
  SymbolModel multi_, zero_diff_;
  IntegerCompressor ic_{32, 9};
};

}  // namespace c3d::laz
