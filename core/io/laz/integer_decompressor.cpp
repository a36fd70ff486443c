// The LAZ integer decompressor (see the header).
#include "core/io/laz/integer_decompressor.h"

namespace c3d::laz {

IntegerDecompressor::IntegerDecompressor(uint32_t bits, uint32_t contexts, uint32_t bits_high,
                                         uint32_t range)
    : bits_high_(bits_high) {
  if (range) {  // the corrector covers range values around 0
    corr_range_ = range;
    while (range) range >>= 1, ++corr_bits_;
    if (corr_range_ == (1u << (corr_bits_ - 1))) --corr_bits_;
  } else if (bits && bits < 32) {
    corr_bits_ = bits;
    corr_range_ = 1u << bits;
  } else {  // full 32 bits: values wrap around
    corr_bits_ = 32;
    corr_range_ = 0;
  }
  bits_.assign(contexts, SymbolModel(corr_bits_ + 1));
  for (uint32_t i = 1; i <= corr_bits_; ++i)
    corrector_.emplace_back(i <= bits_high_ ? 1u << i : 1u << bits_high_);
}

void IntegerDecompressor::reset() {
  for (SymbolModel& m : bits_) m.reset();
  corrector_0_.reset();
  for (SymbolModel& m : corrector_) m.reset();
}

int32_t IntegerDecompressor::decompress(Decoder& dec, int32_t pred, uint32_t context) {
  // Two's-complement wrap-around as the encoder computed it, without signed overflow.
  int32_t real = int32_t(uint32_t(pred) + uint32_t(read_corrector(dec, bits_[context])));
  if (real < 0) real = int32_t(uint32_t(real) + corr_range_);
  else if (uint32_t(real) >= corr_range_) real = int32_t(uint32_t(real) - corr_range_);
  return real;
}

int32_t IntegerDecompressor::read_corrector(Decoder& dec, SymbolModel& bits_model) {
  k_ = dec.decode_symbol(bits_model);
  if (k_ == 0) return int32_t(dec.decode_bit(corrector_0_));
  int64_t c = dec.decode_symbol(corrector_[k_ - 1]);
  if (k_ > bits_high_) {  // the low k - bits_high bits come raw
    const uint32_t low_bits = k_ - bits_high_;
    c = (c << low_bits) | dec.read_bits(low_bits);
  }
  // [0, 2^(k-1)) maps to [-(2^k - 1), -2^(k-1)], the rest to [2^(k-1) + 1, 2^k]
  if (c >= (int64_t(1) << (k_ - 1))) c += 1;
  else c -= (int64_t(1) << k_) - 1;
  return int32_t(c);
}

}  // namespace c3d::laz
