// The POINT10 v2 item decoder (LAZ specification, point formats 0-5).
#include "core/io/laz/point10.h"

#include "core/io/laz/integer_coder.h"

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

namespace {

// Byte offsets in the 20-byte POINT10 record.
constexpr int kIntensity = 12, kFlags = 14, kClass = 15, kScanAngle = 16, kUserData = 17,
              kPointSource = 18;

class Point10Reader : public ItemReader {
 public:
  explicit Point10Reader(Decoder& dec) : dec_(dec) {}
  void init(const uint8_t* first, uint32_t&) override;
  void decode(uint8_t* out, uint32_t&) override;

 private:
  void decode_attributes(uint32_t changed, uint32_t* m);
  void decode_xyz(uint32_t n, uint32_t m, uint32_t l);
  template <typename T>
  T field(int at) const {
    T v;
    std::memcpy(&v, last_ + at, sizeof v);
    return v;
  }
  template <typename T>
  void set(int at, T v) {
    std::memcpy(last_ + at, &v, sizeof v);
  }

  Decoder& dec_;
  uint8_t last_[20] = {};
  uint16_t last_intensity_[16] = {};
  int32_t last_height_[8] = {};
  Median5 last_dx_[16], last_dy_[16];
  SymbolModel changed_values_{64};
  SymbolModel scan_angle_[2] = {SymbolModel(256), SymbolModel(256)};
  ModelBank flags_{256, 256}, classification_{256, 256}, user_data_{256, 256};
  IntegerCoder ic_intensity_{16, 4}, ic_point_source_{16}, ic_dx_{32, 2}, ic_dy_{32, 22},
      ic_z_{32, 20};
};

void Point10Reader::init(const uint8_t* first, uint32_t&) {
  for (int i = 0; i < 16; ++i) last_dx_[i].reset(), last_dy_[i].reset(), last_intensity_[i] = 0;
  for (int32_t& h : last_height_) h = 0;
  changed_values_.reset();
  scan_angle_[0].reset(), scan_angle_[1].reset();
  flags_.reset(), classification_.reset(), user_data_.reset();
  for (IntegerCoder* ic : {&ic_intensity_, &ic_point_source_, &ic_dx_, &ic_dy_, &ic_z_})
    ic->reset();
  std::memcpy(last_, first, 20);
  set<uint16_t>(kIntensity, 0);  // version 2 predicts the first intensity from 0
}

// The attributes flagged in `changed` (bits 5..0: flags byte, intensity,
// class, scan angle, user data, point source); *m becomes the return context.
void Point10Reader::decode_attributes(uint32_t changed, uint32_t* m) {
  if (changed & 32) last_[kFlags] = uint8_t(dec_.decode_symbol(flags_[last_[kFlags]]));
  const uint32_t r = last_[kFlags] & 7, n = (last_[kFlags] >> 3) & 7;
  *m = kReturnMap[n][r];
  if (changed & 16) {
    const uint32_t ctx = *m < 3 ? *m : 3;
    last_intensity_[*m] = uint16_t(ic_intensity_.decompress(dec_, last_intensity_[*m], ctx));
  }
  set<uint16_t>(kIntensity, last_intensity_[*m]);
  if (changed & 8) last_[kClass] = uint8_t(dec_.decode_symbol(classification_[last_[kClass]]));
  if (changed & 4) {
    const int32_t delta = int32_t(dec_.decode_symbol(scan_angle_[(last_[kFlags] >> 6) & 1]));
    last_[kScanAngle] = fold_u8(delta + last_[kScanAngle]);
  }
  if (changed & 2) last_[kUserData] = uint8_t(dec_.decode_symbol(user_data_[last_[kUserData]]));
  if (changed & 1)
    set<uint16_t>(kPointSource, uint16_t(ic_point_source_.decompress(dec_, field<uint16_t>(kPointSource))));
}

void Point10Reader::decode_xyz(uint32_t n, uint32_t m, uint32_t l) {
  const uint32_t single = n == 1;
  int32_t diff = ic_dx_.decompress(dec_, last_dx_[m].get(), single);
  set<int32_t>(0, wrap_add(field<int32_t>(0), diff));
  last_dx_[m].add(diff);
  uint32_t k_bits = ic_dx_.k();
  diff = ic_dy_.decompress(dec_, last_dy_[m].get(), single + (k_bits < 20 ? k_bits & ~1u : 20));
  set<int32_t>(4, wrap_add(field<int32_t>(4), diff));
  last_dy_[m].add(diff);
  k_bits = (ic_dx_.k() + ic_dy_.k()) / 2;
  const int32_t z = ic_z_.decompress(dec_, last_height_[l], single + (k_bits < 18 ? k_bits & ~1u : 18));
  set<int32_t>(8, z);
  last_height_[l] = z;
}

void Point10Reader::decode(uint8_t* out, uint32_t&) {
  const uint32_t changed = dec_.decode_symbol(changed_values_);
  uint32_t m;
  if (changed) {
    decode_attributes(changed, &m);
  } else {
    m = kReturnMap[(last_[kFlags] >> 3) & 7][last_[kFlags] & 7];
  }
  const uint32_t r = last_[kFlags] & 7, n = (last_[kFlags] >> 3) & 7;
  decode_xyz(n, m, return_level(n, r, 7));
  std::memcpy(out, last_, 20);
}

}  // namespace

std::unique_ptr<ItemReader> make_point10_v2(Decoder& dec) { return std::make_unique<Point10Reader>(dec); }

}  // namespace c3d::laz
