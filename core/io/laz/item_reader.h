#pragma once
// Pieces the LAZ item decoders share, most of them with the encoders too:
// the error a damaged stream raises, a record's item coders (RecordItems), a
// bounds-checked cursor over a chunk's bytes, the item decoder interface and
// the small predictors and contexts of the LAZ specification.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/laz_reader.h"

namespace c3d::laz {

// A damaged or unsupported LAZ stream; laz_reader turns it into InputError.
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <typename T>
T load(const uint8_t* p) {  // a field at an unaligned address
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The coders of one record's items (ItemReader or ItemWriter), the one stream
// the point-wise items share, and where each item starts in the record.
template <class Stream, class Coder>
struct RecordItems {
  Stream stream;
  std::vector<std::unique_ptr<Coder>> coders;
  std::vector<uint32_t> offsets;
  bool layered = false;

  // Makes each item's coder (make(item)); the items must fill the record.
  template <class Make>
  void add(const LaszipVlr& vlr, uint32_t record_length, Make make) {
    layered = vlr.compressor == kCompressorLayered;
    uint32_t offset = 0;
    for (const Item& it : vlr.items) {
      coders.push_back(make(it));
      offsets.push_back(offset);
      offset += it.size;
    }
    if (offset != record_length)
      throw FormatError("LASzip items make " + std::to_string(offset) + "-byte records, the header says " +
                        std::to_string(record_length));
  }
};

// Reads a chunk's header fields and layer bytes, never past `end`.
struct ByteCursor {
  const uint8_t* pos;
  const uint8_t* end;
  const uint8_t* take(size_t n, const char* what) {
    if (size_t(end - pos) < n) throw FormatError(std::string("truncated chunk (") + what + ")");
    const uint8_t* p = pos;
    pos += n;
    return p;
  }
  uint32_t u32(const char* what) {
    uint32_t v;
    std::memcpy(&v, take(4, what), 4);
    return v;
  }
};

// One item of a point record (LASzip's POINT10, GPSTIME11, RGB12, BYTE,
// POINT14, ...). A chunk starts with the raw record that init() sees; each
// later record is decode()d. `context` is the scanner channel: POINT14 sets
// it, the other layered items follow it.
class ItemReader {
 public:
  virtual ~ItemReader() = default;
  virtual void read_layer_sizes(ByteCursor&) {}  // layered items only
  virtual void load_layers(ByteCursor&) {}       // layered items only
  virtual void init(const uint8_t* first, uint32_t& context) = 0;
  virtual void decode(uint8_t* out, uint32_t& context) = 0;
  // Layered items: the bytes their layers left unread or read past their
  // ends, summed (0 when a chunk decoded whole).
  virtual long layer_slack() const { return 0; }
};

// Symbol models keyed by a previous value, made on first use (as the encoder
// makes them) and reset at each chunk start.
class ModelBank {
 public:
  ModelBank(size_t keys, uint32_t symbols) : symbols_(symbols), models_(keys) {}
  SymbolModel& operator[](size_t key) {
    auto& m = models_[key];
    if (!m) m = std::make_unique<SymbolModel>(symbols_);
    return *m;
  }
  void reset() {
    for (auto& m : models_)
      if (m) m->reset();
  }

 private:
  uint32_t symbols_;
  std::vector<std::unique_ptr<SymbolModel>> models_;
};

// The state of BYTE and of a channel of BYTE14: one model and one last
// value a byte.
struct ByteContext {
  using Value = uint8_t;
  bool unused = true;
  std::vector<SymbolModel> models;
  std::vector<uint8_t> last;
  void start(const void* from, size_t count) {
    if (models.empty()) models.assign(count, SymbolModel(256));
    for (SymbolModel& m : models) m.reset();
    last.assign(static_cast<const uint8_t*>(from), static_cast<const uint8_t*>(from) + count);
    unused = false;
  }
  uint8_t* values() { return last.data(); }
};

// Median of the last five values, updated in LASzip's streaming order.
class Median5 {
 public:
  void reset() {
    for (int32_t& v : v_) v = 0;
    high_ = true;
  }
  int32_t get() const { return v_[2]; }
  void add(int32_t v);

 private:
  int32_t v_[5] = {0, 0, 0, 0, 0};
  bool high_ = true;
};

inline uint8_t fold_u8(int32_t n) { return uint8_t(n < 0 ? n + 256 : n > 255 ? n - 256 : n); }
inline int32_t clamp_u8(int32_t n) { return n < 0 ? 0 : n > 255 ? 255 : n; }
inline int32_t wrap_add(int32_t a, int32_t b) { return int32_t(uint32_t(a) + uint32_t(b)); }

// Context tables of the LAZ specification: by number of returns n and return r.
extern const uint8_t kReturnMap[8][8];     // POINT10: 16 contexts
extern const uint8_t kReturnMap6[16][16];  // POINT14: 6 contexts
inline uint32_t return_level(uint32_t n, uint32_t r, uint32_t cap) {  // |n - r|, capped
  const uint32_t d = n > r ? n - r : r - n;
  return d < cap ? d : cap;
}
// The contexts of y's and z's corrector (POINT10 and POINT14): the bit
// lengths of x's (and y's) correctors, even, capped; `single`: one return.
inline uint32_t y_context(uint32_t single, uint32_t k_x) { return single + (k_x < 20 ? k_x & ~1u : 20); }
inline uint32_t z_context(uint32_t single, uint32_t k_x, uint32_t k_y) {
  const uint32_t k = (k_x + k_y) / 2;
  return single + (k < 18 ? k & ~1u : 18);
}

}  // namespace c3d::laz
