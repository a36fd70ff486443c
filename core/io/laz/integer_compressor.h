#pragma once
// The LAZ integer compressor, the inverse of IntegerDecompressor over the
// same models (integer_models.h).
#include <cstdint>

#include "core/io/laz/arithmetic_encoder.h"
#include "core/io/laz/integer_models.h"

namespace c3d::laz {

class IntegerCompressor {
 public:
  explicit IntegerCompressor(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bits_high = 8,
                             uint32_t range = 0)
      : m_(bits, contexts, bits_high, range) {}
  void reset() { m_.reset(); }
  void compress(Encoder& enc, int32_t pred, int32_t real, uint32_t context = 0);
  uint32_t k() const { return k_; }  // bit length of the last corrector

 private:
  void write_corrector(Encoder& enc, int32_t c, SymbolModel& bits_model);
  IntegerModels m_;
  uint32_t k_ = 0;
};

}  // namespace c3d::laz
