// The POINT14 item decoder (layered, item versions 3 and 4).
#include "core/io/laz/layered.h"

namespace c3d::laz {

const uint8_t kReturnMap6[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};

void Point14Context::init(const Point14& from) {
  for (SymbolModel& m : changed_values) m.reset();
  scanner_channel.reset(), return_number_gps_same.reset();
  for (ModelBank* b : {&number_of_returns, &return_number, &classification, &flags, &user_data}) b->reset();
  for (IntegerCoder* ic : {&ic_dx, &ic_dy, &ic_z, &ic_intensity, &ic_scan_angle, &ic_point_source}) ic->reset();
  for (int i = 0; i < 12; ++i) last_dx[i].reset(), last_dy[i].reset();
  for (int i = 0; i < 8; ++i) last_z[i] = from.z, last_intensity[i] = from.intensity;
  gps.init(from.gps);
  last = from;
  last.gps_changed = false;
  unused = false;
}

namespace {

class Point14Reader : public ItemReader {
 public:
  void read_layer_sizes(ByteCursor& in) override {
    for (Layer& l : layers_) l.size = in.u32("layer sizes");
  }
  void load_layers(ByteCursor& in) override {
    for (int i = 0; i < kLayers; ++i) layers_[i].load(in, i == kXY);
  }
  void init(const uint8_t* first, uint32_t& context) override;
  void decode(uint8_t* out, uint32_t& context) override;
  long layer_slack() const override {
    long s = 0;
    for (const Layer& l : layers_) s += l.slack();
    return s;
  }

 private:
  Point14Context& switch_channel(uint32_t& context);
  uint32_t decode_returns(Point14Context& c, uint32_t changed, bool gps_change);
  void decode_xyz(Point14Context& c, uint32_t n, uint32_t r, bool gps_change);
  void decode_other_layers(Point14Context& c, uint32_t changed, uint32_t cpr, bool gps_change);

  Layer layers_[kLayers];
  Point14Contexts contexts_;
};

void Point14Reader::init(const uint8_t* first, uint32_t& context_out) {
  context_out = contexts_.begin_chunk(first);
}

// A new scanner channel, coded as its distance from the current one.
Point14Context& Point14Reader::switch_channel(uint32_t& context_out) {
  const uint32_t diff = layers_[kXY].dec.decode_symbol(contexts_.current().scanner_channel);
  context_out = (contexts_.channel() + diff + 1) % 4;
  return contexts_.switch_to(context_out);
}

// The number of returns n (stored) and the return number r (returned).
uint32_t Point14Reader::decode_returns(Point14Context& c, uint32_t changed, bool gps_change) {
  Decoder& dec = layers_[kXY].dec;
  Point14& last = c.last;
  if (changed & 4) last.nret = uint8_t(dec.decode_symbol(c.number_of_returns[last.nret]));
  const uint32_t last_r = last.ret;
  uint32_t r;
  switch (changed & 3) {
    case 0: r = last_r; break;
    case 1: r = (last_r + 1) % 16; break;
    case 2: r = (last_r + 15) % 16; break;
    default:
      r = gps_change ? dec.decode_symbol(c.return_number[last_r])
                     : (last_r + dec.decode_symbol(c.return_number_gps_same) + 2) % 16;
  }
  last.ret = uint8_t(r);
  return r;
}

void Point14Reader::decode_xyz(Point14Context& c, uint32_t n, uint32_t r, bool gps_change) {
  Decoder& dec = layers_[kXY].dec;
  const uint32_t m = xy_context(n, r, gps_change), single = n == 1;
  int32_t diff = c.ic_dx.decompress(dec, c.last_dx[m].get(), single);
  c.last.x = wrap_add(c.last.x, diff);
  c.last_dx[m].add(diff);
  diff = c.ic_dy.decompress(dec, c.last_dy[m].get(), y_context(single, c.ic_dx.k()));
  c.last.y = wrap_add(c.last.y, diff);
  c.last_dy[m].add(diff);
  if (!layers_[kZ].changed) return;
  const uint32_t l = return_level(n, r, 7);
  c.last.z = c.ic_z.decompress(layers_[kZ].dec, c.last_z[l], z_context(single, c.ic_dx.k(), c.ic_dy.k()));
  c.last_z[l] = c.last.z;
}

void Point14Reader::decode_other_layers(Point14Context& c, uint32_t changed, uint32_t cpr, bool gps_change) {
  Point14& p = c.last;
  if (layers_[kClass].changed)
    p.classification = uint8_t(layers_[kClass].dec.decode_symbol(c.classification[class_key(p, cpr)]));
  if (layers_[kFlags].changed) {
    const uint32_t flags = layers_[kFlags].dec.decode_symbol(c.flags[flags_of(p)]);
    p.edge = (flags >> 5) & 1, p.scan_dir = (flags >> 4) & 1, p.class_flags = flags & 15;
  }
  if (layers_[kIntensity].changed) {
    uint16_t& last = c.last_intensity[intensity_slot(cpr, gps_change)];
    last = uint16_t(c.ic_intensity.decompress(layers_[kIntensity].dec, last, cpr));
    p.intensity = last;
  }
  if (layers_[kScanAngle].changed && (changed & 8))
    p.scan_angle = int16_t(c.ic_scan_angle.decompress(layers_[kScanAngle].dec, p.scan_angle, gps_change));
  if (layers_[kUserData].changed)
    p.user_data = uint8_t(layers_[kUserData].dec.decode_symbol(c.user_data[user_data_key(p)]));
  if (layers_[kPointSource].changed && (changed & 32))
    p.point_source = uint16_t(c.ic_point_source.decompress(layers_[kPointSource].dec, p.point_source));
  if (layers_[kGps].changed && gps_change) p.gps = c.gps.decode(layers_[kGps].dec);
}

void Point14Reader::decode(uint8_t* out, uint32_t& context_out) {
  Point14Context* c = &contexts_.current();
  const uint32_t changed = layers_[kXY].dec.decode_symbol(c->changed_values[last_point_context(c->last)]);
  if (changed & 64) c = &switch_channel(context_out);
  const bool gps_change = changed & 16;
  const uint32_t r = decode_returns(*c, changed, gps_change);
  const uint32_t n = c->last.nret;
  decode_xyz(*c, n, r, gps_change);
  const uint32_t cpr = return_context(r, n);
  decode_other_layers(*c, changed, cpr, gps_change);
  c->last.to_raw(out);
  c->last.gps_changed = gps_change;
}

}  // namespace

std::unique_ptr<ItemReader> make_point14(int) { return std::make_unique<Point14Reader>(); }

}  // namespace c3d::laz
