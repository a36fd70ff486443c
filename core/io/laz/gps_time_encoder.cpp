// The LAZ GPS time encoder: the codes GpsTimeDecoder (gps_time.cpp) reads.
#include <cmath>

#include "core/io/laz/gps_time.h"

namespace c3d::laz {

namespace {

bool fits_int32(int64_t v) { return v >= INT32_MIN && v <= INT32_MAX; }
int64_t difference(uint64_t a, uint64_t b) { return int64_t(a - b); }  // of the bit patterns
int32_t times(int32_t multi, int32_t diff) { return int32_t(uint32_t(multi) * uint32_t(diff)); }

}  // namespace

GpsTimeEncoder::GpsTimeEncoder(bool layered)
    : layered_(layered),
      multi_(layered ? kGpsMultiTotal - 1 : kGpsMultiTotal),
      zero_diff_(layered ? 5 : 6) {}

void GpsTimeEncoder::init(uint64_t first_bits) {
  last_ = next_ = 0;
  for (int i = 0; i < 4; ++i) time_[i] = 0, diff_[i] = 0, extreme_[i] = 0;
  time_[0] = first_bits;
  multi_.reset();
  zero_diff_.reset();
  ic_.reset();
}

// The layered variant has no "unchanged" code and numbers the codes above it one lower.
void GpsTimeEncoder::encode_code(Encoder& enc, SymbolModel& m, int32_t code, bool after_zero) {
  if (layered_ && (after_zero || code > kGpsUnchanged)) --code;
  enc.encode_symbol(m, uint32_t(code));
}

// A time far from its sequence may continue one of the other three.
bool GpsTimeEncoder::switch_sequence(Encoder& enc, int64_t time, bool after_zero) {
  for (uint32_t i = 1; i < 4; ++i) {
    if (!fits_int32(difference(uint64_t(time), time_[(last_ + i) & 3]))) continue;
    encode_code(enc, after_zero ? zero_diff_ : multi_, after_zero ? int32_t(i) + 2 : kGpsCodeFull + int32_t(i),
                after_zero);
    last_ = (last_ + i) & 3;
    return true;
  }
  return false;
}

void GpsTimeEncoder::encode_full(Encoder& enc, uint64_t bits, bool after_zero) {
  encode_code(enc, after_zero ? zero_diff_ : multi_, after_zero ? 2 : kGpsCodeFull, after_zero);
  ic_.compress(enc, int32_t(uint32_t(time_[last_] >> 32)), int32_t(uint32_t(bits >> 32)), 8);
  enc.write_int(uint32_t(bits));
  next_ = (next_ + 1) & 3;
  last_ = next_;
  diff_[last_] = 0;
  extreme_[last_] = 0;
}

void GpsTimeEncoder::count_extreme(int32_t diff) {
  if (++extreme_[last_] > 3) {  // a new regular difference
    diff_[last_] = diff;
    extreme_[last_] = 0;
  }
}

// A difference coded against `multi` times the last one (contexts 1-7).
void GpsTimeEncoder::encode_after_diff(Encoder& enc, int32_t diff) {
  const int32_t last = diff_[last_];
  const float ratio = float(diff) / float(last);
  // Rounded as LASzip rounds; beyond the extreme codes every value codes alike.
  const int32_t multi = ratio >= float(kGpsMulti)        ? kGpsMulti
                        : ratio <= float(kGpsMultiMinus) ? kGpsMultiMinus
                                                         : int32_t(std::lround(ratio));
  if (multi == 1) {
    encode_code(enc, multi_, 1, false);
    ic_.compress(enc, last, diff, 1);
    extreme_[last_] = 0;
  } else if (multi > 0 && multi < kGpsMulti) {
    encode_code(enc, multi_, multi, false);
    ic_.compress(enc, times(multi, last), diff, multi < 10 ? 2 : 3);
  } else if (multi == kGpsMulti) {
    encode_code(enc, multi_, kGpsMulti, false);
    ic_.compress(enc, times(kGpsMulti, last), diff, 4);
    count_extreme(diff);
  } else if (multi < 0 && multi > kGpsMultiMinus) {
    encode_code(enc, multi_, kGpsMulti - multi, false);
    ic_.compress(enc, times(multi, last), diff, 5);
  } else if (multi == kGpsMultiMinus) {
    encode_code(enc, multi_, kGpsMulti - kGpsMultiMinus, false);
    ic_.compress(enc, times(kGpsMultiMinus, last), diff, 6);
    count_extreme(diff);
  } else {
    encode_code(enc, multi_, 0, false);
    ic_.compress(enc, 0, diff, 7);
    count_extreme(diff);
  }
}

void GpsTimeEncoder::encode(Encoder& enc, uint64_t bits) {
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
    time_[last_] = bits;
    return;
  }
}

}  // namespace c3d::laz
