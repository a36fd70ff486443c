// Model updates and stream start of the LAZ arithmetic decoder.
#include "core/io/laz/arithmetic_decoder.h"

namespace c3d::laz {

SymbolModel::SymbolModel(uint32_t symbols) : symbols_(symbols), last_symbol_(symbols - 1) {
  // Alphabets over 16 symbols get a decoder table of 2^table_bits entries.
  if (symbols > 16) {
    uint32_t table_bits = 3;
    while (symbols > (1u << (table_bits + 2))) ++table_bits;
    table_size_ = 1u << table_bits;
    table_shift_ = kSymbolLengthShift - table_bits;
    table_.assign(table_size_ + 2, 0);
  }
  distribution_.assign(symbols, 0);
  count_.assign(symbols, 1);
  reset();
}

void SymbolModel::reset() {
  total_count_ = 0;
  update_cycle_ = symbols_;
  count_.assign(symbols_, 1);
  update();
  until_update_ = update_cycle_ = (symbols_ + 6) >> 1;
}

void SymbolModel::update() {
  if ((total_count_ += update_cycle_) > kSymbolMaxCount) {
    total_count_ = 0;
    for (uint32_t& c : count_) total_count_ += (c = (c + 1) >> 1);
  }
  const uint32_t scale = 0x80000000u / total_count_;
  uint32_t sum = 0, s = 0;
  for (uint32_t k = 0; k < symbols_; ++k) {
    distribution_[k] = (scale * sum) >> (31 - kSymbolLengthShift);
    sum += count_[k];
    if (table_.empty()) continue;
    const uint32_t w = distribution_[k] >> table_shift_;
    while (s < w) table_[++s] = k - 1;
  }
  if (!table_.empty()) {
    table_[0] = 0;
    while (s <= table_size_) table_[++s] = symbols_ - 1;
  }
  update_cycle_ = (5 * update_cycle_) >> 2;
  const uint32_t max_cycle = (symbols_ + 6) << 3;
  if (update_cycle_ > max_cycle) update_cycle_ = max_cycle;
  until_update_ = update_cycle_;
}

void BitModel::reset() {
  bit_0_count_ = 1;
  bit_count_ = 2;
  bit_0_prob_ = 1u << (kBitLengthShift - 1);
  update_cycle_ = until_update_ = 4;
}

void BitModel::update() {
  if ((bit_count_ += update_cycle_) > kBitMaxCount) {
    bit_count_ = (bit_count_ + 1) >> 1;
    bit_0_count_ = (bit_0_count_ + 1) >> 1;
    if (bit_0_count_ == bit_count_) ++bit_count_;
  }
  const uint32_t scale = 0x80000000u / bit_count_;
  bit_0_prob_ = (bit_0_count_ * scale) >> (31 - kBitLengthShift);
  update_cycle_ = (5 * update_cycle_) >> 2;
  if (update_cycle_ > 64) update_cycle_ = 64;
  until_update_ = update_cycle_;
}

void Decoder::start(const uint8_t* begin, const uint8_t* end) {
  pos_ = begin;
  end_ = end;
  overrun_ = 0;
  length_ = kMaxLength;
  value_ = 0;
  for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next_byte();
}

uint32_t Decoder::read_int() {
  const uint32_t low = read_short();
  const uint32_t high = read_short();
  return (high << 16) | low;
}

}  // namespace c3d::laz
