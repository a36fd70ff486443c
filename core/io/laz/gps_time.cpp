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

GpsTimeCoder::GpsTimeCoder(bool layered)
    : layered_(layered), multi_(layered ? kMultiTotal - 1 : kMultiTotal), zero_diff_(layered ? 5 : 6) {}

void GpsTimeCoder::init(uint64_t first_bits) {
  last_ = next_ = 0;
  for (int i = 0; i < 4; ++i) time_[i] = 0, diff_[i] = 0, extreme_[i] = 0;
  time_[0] = first_bits;
  multi_.reset();
  zero_diff_.reset();
  ic_.reset();
}

void GpsTimeCoder::start_sequence(uint64_t bits) {
  next_ = (next_ + 1) & 3;
  last_ = next_;
  time_[last_] = bits;
  diff_[last_] = 0;
  extreme_[last_] = 0;
}

void GpsTimeCoder::count_extreme(int32_t diff) {
  if (++extreme_[last_] > 3) {  // a new regular difference
    diff_[last_] = diff;
    extreme_[last_] = 0;
  }
}

// Codes 2-499 predict code times the last difference, 500 and 501-510
// (-1 to -10 times) likewise, the extremes 500 and -10 as extreme; code 0 is
// an extreme difference predicted from nothing.
GpsTimeCoder::Multiplier GpsTimeCoder::multiplier(int32_t code) const {
  const int32_t last = diff_[last_];
  const auto times = [last](int32_t multi) { return int32_t(uint32_t(multi) * uint32_t(last)); };
  if (code == 0) return {0, 7, true};
  if (code < kMulti) return {times(code), code < 10 ? 2u : 3u, false};
  if (code == kMulti) return {times(kMulti), 4, true};
  const int32_t multi = kMulti - code;
  if (multi > kMultiMinus) return {times(multi), 5, false};
  return {times(kMultiMinus), 6, true};
}

void GpsTimeCoder::decode_full(Decoder& dec) {
  const uint32_t high = uint32_t(ic_.decompress(dec, int32_t(uint32_t(time_[last_] >> 32)), 8));
  start_sequence((uint64_t(high) << 32) | dec.read_int());
}

// After a zero difference: 0 unchanged, 1 a 32-bit difference, 2 a full
// time, 3-5 switch sequence. Returns true when a switch asks to go on.
bool GpsTimeCoder::decode_after_zero_diff(Decoder& dec) {
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

// A difference predicted from the multiplier code (contexts 2-7).
int32_t GpsTimeCoder::diff_for_multiplier(Decoder& dec, int32_t code) {
  const Multiplier m = multiplier(code);
  const int32_t diff = ic_.decompress(dec, m.pred, m.context);
  if (m.extreme) count_extreme(diff);
  return diff;
}

bool GpsTimeCoder::decode_after_diff(Decoder& dec) {
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

uint64_t GpsTimeCoder::decode(Decoder& dec) {
  for (int i = 0; i < kMaxSwitches; ++i) {
    const bool switched = diff_[last_] == 0 ? decode_after_zero_diff(dec) : decode_after_diff(dec);
    if (!switched) return time_[last_];
  }
  throw FormatError("GPS time stream switches sequence without end");
}

}  // namespace c3d::laz
