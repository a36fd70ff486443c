// The LAZ integer compressor (see integer_coder.h).
#include "core/io/laz/integer_coder.h"

namespace c3d::laz {

void IntegerCoder::compress(Encoder& enc, int32_t pred, int32_t real, uint32_t context) {
  // The corrector, folded into [corr_min, corr_max] (32-bit values wrap around).
  int32_t corr = int32_t(uint32_t(real) - uint32_t(pred));
  if (m_.corr_range) {
    int64_t c = int64_t(real) - int64_t(pred);
    if (c < m_.corr_min) c += m_.corr_range;
    else if (c > m_.corr_max) c -= m_.corr_range;
    corr = int32_t(c);
  }
  write_corrector(enc, corr, m_.bits[context]);
}

void IntegerCoder::write_corrector(Encoder& enc, int32_t c, SymbolModel& bits_model) {
  // k: the tightest interval [-(2^k - 1), 2^k] holding c.
  uint32_t c1 = c <= 0 ? 0u - uint32_t(c) : uint32_t(c) - 1;
  k_ = 0;
  while (c1) c1 >>= 1, ++k_;
  enc.encode_symbol(bits_model, k_);
  if (k_ == 0) {  // c is 0 or 1
    enc.encode_bit(m_.corrector_0, uint32_t(c));
    return;
  }
  if (k_ >= 32) return;  // c = -2^31: k says it all
  // Negative c to [0, 2^(k-1)), positive to [2^(k-1), 2^k).
  uint32_t v = c < 0 ? uint32_t(int64_t(c) + (int64_t(1) << k_) - 1) : uint32_t(c) - 1;
  if (k_ <= m_.bits_high) {
    enc.encode_symbol(m_.corrector[k_ - 1], v);
    return;
  }
  const uint32_t low_bits = k_ - m_.bits_high;  // the low bits go raw
  const uint32_t low = v & ((1u << low_bits) - 1);
  enc.encode_symbol(m_.corrector[k_ - 1], v >> low_bits);
  enc.write_bits(low_bits, low);
}

}  // namespace c3d::laz
