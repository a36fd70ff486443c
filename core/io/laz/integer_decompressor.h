#pragma once
// The LAZ integer decompressor: a value is a prediction plus a corrector; the
// corrector's bit length k is an adaptive symbol (one model per context), its
// position within [-(2^k-1), 2^k] an adaptive symbol of up to bits_high bits
// followed by raw bits. k of the last value is itself a context for others.
#include <cstdint>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"

namespace c3d::laz {

class IntegerDecompressor {
 public:
  explicit IntegerDecompressor(uint32_t bits = 16, uint32_t contexts = 1, uint32_t bits_high = 8,
                               uint32_t range = 0);
  void reset();  // models back to their start, as at a chunk start
  int32_t decompress(Decoder& dec, int32_t pred, uint32_t context = 0);
  uint32_t k() const { return k_; }  // bit length of the last corrector

 private:
  int32_t read_corrector(Decoder& dec, SymbolModel& bits_model);
  uint32_t corr_bits_ = 0, corr_range_ = 0, bits_high_ = 8, k_ = 0;
  std::vector<SymbolModel> bits_;       // per context: which k
  BitModel corrector_0_;                // k = 0: the corrector is 0 or 1
  std::vector<SymbolModel> corrector_;  // k = 1..corr_bits (index k - 1)
};

}  // namespace c3d::laz
