#pragma once
// The entropy decoder of the LAZ format (LASzip's adaptation of Amir Said's
// FastAC, as the LAZ specification fixes it): a 32-bit range decoder,
// adaptive symbol models that rebuild their distribution periodically (with
// a lookup table for alphabets over 16 symbols) and adaptive bit models.
// Bit-exactness with the encoder depends on every constant here.
//
// A damaged stream must never read out of bounds: bytes past the end read as
// zero (the encoder pads its streams with zeros, so a valid stream never
// needs them), and a table index is clamped where a damaged value could push
// it past the table.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace c3d::laz {

constexpr uint32_t kMinLength = 1u << 24;      // renormalise below 2^24
constexpr uint32_t kMaxLength = 0xFFFFFFFFu;   // the interval a stream starts with
constexpr uint32_t kBitLengthShift = 13;       // bit probabilities in 13 bits
constexpr uint32_t kBitMaxCount = 1u << 13;    // halve bit counts beyond this
constexpr uint32_t kSymbolLengthShift = 15;    // symbol distributions in 15 bits
constexpr uint32_t kSymbolMaxCount = 1u << 15; // halve symbol counts beyond this

class SymbolModel {
 public:
  explicit SymbolModel(uint32_t symbols);
  void reset();  // back to equiprobable, as at the start of a chunk
  uint32_t symbols() const { return symbols_; }

 private:
  friend class Decoder;
  friend class Encoder;
  void update();
  uint32_t symbols_, last_symbol_;
  uint32_t table_size_ = 0, table_shift_ = 0;
  uint32_t total_count_ = 0, update_cycle_ = 0, until_update_ = 0;
  std::vector<uint32_t> distribution_, count_, table_;
};

class BitModel {
 public:
  BitModel() { reset(); }
  void reset();

 private:
  friend class Decoder;
  friend class Encoder;
  void update();
  uint32_t bit_0_count_, bit_count_, bit_0_prob_, update_cycle_, until_update_;
};

class Decoder {
 public:
  // Starts decoding [begin, end): the first four bytes are the initial value.
  void start(const uint8_t* begin, const uint8_t* end);
  uint32_t decode_bit(BitModel& m);
  uint32_t decode_symbol(SymbolModel& m);
  uint32_t read_bits(uint32_t bits);  // 1-32 raw bits
  uint32_t read_short() { return read_bits(16); }
  uint32_t read_int();
  // Bytes asked for past the end (a damaged or truncated stream).
  size_t overrun() const { return overrun_; }
  // Bytes left unread, less those asked for past the end: a stream decoded
  // whole ends at 0 (the encoder pads it to the decoder's last read).
  long slack() const { return long(end_ - pos_) - long(overrun_); }

 private:
  uint8_t next_byte() {
    if (pos_ < end_) return *pos_++;
    ++overrun_;
    return 0;
  }
  void renormalise() {
    do value_ = (value_ << 8) | next_byte();
    while ((length_ <<= 8) < kMinLength);
  }
  uint32_t symbol_by_table(SymbolModel& m, uint32_t* x, uint32_t* y);
  uint32_t symbol_by_bisection(SymbolModel& m, uint32_t* x, uint32_t* y);

  const uint8_t* pos_ = nullptr;
  const uint8_t* end_ = nullptr;
  uint32_t value_ = 0, length_ = kMaxLength;
  size_t overrun_ = 0;
};

// ------------------------------------------------------------ hot path ----

inline uint32_t Decoder::decode_bit(BitModel& m) {
  const uint32_t x = m.bit_0_prob_ * (length_ >> kBitLengthShift);
  const uint32_t bit = value_ >= x;
  if (bit == 0) {
    length_ = x;
    ++m.bit_0_count_;
  } else {
    value_ -= x;
    length_ -= x;
  }
  if (length_ < kMinLength) renormalise();
  if (--m.until_update_ == 0) m.update();
  return bit;
}

inline uint32_t Decoder::symbol_by_table(SymbolModel& m, uint32_t* x, uint32_t* y) {
  const uint32_t dv = value_ / (length_ >>= kSymbolLengthShift);
  uint32_t t = dv >> m.table_shift_;
  if (t > m.table_size_) t = m.table_size_;  // only a damaged stream gets here
  uint32_t sym = m.table_[t];
  uint32_t n = m.table_[t + 1] + 1;
  while (n > sym + 1) {  // bisection within the table's bracket
    const uint32_t k = (sym + n) >> 1;
    if (m.distribution_[k] > dv) n = k;
    else sym = k;
  }
  *x = m.distribution_[sym] * length_;
  if (sym != m.last_symbol_) *y = m.distribution_[sym + 1] * length_;
  return sym;
}

inline uint32_t Decoder::symbol_by_bisection(SymbolModel& m, uint32_t* x, uint32_t* y) {
  uint32_t sym = 0, n = m.symbols_;
  *x = 0;
  length_ >>= kSymbolLengthShift;
  uint32_t k = n >> 1;
  do {
    const uint32_t z = length_ * m.distribution_[k];
    if (z > value_) {
      n = k;
      *y = z;
    } else {
      sym = k;
      *x = z;
    }
  } while ((k = (sym + n) >> 1) != sym);
  return sym;
}

inline uint32_t Decoder::decode_symbol(SymbolModel& m) {
  uint32_t x, y = length_;
  const uint32_t sym = m.table_.empty() ? symbol_by_bisection(m, &x, &y) : symbol_by_table(m, &x, &y);
  value_ -= x;
  length_ = y - x;
  if (length_ < kMinLength) renormalise();
  ++m.count_[sym];
  if (--m.until_update_ == 0) m.update();
  return sym;
}

inline uint32_t Decoder::read_bits(uint32_t bits) {
  if (bits > 19) {  // the range holds at most 19 raw bits at once
    const uint32_t low = read_short();
    return (read_bits(bits - 16) << 16) | low;
  }
  const uint32_t sym = value_ / (length_ >>= bits);
  value_ -= length_ * sym;
  if (length_ < kMinLength) renormalise();
  return sym;
}

}  // namespace c3d::laz
