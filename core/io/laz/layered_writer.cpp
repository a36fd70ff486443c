// The POINT14 item encoder (layered, item version 3): the inverse of
// layered.cpp, over the same models, one encoder per layer.
#include "core/io/laz/gps_time.h"
#include "core/io/laz/integer_coder.h"
#include "core/io/laz/item_writer.h"
#include "core/io/laz/layered.h"

namespace c3d::laz {

namespace {

// The models and predictors of one scanner channel (as the decoder's Context).
struct WriteContext {
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

  void init(const Point14& from) {
    for (SymbolModel& m : changed_values) m.reset();
    scanner_channel.reset(), return_number_gps_same.reset();
    for (ModelBank* b : {&number_of_returns, &return_number, &classification, &flags, &user_data}) b->reset();
    for (IntegerCoder* ic : {&ic_dx, &ic_dy, &ic_z, &ic_intensity, &ic_scan_angle, &ic_point_source})
      ic->reset();
    for (int i = 0; i < 12; ++i) last_dx[i].reset(), last_dy[i].reset();
    for (int i = 0; i < 8; ++i) last_z[i] = from.z, last_intensity[i] = from.intensity;
    gps.init(from.gps);
    last = from;
    last.gps_changed = false;
    unused = false;
  }
};

uint32_t flags_of(const Point14& p) { return uint32_t((p.edge << 5) | (p.scan_dir << 4) | p.class_flags); }

class Point14Writer : public ItemWriter {
 public:
  void init(const uint8_t* first, uint32_t& context) override;
  void encode(const uint8_t* item, uint32_t& context) override;
  void finish_layers() override {
    for (int i = 0; i < kLayers; ++i) layers_[i].finish(i == kXY);
  }
  void write_layer_sizes(std::vector<uint8_t>& out) const override {
    for (const LayerOut& l : layers_) put_u32(out, uint32_t(l.bytes.size()));
  }
  void write_layers(std::vector<uint8_t>& out) const override {
    for (const LayerOut& l : layers_) out.insert(out.end(), l.bytes.begin(), l.bytes.end());
  }

 private:
  WriteContext& context(uint32_t c) {
    if (!contexts_[c]) contexts_[c] = std::make_unique<WriteContext>();
    return *contexts_[c];
  }
  uint32_t changed_values(const Point14& last, const Point14& p) const;
  void encode_returns(WriteContext& c, const Point14& p, uint32_t changed, bool gps_change);
  void encode_xyz(WriteContext& c, const Point14& p, bool gps_change);
  void encode_other_layers(WriteContext& c, const Point14& p, uint32_t changed, bool gps_change);

