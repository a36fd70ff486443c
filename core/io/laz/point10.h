#pragma once
// LAZ item decoders of point formats 0-5 (compressor version 2): POINT10 (the
// 20 bytes every legacy record starts with), GPSTIME11, RGB12 and BYTE (extra
// bytes). All share the chunk's one arithmetic decoder.
#include <memory>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/item_reader.h"

namespace c3d::laz {

std::unique_ptr<ItemReader> make_point10_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_gpstime11_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_rgb12_v2(Decoder& dec);
std::unique_ptr<ItemReader> make_byte_v2(Decoder& dec, uint32_t count);

}  // namespace c3d::laz
