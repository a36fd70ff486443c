#pragma once
// The models of the LAZ integer coder, shared by the decompressor and the
// compressor: a value is a prediction plus a corrector; the corrector's bit
// length k is an adaptive symbol (one model per context), its position within
// [-(2^k-1), 2^k] an adaptive symbol of up to bits_high bits followed by raw
// bits. k of the last value is itself a context for others.
#include <cstdint>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"

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

}  // namespace c3d::laz
