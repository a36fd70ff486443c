#pragma once
// The GPS time predictor of LAZ (GPSTIME11 v2 and POINT14's gps_time layer):
// four interleaved sequences, each predicting the next time as a multiple of
// its last integer difference of the double's bit pattern.
#include <cstdint>

#include "core/io/laz/integer_coder.h"

namespace c3d::laz {

// Codes of the multiplier model (version 2 numbering; the layered variant
// has no kGpsUnchanged and so numbers the last codes one lower).
constexpr int32_t kGpsMulti = 500, kGpsMultiMinus = -10;
constexpr int32_t kGpsUnchanged = kGpsMulti - kGpsMultiMinus + 1;  // 511
constexpr int32_t kGpsCodeFull = kGpsMulti - kGpsMultiMinus + 2;   // 512
constexpr int32_t kGpsMultiTotal = kGpsMulti - kGpsMultiMinus + 6; // 516 symbols

// One sequence state for both directions: decode (gps_time.cpp) reads the
// codes encode (gps_time_encoder.cpp) writes.
class GpsTimeCoder {
 public:
  // layered: POINT14's variant, whose codes lack the "unchanged" symbol.
  explicit GpsTimeCoder(bool layered);
  void init(uint64_t first_bits);
  uint64_t decode(Decoder& dec);             // the next time's bit pattern
  void encode(Encoder& enc, uint64_t bits);  // layered: only times that changed

 private:
  // How a difference with multiplier code `code` (0 or 2-510) is predicted.
  struct Multiplier {
    int32_t pred;
    uint32_t context;
    bool extreme;  // counts towards a new regular difference
  };
  Multiplier multiplier(int32_t code) const;
  void count_extreme(int32_t diff);
  void start_sequence(uint64_t bits);  // a full time opens the next sequence

  bool decode_after_zero_diff(Decoder& dec);
  bool decode_after_diff(Decoder& dec);
  void decode_full(Decoder& dec);
  int32_t diff_for_multiplier(Decoder& dec, int32_t code);

  void encode_code(Encoder& enc, SymbolModel& m, int32_t code, bool after_zero);
  bool switch_sequence(Encoder& enc, int64_t time, bool after_zero);
  void encode_full(Encoder& enc, uint64_t bits, bool after_zero);
  void encode_after_diff(Encoder& enc, int32_t diff);

  bool layered_;
  uint32_t last_ = 0, next_ = 0;
  uint64_t time_[4] = {};
  int32_t diff_[4] = {};
  int32_t extreme_[4] = {};
  SymbolModel multi_, zero_diff_;
  IntegerCoder ic_{32, 9};
};

}  // namespace c3d::laz
