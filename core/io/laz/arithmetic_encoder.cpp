// The LAZ arithmetic encoder (see the header).
#include "core/io/laz/arithmetic_encoder.h"

namespace c3d::laz {

void Encoder::encode_bit(BitModel& m, uint32_t bit) {
  const uint32_t x = m.bit_0_prob_ * (length_ >> kBitLengthShift);
  if (bit == 0) {
    length_ = x;
    ++m.bit_0_count_;
  } else {
    add_to_base(x);
    length_ -= x;
  }
  if (length_ < kMinLength) renormalise();
  if (--m.until_update_ == 0) m.update();
}

void Encoder::encode_symbol(SymbolModel& m, uint32_t sym) {
  uint32_t x;
  if (sym == m.last_symbol_) {  // the top of the interval: no product needed
    x = m.distribution_[sym] * (length_ >> kSymbolLengthShift);
    add_to_base(x);
    length_ -= x;
  } else {
    x = m.distribution_[sym] * (length_ >>= kSymbolLengthShift);
    add_to_base(x);
    length_ = m.distribution_[sym + 1] * length_ - x;
  }
  if (length_ < kMinLength) renormalise();
  ++m.count_[sym];
  if (--m.until_update_ == 0) m.update();
}

void Encoder::write_bits(uint32_t bits, uint32_t value) {
  if (bits > 19) {  // as the decoder reads them: the low 16 bits first
    write_short(value & 0xFFFFu);
    value >>= 16;
    bits -= 16;
  }
  add_to_base(value * (length_ >>= bits));
  if (length_ < kMinLength) renormalise();
}

void Encoder::propagate_carry() {
  for (auto p = out_.rbegin(); p != out_.rend(); ++p) {
    if (*p != 0xFF) {
      ++*p;
      return;
    }
    *p = 0;
  }
}

std::vector<uint8_t> Encoder::finish() {
  const uint32_t before = base_;
  bool another_byte = true;
  if (length_ > 2 * kMinLength) {
    base_ += kMinLength;
    length_ = kMinLength >> 1;
  } else {
    base_ += kMinLength >> 1;
    length_ = kMinLength >> 9;
    another_byte = false;
  }
  if (before > base_) propagate_carry();
  renormalise();
  // The decoder reads four bytes ahead of the last symbol: pad with zeros.
  out_.insert(out_.end(), another_byte ? 3 : 2, 0);
  std::vector<uint8_t> bytes;
  bytes.swap(out_);
  base_ = 0;
  length_ = kMaxLength;
  return bytes;
}

}  // namespace c3d::laz
