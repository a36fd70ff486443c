// The LAZ integer models and decompressor (see integer_coder.h).
#include "core/io/laz/integer_coder.h"

namespace c3d::laz {

IntegerModels::IntegerModels(uint32_t bits_in, uint32_t contexts, uint32_t bits_high_in, uint32_t range)
    : bits_high(bits_high_in) {
  if (range) {  // the corrector covers range values around 0
    corr_range = range;
    while (range) range >>= 1, ++corr_bits;
    if (corr_range == (1u << (corr_bits - 1))) --corr_bits;
  } else if (bits_in && bits_in < 32) {
    corr_bits = bits_in;
    corr_range = 1u << bits_in;
  } else {  // full 32 bits: values wrap around
    corr_bits = 32;
    corr_range = 0;
  }
  corr_min = corr_range ? -int32_t(corr_range / 2) : INT32_MIN;
  corr_max = corr_range ? int32_t(int64_t(corr_min) + corr_range - 1) : INT32_MAX;
  bits.assign(contexts, SymbolModel(corr_bits + 1));
  for (uint32_t i = 1; i <= corr_bits; ++i)
    corrector.emplace_back(i <= bits_high ? 1u << i : 1u << bits_high);
}

void IntegerModels::reset() {
  for (SymbolModel& m : bits) m.reset();
  corrector_0.reset();
  for (SymbolModel& m : corrector) m.reset();
}

int32_t IntegerCoder::decompress(Decoder& dec, int32_t pred, uint32_t context) {
  // Two's-complement wrap-around as the encoder computed it, without signed overflow.
  int32_t real = int32_t(uint32_t(pred) + uint32_t(read_corrector(dec, m_.bits[context])));
  if (real < 0) real = int32_t(uint32_t(real) + m_.corr_range);
  else if (uint32_t(real) >= m_.corr_range) real = int32_t(uint32_t(real) - m_.corr_range);
  return real;
}

int32_t IntegerCoder::read_corrector(Decoder& dec, SymbolModel& bits_model) {
  k_ = dec.decode_symbol(bits_model);
  if (k_ == 0) return int32_t(dec.decode_bit(m_.corrector_0));
  // k = 32 (32-bit values only) is the one corrector -2^31: no further bits.
  if (k_ >= 32) return m_.corr_min;
  int64_t c = dec.decode_symbol(m_.corrector[k_ - 1]);
  if (k_ > m_.bits_high) {  // the low k - bits_high bits come raw
    const uint32_t low_bits = k_ - m_.bits_high;
    c = (c << low_bits) | dec.read_bits(low_bits);
  }
  // [0, 2^(k-1)) maps to [-(2^k - 1), -2^(k-1)], the rest to [2^(k-1) + 1, 2^k]
  if (c >= (int64_t(1) << (k_ - 1))) c += 1;
  else c -= (int64_t(1) << k_) - 1;
  return int32_t(c);
}

}  // namespace c3d::laz
