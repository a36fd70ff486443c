// The LAZ GPS time predictor (see the header).
#include "core/io/laz/gps_time.h"

#include "core/io/laz/item_reader.h"

namespace c3d::laz {

namespace {

constexpr int32_t kMulti = kGpsMulti, kMultiMinus = kGpsMultiMinus;
constexpr int32_t kUnchanged = kGpsUnchanged, kCodeFull = kGpsCodeFull, kMultiTotal = kGpsMultiTotal;
// A valid stream switches sequence once before a time; more is damage.
constexpr int kMaxSwitches = 4;

}  // namespace

GpsTimeDecoder::GpsTimeDecoder(bool layered)
    : layered_(layered), multi_(layered ? kMultiTotal - 1 : kMultiTotal), zero_diff_(layered ? 5 : 6) {}

void GpsTimeDecoder::init(uint64_t first_bits) {
  last_ = next_ = 0;
  for (int i = 0; i < 4; ++i) time_[i] = 0, diff_[i] = 0, extreme_[i] = 0;
  time_[0] = first_bits;
  multi_.reset();
  zero_diff_.reset();
  ic_.reset();
}

void GpsTimeDecoder::decode_full(Decoder& dec) {
  next_ = (next_ + 1) & 3;
  const uint32_t high = uint32_t(ic_.decompress(dec, int32_t(uint32_t(time_[last_] >> 32)), 8));
  time_[next_] = (uint64_t(high) << 32) | dec.read_int();
  last_ = next_;
  diff_[last_] = 0;
  extreme_[last_] = 0;
}

// After a zero difference: 0 unchanged, 1 a 32-bit difference, 2 a full
// time, 3-5 switch sequence. Returns true when a switch asks to go on.
bool GpsTimeDecoder::decode_after_zero_diff(Decoder& dec) {
  const int32_t code = int32_t(dec.decode_symbol(zero_diff_)) + (layered_ ? 1 : 0);
  if (code == 1) {
    diff_[last_] = ic_.decompress(dec, 0, 0);
    time_[last_] += uint64_t(int64_t(diff_[last_]));
    extreme_[last_] = 0;
  } else if (code == 2) {
    decode_full(dec);
  } else if (code > 2) {
    last_ = (last_ + uint32_t(code) - 2) & 3;
    return true;
  }
  return false;
}

// A difference predicted as `multi` times the last one (contexts 2-7).
int32_t GpsTimeDecoder::diff_for_multiplier(Decoder& dec, int32_t multi) {
  const int32_t last = diff_[last_];
  int32_t diff;
  bool extreme = false;
  if (multi == 0) {
    diff = ic_.decompress(dec, 0, 7);
    extreme = true;
  } else if (multi < kMulti) {
    diff = ic_.decompress(dec, int32_t(uint32_t(multi) * uint32_t(last)), multi < 10 ? 2 : 3);
  } else if (multi == kMulti) {
    diff = ic_.decompress(dec, int32_t(uint32_t(kMulti) * uint32_t(last)), 4);
    extreme = true;
  } else {
    multi = kMulti - multi;
    if (multi > kMultiMinus) {
      diff = ic_.decompress(dec, int32_t(uint32_t(multi) * uint32_t(last)), 5);
    } else {
      diff = ic_.decompress(dec, int32_t(uint32_t(kMultiMinus) * uint32_t(last)), 6);
      extreme = true;
    }
  }
  if (extreme && ++extreme_[last_] > 3) {  // a new regular difference
    diff_[last_] = diff;
    extreme_[last_] = 0;
  }
  return diff;
}

bool GpsTimeDecoder::decode_after_diff(Decoder& dec) {
  int32_t code = int32_t(dec.decode_symbol(multi_));
  if (layered_ && code >= kUnchanged) ++code;
  if (code == 1) {
    time_[last_] += uint64_t(int64_t(ic_.decompress(dec, diff_[last_], 1)));
    extreme_[last_] = 0;
  } else if (code < kUnchanged) {
    time_[last_] += uint64_t(int64_t(diff_for_multiplier(dec, code)));
  } else if (code == kCodeFull) {
    decode_full(dec);
  } else if (code > kCodeFull) {
    last_ = (last_ + uint32_t(code - kCodeFull)) & 3;
    return true;
  }
  return false;
}

uint64_t GpsTimeDecoder::decode(Decoder& dec) {
  for (int i = 0; i < kMaxSwitches; ++i) {
    const bool switched = diff_[last_] == 0 ? decode_after_zero_diff(dec) : decode_after_diff(dec);
    if (!switched) return time_[last_];
  }
  throw FormatError("GPS time stream switches sequence without end");
}

}  // namespace c3d::laz
