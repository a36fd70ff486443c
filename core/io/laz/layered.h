#pragma once
// LAZ items of point formats 6-10 (layered compressor, item versions 3 and
// 4): each attribute of a chunk is its own arithmetic stream ("layer"), and
// up to four model sets follow the scanner channel. The contexts, models and
// per-channel state here serve the decoders (layered.cpp, layered_items.cpp)
// and the encoders (layered_writer.cpp, layered_items_writer.cpp) alike.
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/gps_time.h"
#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_reader.h"
#include "core/io/laz/rgb.h"

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
  long slack() const { return changed ? std::labs(dec.slack()) : 0; }
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

// POINT14's contexts of the LAZ specification, the same in both directions.
// Return r of n returns: first (1), last (2), both (3), neither (0).
inline uint32_t return_context(uint32_t r, uint32_t n) { return (r == 1 ? 1 : 0) + (r >= n ? 2 : 0); }
// The changed-values model follows the last point's returns and GPS change.
inline uint32_t last_point_context(const Point14& p) {
  return return_context(p.ret, p.nret) + (p.gps_changed ? 4 : 0);
}
inline uint32_t xy_context(uint32_t n, uint32_t r, bool gps_change) {
  return (uint32_t(kReturnMap6[n][r]) << 1) | uint32_t(gps_change);
}
inline uint32_t class_key(const Point14& last, uint32_t cpr) {
  return ((last.classification & 0x1Fu) << 1) + (cpr == 3 ? 1 : 0);
}
inline uint32_t flags_of(const Point14& p) { return uint32_t((p.edge << 5) | (p.scan_dir << 4) | p.class_flags); }
inline uint32_t user_data_key(const Point14& last) { return last.user_data / 4u; }
inline uint32_t intensity_slot(uint32_t cpr, bool gps_change) { return (cpr << 1) | uint32_t(gps_change); }

// The models and predictors of one scanner channel (decoder and encoder alike).
struct Point14Context {
  bool unused = true;
  Point14 last;
  uint16_t last_intensity[8] = {};
  int32_t last_z[8] = {};
  Median5 last_dx[12], last_dy[12];
  SymbolModel changed_values[8] = {SymbolModel(128), SymbolModel(128), SymbolModel(128), SymbolModel(128),
                                   SymbolModel(128), SymbolModel(128), SymbolModel(128), SymbolModel(128)};
  SymbolModel scanner_channel{3}, return_number_gps_same{13};
  ModelBank number_of_returns{16, 16}, return_number{16, 16};
  ModelBank classification{64, 256}, flags{64, 64}, user_data{64, 256};
  IntegerCoder ic_dx{32, 2}, ic_dy{32, 22}, ic_z{32, 20};
  IntegerCoder ic_intensity{16, 4}, ic_scan_angle{16, 2}, ic_point_source{16};
  GpsTimeCoder gps{true};

  void init(const Point14& from);  // the models afresh, predicting from `from`
};

// The contexts of a chunk's four scanner channels, each made on first use.
class Point14Contexts {
 public:
  // Starts a chunk at its first (raw) record; returns its channel.
  uint32_t begin_chunk(const uint8_t* first_record) {
    for (auto& c : contexts_)
      if (c) c->unused = true;
    Point14 first;
    first.from_raw(first_record);
    current_ = first.channel;
    at(current_).init(first);
    return current_;
  }
  uint32_t channel() const { return current_; }
  Point14Context& current() { return at(current_); }
  // The last point of `channel` when it was used in this chunk, else null.
  const Point14* used(uint32_t channel) const {
    const auto& c = contexts_[channel];
    return c && !c->unused ? &c->last : nullptr;
  }
  // A channel not used yet in the chunk starts from the current one's last point.
  Point14Context& switch_to(uint32_t channel) {
    Point14Context& old = at(current_);
    Point14Context& now = at(channel);
    if (now.unused) now.init(old.last);
    current_ = channel;
    now.last.channel = uint8_t(channel);
    return now;
  }

 private:
  Point14Context& at(uint32_t c) {
    if (!contexts_[c]) contexts_[c] = std::make_unique<Point14Context>();
    return *contexts_[c];
  }
  std::unique_ptr<Point14Context> contexts_[4];
  uint32_t current_ = 0;
};

// The contexts of a layered item that follows POINT14's scanner channel.
// Version 3 has a quirk the encoder shares, so both directions keep it: on
// switching to a channel already used in the chunk, the predictor keeps the
// previous channel's last value (version 4 takes the new channel's).
template <class Context>
class ChannelFollower {
 public:
  explicit ChannelFollower(size_t bytes) : bytes_(bytes) {}
  void begin_chunk(uint32_t channel, const uint8_t* first) {
    for (Context& c : contexts_) c.unused = true;
    current_ = channel;
    contexts_[current_].start(first, bytes_);
  }
  // The context of `channel`; `last`: the values to predict from (and update).
  Context& follow(uint32_t channel, int version, typename Context::Value*& last) {
    last = contexts_[current_].values();
    if (current_ != channel) {
      current_ = channel;
      Context& now = contexts_[current_];
      if (now.unused) {
        now.start(last, bytes_);
        last = now.values();
      } else if (version >= 4) {
        last = now.values();
      }
    }
    return contexts_[current_];
  }

 private:
  size_t bytes_;
  Context contexts_[4];
  uint32_t current_ = 0;
};

enum LayerId { kXY, kZ, kClass, kFlags, kIntensity, kScanAngle, kUserData, kPointSource, kGps, kLayers };

std::unique_ptr<ItemReader> make_point14(int version);
std::unique_ptr<ItemReader> make_rgb14(int version, bool nir);
std::unique_ptr<ItemReader> make_byte14(int version, uint32_t count);

}  // namespace c3d::laz
