#pragma once
// The entropy encoder of the LAZ format, the inverse of arithmetic_decoder.h
// (LASzip's FastAC range encoder as the LAZ specification fixes it). It uses
// the decoder's models, so both sides adapt alike: an encoded stream decodes
// to the same symbols because every model update happens in the same order.
#include <cstdint>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"

namespace c3d::laz {

class Encoder {
 public:
  void encode_bit(BitModel& m, uint32_t bit);
  void encode_symbol(SymbolModel& m, uint32_t sym);
  void write_bits(uint32_t bits, uint32_t value);  // 1-32 raw bits
  void write_short(uint32_t value) { write_bits(16, value & 0xFFFFu); }
  void write_int(uint32_t value) {
    write_short(value & 0xFFFFu);
    write_short(value >> 16);
  }
  // Flushes the interval (with the zero bytes the decoder reads ahead) and
  // returns the stream; the encoder starts afresh.
  std::vector<uint8_t> finish();

 private:
  void propagate_carry();
  void renormalise() {
    do {
      out_.push_back(uint8_t(base_ >> 24));
      base_ <<= 8;
    } while ((length_ <<= 8) < kMinLength);
  }
  void add_to_base(uint32_t x) {
    const uint32_t before = base_;
    base_ += x;
    if (before > base_) propagate_carry();  // overflow: carry into the bytes out
  }

  std::vector<uint8_t> out_;
  uint32_t base_ = 0, length_ = kMaxLength;
};

}  // namespace c3d::laz
