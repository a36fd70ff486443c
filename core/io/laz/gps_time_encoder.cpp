// The LAZ GPS time encoder: the codes GpsTimeCoder::decode (gps_time.cpp) reads.
#include <cmath>

#include "core/io/laz/gps_time.h"

namespace c3d::laz {

namespace {

bool fits_int32(int64_t v) { return v >= INT32_MIN && v <= INT32_MAX; }
int64_t difference(uint64_t a, uint64_t b) { return int64_t(a - b); }  // of the bit patterns

}  // namespace

// The layered variant has no "unchanged" code and numbers the codes above it one lower.
void GpsTimeCoder::encode_code(Encoder& enc, SymbolModel& m, int32_t code, bool after_zero) {
  if (layered_ && (after_zero || code > kGpsUnchanged)) --code;
  enc.encode_symbol(m, uint32_t(code));
}

// A time far from its sequence may continue one of the other three.
bool GpsTimeCoder::switch_sequence(Encoder& enc, int64_t time, bool after_zero) {
  for (uint32_t i = 1; i < 4; ++i) {
    if (!fits_int32(difference(uint64_t(time), time_[(last_ + i) & 3]))) continue;
    encode_code(enc, after_zero ? zero_diff_ : multi_, after_zero ? int32_t(i) + 2 : kGpsCodeFull + int32_t(i),
                after_zero);
    last_ = (last_ + i) & 3;
    return true;
  }
  return false;
}

void GpsTimeCoder::encode_full(Encoder& enc, uint64_t bits, bool after_zero) {
  encode_code(enc, after_zero ? zero_diff_ : multi_, after_zero ? 2 : kGpsCodeFull, after_zero);
  ic_.compress(enc, int32_t(uint32_t(time_[last_] >> 32)), int32_t(uint32_t(bits >> 32)), 8);
  enc.write_int(uint32_t(bits));
  start_sequence(bits);
}

// A difference coded against a multiple of the last one (contexts 1-7).
void GpsTimeCoder::encode_after_diff(Encoder& enc, int32_t diff) {
  const int32_t last = diff_[last_];
  const float ratio = float(diff) / float(last);
  // Rounded as LASzip rounds; beyond the extreme codes every value codes alike.
  const int32_t multi = ratio >= float(kGpsMulti)        ? kGpsMulti
                        : ratio <= float(kGpsMultiMinus) ? kGpsMultiMinus
                                                         : int32_t(std::lround(ratio));
  const int32_t code = multi >= 0 ? multi : kGpsMulti - multi;
  encode_code(enc, multi_, code, false);
  if (code == 1) {
    ic_.compress(enc, last, diff, 1);
    extreme_[last_] = 0;
    return;
  }
  const Multiplier m = multiplier(code);
  ic_.compress(enc, m.pred, diff, m.context);
  if (m.extreme) count_extreme(diff);
}

void GpsTimeCoder::encode(Encoder& enc, uint64_t bits) {
  for (;;) {  // at most one switch of sequence, then a code
    const bool after_zero = diff_[last_] == 0;
    if (bits == time_[last_]) {
      encode_code(enc, after_zero ? zero_diff_ : multi_, after_zero ? 0 : kGpsUnchanged, after_zero);
      return;
    }
    const int64_t diff = difference(bits, time_[last_]);
    if (fits_int32(diff)) {
      if (after_zero) {
        encode_code(enc, zero_diff_, 1, true);
        ic_.compress(enc, 0, int32_t(diff), 0);
        diff_[last_] = int32_t(diff);
        extreme_[last_] = 0;
      } else {
        encode_after_diff(enc, int32_t(diff));
      }
      time_[last_] = bits;
      return;
    }
    if (switch_sequence(enc, int64_t(bits), after_zero)) continue;
    encode_full(enc, bits, after_zero);
    return;
  }
}

}  // namespace c3d::laz
