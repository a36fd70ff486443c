// The POINT14 item encoder (layered, item version 3): the inverse of
// layered.cpp, over the same models, one encoder per layer.
#include "core/io/laz/item_writer.h"
#include "core/io/laz/layered.h"

namespace c3d::laz {

namespace {

class Point14Writer : public ItemWriter {
 public:
  void init(const uint8_t* first, uint32_t& context) override;
  void encode(const uint8_t* item, uint32_t& context) override;
  void finish_layers() override {
    for (int i = 0; i < kLayers; ++i) layers_[i].finish(i == kXY);
  }
  void write_layer_sizes(std::vector<uint8_t>& out) const override { put_layer_sizes(layers_, kLayers, out); }
  void write_layers(std::vector<uint8_t>& out) const override { put_layers(layers_, kLayers, out); }

 private:
  uint32_t changed_values(const Point14& last, const Point14& p) const;
  void encode_returns(Point14Context& c, const Point14& p, uint32_t changed, bool gps_change);
  void encode_xyz(Point14Context& c, const Point14& p, bool gps_change);
  void encode_other_layers(Point14Context& c, const Point14& p, uint32_t changed, bool gps_change);

  LayerOut layers_[kLayers];
  Point14Contexts contexts_;
};

void Point14Writer::init(const uint8_t* first, uint32_t& context_out) {
  for (LayerOut& l : layers_) l.changed = false;
  context_out = contexts_.begin_chunk(first);
}

// Bits 6..0: scanner channel, point source, GPS time, scan angle, number of
// returns changed; return number same (0), +1 (1), -1 (2) or else (3).
uint32_t Point14Writer::changed_values(const Point14& last, const Point14& p) const {
  uint32_t changed = (uint32_t(p.channel != contexts_.channel()) << 6) | (uint32_t(p.point_source != last.point_source) << 5) |
                     (uint32_t(p.gps != last.gps) << 4) | (uint32_t(p.scan_angle != last.scan_angle) << 3) |
                     (uint32_t(p.nret != last.nret) << 2);
  if (p.ret != last.ret) {
    if (p.ret == (last.ret + 1) % 16) changed |= 1;
    else if (p.ret == (last.ret + 15) % 16) changed |= 2;
    else changed |= 3;
  }
  return changed;
}

void Point14Writer::encode_returns(Point14Context& c, const Point14& p, uint32_t changed, bool gps_change) {
  Encoder& enc = layers_[kXY].enc;
  if (changed & 4) enc.encode_symbol(c.number_of_returns[c.last.nret], p.nret);
  if ((changed & 3) != 3) return;
  if (gps_change) enc.encode_symbol(c.return_number[c.last.ret], p.ret);
  else enc.encode_symbol(c.return_number_gps_same, (uint32_t(p.ret) + 32 - c.last.ret - 2) % 16);
}

void Point14Writer::encode_xyz(Point14Context& c, const Point14& p, bool gps_change) {
  Encoder& enc = layers_[kXY].enc;
  const uint32_t n = p.nret, r = p.ret;
  const uint32_t m = xy_context(n, r, gps_change), single = n == 1;
  int32_t diff = int32_t(uint32_t(p.x) - uint32_t(c.last.x));
  c.ic_dx.compress(enc, c.last_dx[m].get(), diff, single);
  c.last_dx[m].add(diff);
  diff = int32_t(uint32_t(p.y) - uint32_t(c.last.y));
  c.ic_dy.compress(enc, c.last_dy[m].get(), diff, y_context(single, c.ic_dx.k()));
  c.last_dy[m].add(diff);
  const uint32_t l = return_level(n, r, 7);
  c.ic_z.compress(layers_[kZ].enc, c.last_z[l], p.z, z_context(single, c.ic_dx.k(), c.ic_dy.k()));
  c.last_z[l] = p.z;
  layers_[kZ].changed |= p.z != c.last.z;
}

void Point14Writer::encode_other_layers(Point14Context& c, const Point14& p, uint32_t changed, bool gps_change) {
  const Point14& last = c.last;
  const uint32_t cpr = return_context(p.ret, p.nret);
  layers_[kClass].enc.encode_symbol(c.classification[class_key(last, cpr)], p.classification);
  layers_[kClass].changed |= p.classification != last.classification;
  layers_[kFlags].enc.encode_symbol(c.flags[flags_of(last)], flags_of(p));
  layers_[kFlags].changed |= flags_of(p) != flags_of(last);
  uint16_t& intensity = c.last_intensity[intensity_slot(cpr, gps_change)];
  c.ic_intensity.compress(layers_[kIntensity].enc, intensity, p.intensity, cpr);
  intensity = p.intensity;
  layers_[kIntensity].changed |= p.intensity != last.intensity;
  if (changed & 8) {
    c.ic_scan_angle.compress(layers_[kScanAngle].enc, last.scan_angle, p.scan_angle, gps_change);
    layers_[kScanAngle].changed = true;
  }
  layers_[kUserData].enc.encode_symbol(c.user_data[user_data_key(last)], p.user_data);
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
  Point14Context* c = &contexts_.current();
  // Changes count against the point's own channel (a new one starts from this channel's last).
  const Point14* own = contexts_.used(p.channel);
  const uint32_t changed = changed_values(own ? *own : c->last, p);
  layers_[kXY].enc.encode_symbol(c->changed_values[last_point_context(c->last)], changed);
  if (changed & 64) {
    layers_[kXY].enc.encode_symbol(c->scanner_channel, (p.channel + 3 - contexts_.channel()) % 4);
    c = &contexts_.switch_to(p.channel);
  }
  context_out = contexts_.channel();
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