  LayerOut layers_[kLayers];
  std::unique_ptr<WriteContext> contexts_[4];
  uint32_t current_ = 0;
};

void Point14Writer::init(const uint8_t* first, uint32_t& context_out) {
  for (auto& c : contexts_)
    if (c) c->unused = true;
  for (LayerOut& l : layers_) l.changed = false;
  Point14 p;
  p.from_raw(first);
  current_ = p.channel;
  context_out = current_;
  context(current_).init(p);
}

// Bits 6..0: scanner channel, point source, GPS time, scan angle, number of
// returns changed; return number same (0), +1 (1), -1 (2) or else (3).
uint32_t Point14Writer::changed_values(const Point14& last, const Point14& p) const {
  uint32_t changed = (uint32_t(p.channel != current_) << 6) | (uint32_t(p.point_source != last.point_source) << 5) |
                     (uint32_t(p.gps != last.gps) << 4) | (uint32_t(p.scan_angle != last.scan_angle) << 3) |
                     (uint32_t(p.nret != last.nret) << 2);
  if (p.ret != last.ret) {
    if (p.ret == (last.ret + 1) % 16) changed |= 1;
    else if (p.ret == (last.ret + 15) % 16) changed |= 2;
    else changed |= 3;
  }
  return changed;
}

void Point14Writer::encode_returns(WriteContext& c, const Point14& p, uint32_t changed, bool gps_change) {
  Encoder& enc = layers_[kXY].enc;
  if (changed & 4) enc.encode_symbol(c.number_of_returns[c.last.nret], p.nret);
  if ((changed & 3) != 3) return;
  if (gps_change) enc.encode_symbol(c.return_number[c.last.ret], p.ret);
  else enc.encode_symbol(c.return_number_gps_same, (uint32_t(p.ret) + 32 - c.last.ret - 2) % 16);
}

void Point14Writer::encode_xyz(WriteContext& c, const Point14& p, bool gps_change) {
  Encoder& enc = layers_[kXY].enc;
  const uint32_t n = p.nret, r = p.ret;
  const uint32_t m = (uint32_t(kReturnMap6[n][r]) << 1) | gps_change, single = n == 1;
  int32_t diff = int32_t(uint32_t(p.x) - uint32_t(c.last.x));
  c.ic_dx.compress(enc, c.last_dx[m].get(), diff, single);
  c.last_dx[m].add(diff);
  uint32_t k_bits = c.ic_dx.k();
  diff = int32_t(uint32_t(p.y) - uint32_t(c.last.y));
  c.ic_dy.compress(enc, c.last_dy[m].get(), diff, single + (k_bits < 20 ? k_bits & ~1u : 20));
  c.last_dy[m].add(diff);
  k_bits = (c.ic_dx.k() + c.ic_dy.k()) / 2;
  const uint32_t l = return_level(n, r, 7);
  c.ic_z.compress(layers_[kZ].enc, c.last_z[l], p.z, single + (k_bits < 18 ? k_bits & ~1u : 18));
  c.last_z[l] = p.z;
  layers_[kZ].changed |= p.z != c.last.z;
}

void Point14Writer::encode_other_layers(WriteContext& c, const Point14& p, uint32_t changed, bool gps_change) {
  const Point14& last = c.last;
  const uint32_t cpr = (p.ret == 1 ? 1 : 0) + (p.ret >= p.nret ? 2 : 0);
  const uint32_t class_key = ((last.classification & 0x1Fu) << 1) + (cpr == 3 ? 1 : 0);
  layers_[kClass].enc.encode_symbol(c.classification[class_key], p.classification);
  layers_[kClass].changed |= p.classification != last.classification;
  layers_[kFlags].enc.encode_symbol(c.flags[flags_of(last)], flags_of(p));
  layers_[kFlags].changed |= flags_of(p) != flags_of(last);
  uint16_t& intensity = c.last_intensity[(cpr << 1) | gps_change];
  c.ic_intensity.compress(layers_[kIntensity].enc, intensity, p.intensity, cpr);
  intensity = p.intensity;
  layers_[kIntensity].changed |= p.intensity != last.intensity;
  if (changed & 8) {
    c.ic_scan_angle.compress(layers_[kScanAngle].enc, last.scan_angle, p.scan_angle, gps_change);
    layers_[kScanAngle].changed = true;
  }
  layers_[kUserData].enc.encode_symbol(c.user_data[last.user_data / 4], p.user_data);
  layers_[kUserData].changed |= p.user_data != last.user_data;
  if (changed & 32) {
    c.ic_point_source.compress(layers_[kPointSource].enc, last.point_source, p.point_source);
    layers_[kPointSource].changed = true;
  }
  if (gps_change) {
    c.gps.encode(layers_[kGps].enc, p.gps);
    layers_[kGps].changed = true;
  }
}

void Point14Writer::encode(const uint8_t* item, uint32_t& context_out) {
  Point14 p;
  p.from_raw(item);
  WriteContext* c = &context(current_);
  const Point14& prev = c->last;
  const uint32_t lpr = (prev.ret == 1 ? 1 : 0) + (prev.ret >= prev.nret ? 2 : 0) + (prev.gps_changed ? 4 : 0);
  // Changes count against the point's own channel (a new one starts from this channel's last).
  const Point14& last = p.channel != current_ && contexts_[p.channel] && !contexts_[p.channel]->unused
                            ? contexts_[p.channel]->last
                            : c->last;
  const uint32_t changed = changed_values(last, p);
  layers_[kXY].enc.encode_symbol(c->changed_values[lpr], changed);
  if (changed & 64) {
    layers_[kXY].enc.encode_symbol(c->scanner_channel, (p.channel + 3 - current_) % 4);
    WriteContext& now = context(p.channel);
    if (now.unused) now.init(c->last);
    current_ = p.channel;
    now.last.channel = p.channel;
    c = &now;
  }
  context_out = current_;
  const bool gps_change = changed & 16;
  encode_returns(*c, p, changed, gps_change);
  encode_xyz(*c, p, gps_change);
  encode_other_layers(*c, p, changed, gps_change);
  c->last = p;
  c->last.gps_changed = gps_change;
}

}  // namespace

std::unique_ptr<ItemWriter> make_point14_writer() { return std::make_unique<Point14Writer>(); }

}  // namespace c3d::laz
