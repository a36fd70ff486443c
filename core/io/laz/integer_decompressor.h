#pragma once
// The LAZ integer decompressor (the models: integer_models.h).
#include <cstdint>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/integer_models.h"

namespace c3d::laz {

class IntegerDecompressor {
 public:
  explicit IntegerDecompressor(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bits_high = 8,
                               uint32_t range = 0)
      : m_(bits, contexts, bits_high, range) {}
  void reset() { m_.reset(); }
  int32_t decompress(Decoder& dec, int32_t pred, uint32_t context = 0);
  uint32_t k() const { return k_; }  // bit length of the last corrector

 private:
  int32_t read_corrector(Decoder& dec, SymbolModel& bits_model);
  IntegerModels m_;
  uint32_t k_ = 0;
};

}  // namespace c3d::laz
