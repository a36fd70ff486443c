#pragma once
// LAZ item decoders of point formats 6-10 (layered compressor, item versions
// 3 and 4): each attribute of a chunk is its own arithmetic stream ("layer"),
// and up to four model sets follow the scanner channel.
#include <cstring>
#include <memory>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/item_reader.h"

namespace c3d::laz {

// One layer of a chunk: its byte count, then its own decoder over its bytes.
struct Layer {
  uint32_t size = 0;
  bool changed = false;  // holds data in this chunk (else the value stays)
  Decoder dec;
  void load(ByteCursor& in, bool always = false) {
    const uint8_t* p = in.take(size, "layer bytes");
    changed = size > 0;
    if (changed || always) dec.start(p, p + size);
  }
};

// The 30-byte POINT14 record, unpacked.
struct Point14 {
  int32_t x = 0, y = 0, z = 0;
  uint16_t intensity = 0;
  uint8_t ret = 0, nret = 0, class_flags = 0, channel = 0, scan_dir = 0, edge = 0;
  uint8_t classification = 0, user_data = 0;
  int16_t scan_angle = 0;
  uint16_t point_source = 0;
  uint64_t gps = 0;
  bool gps_changed = false;  // not in the record: a context of the next point

  void from_raw(const uint8_t* p) {
    std::memcpy(&x, p, 4), std::memcpy(&y, p + 4, 4), std::memcpy(&z, p + 8, 4);
    std::memcpy(&intensity, p + 12, 2);
    ret = p[14] & 15, nret = p[14] >> 4;
    class_flags = p[15] & 15, channel = (p[15] >> 4) & 3, scan_dir = (p[15] >> 6) & 1, edge = p[15] >> 7;
    classification = p[16], user_data = p[17];
    std::memcpy(&scan_angle, p + 18, 2), std::memcpy(&point_source, p + 20, 2);
    std::memcpy(&gps, p + 22, 8);
  }
  void to_raw(uint8_t* p) const {
    std::memcpy(p, &x, 4), std::memcpy(p + 4, &y, 4), std::memcpy(p + 8, &z, 4);
    std::memcpy(p + 12, &intensity, 2);
    p[14] = uint8_t(ret | (nret << 4));
    p[15] = uint8_t(class_flags | (channel << 4) | (scan_dir << 6) | (edge << 7));
    p[16] = classification, p[17] = user_data;
    std::memcpy(p + 18, &scan_angle, 2), std::memcpy(p + 20, &point_source, 2);
    std::memcpy(p + 22, &gps, 8);
  }
};

enum LayerId { kXY, kZ, kClass, kFlags, kIntensity, kScanAngle, kUserData, kPointSource, kGps, kLayers };

std::unique_ptr<ItemReader> make_point14(int version);
std::unique_ptr<ItemReader> make_rgb14(int version, bool nir);
std::unique_ptr<ItemReader> make_byte14(int version, uint32_t count);

}  // namespace c3d::laz
