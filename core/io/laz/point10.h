#pragma once
// LAZ item decoders of point formats 0-5 (compressor version 2): POINT10 (the
// 20 bytes every legacy record starts with), GPSTIME11, RGB12 and BYTE (extra
// bytes). All share the chunk's one arithmetic decoder. POINT10's models and
// predictors (Point10Context) serve the encoder (items_v2_writer.cpp) too.
#include <cstring>
#include <memory>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_reader.h"

namespace c3d::laz {

// The models and predictors of POINT10 v2, the same in both directions.
struct Point10Context {
  // Byte offsets in the 20-byte POINT10 record.
  static constexpr int kIntensity = 12, kFlags = 14, kClass = 15, kScanAngle = 16, kUserData = 17,
                       kPointSource = 18;
  uint8_t last[20] = {};
  uint16_t last_intensity[16] = {};
  int32_t last_height[8] = {};
  Median5 last_dx[16], last_dy[16];
  SymbolModel changed_values{64};
  SymbolModel scan_angle[2] = {SymbolModel(256), SymbolModel(256)};
  ModelBank flags{256, 256}, classification{256, 256}, user_data{256, 256};
  IntegerCoder ic_intensity{16, 4}, ic_point_source{16}, ic_dx{32, 2}, ic_dy{32, 22}, ic_z{32, 20};

  void init(const uint8_t* first);  // the models afresh, predicting from `first`
  // The context of x, y and intensity: the return r of n in a flags byte.
  static uint32_t return_map(uint8_t flags) { return kReturnMap[(flags >> 3) & 7][flags & 7]; }
  static uint32_t intensity_context(uint32_t m) { return m < 3 ? m : 3; }
  template <typename T>
  static T load(const uint8_t* record, int at) {
    return laz::load<T>(record + at);
  }
  template <typename T>
  T field(int at) const {
    return load<T>(last, at);
  }
  template <typename T>
  void set(int at, T v) {
    std::memcpy(last + at, &v, sizeof v);
  }
};

std::unique_ptr<ItemReader> make_point10_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_gpstime11_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_rgb12_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_byte_v2(Decoder& dec, uint32_t count);

}  // namespace c3d::laz
