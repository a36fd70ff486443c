// The RGB14, RGBNIR14 and BYTE14 item decoders (layered, item versions 3 and
// 4). They follow the scanner channel POINT14 decodes (ChannelFollower,
// layered.h, with version 3's quirk).
#include <vector>

#include "core/io/laz/layered.h"
#include "core/io/laz/rgb.h"

namespace c3d::laz {

namespace {

class Rgb14Reader : public ItemReader {
 public:
  Rgb14Reader(int version, bool nir) : version_(version), nir_(nir), contexts_(nir ? 8 : 6) {}
  void read_layer_sizes(ByteCursor& in) override {
    rgb_.size = in.u32("layer sizes");
    if (nir_) nir_layer_.size = in.u32("layer sizes");
  }
  void load_layers(ByteCursor& in) override {
    rgb_.load(in);
    if (nir_) nir_layer_.load(in);
  }
  void init(const uint8_t* first, uint32_t& context) override { contexts_.begin_chunk(context, first); }
  void decode(uint8_t* out, uint32_t& context) override;
  long layer_slack() const override { return rgb_.slack() + (nir_ ? nir_layer_.slack() : 0); }

 private:
  uint16_t decode_nir(RgbContext& c, uint16_t last);

  int version_;
  bool nir_;
  Layer rgb_, nir_layer_;
  ChannelFollower<RgbContext> contexts_;
};

uint16_t Rgb14Reader::decode_nir(RgbContext& c, uint16_t last) {
  Decoder& dec = nir_layer_.dec;
  const uint32_t sym = dec.decode_symbol(c.nir_used);
  uint16_t low = byte_of(last, true), high = byte_of(last, false);
  if (sym & 1) low = fold_u8(int32_t(dec.decode_symbol(c.nir_diff[0])) + low);
  if (sym & 2) high = fold_u8(int32_t(dec.decode_symbol(c.nir_diff[1])) + high);
  return uint16_t(low | (high << 8));
}

void Rgb14Reader::decode(uint8_t* out, uint32_t& context) {
  uint16_t* last;
  RgbContext& c = contexts_.follow(context, version_, last);
  uint16_t value[4];
  if (rgb_.changed) {
    decode_rgb(rgb_.dec, c.rgb, last, value);
    std::memcpy(last, value, 6);
  } else {
    std::memcpy(value, last, 6);
  }
  if (nir_) value[3] = last[3] = nir_layer_.changed ? decode_nir(c, last[3]) : last[3];
  std::memcpy(out, value, nir_ ? 8 : 6);
}

class Byte14Reader : public ItemReader {
 public:
  Byte14Reader(int version, uint32_t count) : version_(version), layers_(count), contexts_(count) {}
  void read_layer_sizes(ByteCursor& in) override {
    for (Layer& l : layers_) l.size = in.u32("layer sizes");
  }
  void load_layers(ByteCursor& in) override {
    for (Layer& l : layers_) l.load(in);
  }
  void init(const uint8_t* first, uint32_t& context) override { contexts_.begin_chunk(context, first); }
  void decode(uint8_t* out, uint32_t& context) override;
  long layer_slack() const override {
    long s = 0;
    for (const Layer& l : layers_) s += l.slack();
    return s;
  }

 private:
  int version_;
  std::vector<Layer> layers_;
  ChannelFollower<ByteContext> contexts_;
};

void Byte14Reader::decode(uint8_t* out, uint32_t& context) {
  uint8_t* last;
  ByteContext& c = contexts_.follow(context, version_, last);
  for (size_t i = 0; i < layers_.size(); ++i) {
    if (layers_[i].changed)
      last[i] = fold_u8(last[i] + int32_t(layers_[i].dec.decode_symbol(c.models[i])));
    out[i] = last[i];
  }
}

}  // namespace

std::unique_ptr<ItemReader> make_rgb14(int version, bool nir) {
  return std::make_unique<Rgb14Reader>(version, nir);
}
std::unique_ptr<ItemReader> make_byte14(int version, uint32_t count) {
  return std::make_unique<Byte14Reader>(version, count);
}

}  // namespace c3d::laz
