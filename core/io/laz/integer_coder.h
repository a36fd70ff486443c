#pragma once
// The LAZ integer coder, one for both directions: a value is a prediction
// plus a corrector; the corrector's bit length k is an adaptive symbol (one
// model per context), its position within [-(2^k-1), 2^k] an adaptive symbol
// of up to bits_high bits followed by raw bits. k of the last value is itself
// a context for others. decompress (integer_decompressor.cpp) reads what
// compress (integer_compressor.cpp) writes, over the same models.
#include <cstdint>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/arithmetic_encoder.h"

namespace c3d::laz {

struct IntegerModels {
  IntegerModels(uint32_t bits, uint32_t contexts, uint32_t bits_high, uint32_t range);
  void reset();  // models back to their start, as at a chunk start

  uint32_t corr_bits = 0, corr_range = 0, bits_high = 8;
  int32_t corr_min = 0, corr_max = 0;  // correctors fold into [corr_min, corr_max]
  std::vector<SymbolModel> bits;       // per context: which k
  BitModel corrector_0;                // k = 0: the corrector is 0 or 1
  std::vector<SymbolModel> corrector;  // k = 1..corr_bits (index k - 1)
};

class IntegerCoder {
 public:
  explicit IntegerCoder(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bits_high = 8, uint32_t range = 0)
      : m_(bits, contexts, bits_high, range) {}
  void reset() { m_.reset(); }
  int32_t decompress(Decoder& dec, int32_t pred, uint32_t context = 0);
  void compress(Encoder& enc, int32_t pred, int32_t real, uint32_t context = 0);
  uint32_t k() const { return k_; }  // bit length of the last corrector

 private:
  int32_t read_corrector(Decoder& dec, SymbolModel& bits_model);
  void write_corrector(Encoder& enc, int32_t c, SymbolModel& bits_model);
  IntegerModels m_;
  uint32_t k_ = 0;
};

}  // namespace c3d::laz
