// The POINT10 v2 item decoder (LAZ specification, point formats 0-5).
#include "core/io/laz/point10.h"


namespace c3d::laz {

const uint8_t kReturnMap[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8}, {14, 0, 1, 3, 6, 10, 10, 9},   {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},   {11, 6, 7, 8, 9, 13, 13, 12},  {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};

void Median5::add(int32_t v) {
  int32_t* m = v_;
  if (high_) {
    if (v < m[2]) {
      m[4] = m[3], m[3] = m[2];
      if (v < m[0]) m[2] = m[1], m[1] = m[0], m[0] = v;
      else if (v < m[1]) m[2] = m[1], m[1] = v;
      else m[2] = v;
    } else {
      if (v < m[3]) m[4] = m[3], m[3] = v;
      else m[4] = v;
      high_ = false;
    }
  } else {
    if (m[2] < v) {
      m[0] = m[1], m[1] = m[2];
      if (m[4] < v) m[2] = m[3], m[3] = m[4], m[4] = v;
      else if (m[3] < v) m[2] = m[3], m[3] = v;
      else m[2] = v;
    } else {
      if (m[1] < v) m[0] = m[1], m[1] = v;
      else m[0] = v;
      high_ = true;
    }
  }
}

void Point10Context::init(const uint8_t* first) {
  for (int i = 0; i < 16; ++i) last_dx[i].reset(), last_dy[i].reset(), last_intensity[i] = 0;
  for (int32_t& h : last_height) h = 0;
  changed_values.reset();
  scan_angle[0].reset(), scan_angle[1].reset();
  flags.reset(), classification.reset(), user_data.reset();
  for (IntegerCoder* ic : {&ic_intensity, &ic_point_source, &ic_dx, &ic_dy, &ic_z}) ic->reset();
  std::memcpy(last, first, 20);
  std::memset(last + kIntensity, 0, 2);  // version 2 predicts the first intensity from 0
}

namespace {

class Point10Reader : public ItemReader, Point10Context {
 public:
  explicit Point10Reader(Decoder& dec) : dec_(dec) {}
  void init(const uint8_t* first, uint32_t&) override;
  void decode(uint8_t* out, uint32_t&) override;

 private:
  void decode_attributes(uint32_t changed, uint32_t* m);
  void decode_xyz(uint32_t n, uint32_t m, uint32_t l);

  Decoder& dec_;
};

void Point10Reader::init(const uint8_t* first, uint32_t&) { Point10Context::init(first); }

// The attributes flagged in `changed` (bits 5..0: flags byte, intensity,
// class, scan angle, user data, point source); *m becomes the return context.
void Point10Reader::decode_attributes(uint32_t changed, uint32_t* m) {
  if (changed & 32) last[kFlags] = uint8_t(dec_.decode_symbol(flags[last[kFlags]]));
  *m = return_map(last[kFlags]);
  if (changed & 16) {
    last_intensity[*m] = uint16_t(ic_intensity.decompress(dec_, last_intensity[*m], intensity_context(*m)));
  }
  set<uint16_t>(kIntensity, last_intensity[*m]);
  if (changed & 8) last[kClass] = uint8_t(dec_.decode_symbol(classification[last[kClass]]));
  if (changed & 4) {
    const int32_t delta = int32_t(dec_.decode_symbol(scan_angle[(last[kFlags] >> 6) & 1]));
    last[kScanAngle] = fold_u8(delta + last[kScanAngle]);
  }
  if (changed & 2) last[kUserData] = uint8_t(dec_.decode_symbol(user_data[last[kUserData]]));
  if (changed & 1)
    set<uint16_t>(kPointSource, uint16_t(ic_point_source.decompress(dec_, field<uint16_t>(kPointSource))));
}

void Point10Reader::decode_xyz(uint32_t n, uint32_t m, uint32_t l) {
  const uint32_t single = n == 1;
  int32_t diff = ic_dx.decompress(dec_, last_dx[m].get(), single);
  set<int32_t>(0, wrap_add(field<int32_t>(0), diff));
  last_dx[m].add(diff);
  diff = ic_dy.decompress(dec_, last_dy[m].get(), y_context(single, ic_dx.k()));
  set<int32_t>(4, wrap_add(field<int32_t>(4), diff));
  last_dy[m].add(diff);
  const int32_t z = ic_z.decompress(dec_, last_height[l], z_context(single, ic_dx.k(), ic_dy.k()));
  set<int32_t>(8, z);
  last_height[l] = z;
}

void Point10Reader::decode(uint8_t* out, uint32_t&) {
  const uint32_t changed = dec_.decode_symbol(changed_values);
  uint32_t m;
  if (changed) {
    decode_attributes(changed, &m);
  } else {
    m = return_map(last[kFlags]);
  }
  const uint32_t r = last[kFlags] & 7, n = (last[kFlags] >> 3) & 7;
  decode_xyz(n, m, return_level(n, r, 7));
  std::memcpy(out, last, 20);
}

}  // namespace

std::unique_ptr<ItemReader> make_point10_v2(Decoder& dec) { return std::make_unique<Point10Reader>(dec); }

}  // namespace c3d::laz
