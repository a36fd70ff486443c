// The RGB14 and BYTE14 item encoders (layered, item version 3): the inverses
// of layered_items.cpp, following the scanner channel alike (ChannelFollower).
#include <cstring>

#include "core/io/laz/item_writer.h"
#include "core/io/laz/layered.h"

namespace c3d::laz {

namespace {

constexpr int kVersion = 3;  // the layered item version the writer writes

class Rgb14Writer : public ItemWriter {
 public:
  explicit Rgb14Writer(bool nir) : nir_(nir), contexts_(nir ? 8 : 6) {}
  void init(const uint8_t* first, uint32_t& context) override {
    layers_[kRgb].changed = layers_[kNir].changed = false;
    contexts_.begin_chunk(context, first);
  }
  void encode(const uint8_t* item, uint32_t& context) override {
    uint16_t* last;
    RgbContext& c = contexts_.follow(context, kVersion, last);
    uint16_t rgb[3];
    std::memcpy(rgb, item, 6);
    layers_[kRgb].changed |= std::memcmp(rgb, last, 6) != 0;
    encode_rgb(layers_[kRgb].enc, c.rgb, last, rgb);
    std::memcpy(last, rgb, 6);
    if (nir_) {
      uint16_t nir;
      std::memcpy(&nir, item + 6, 2);
      encode_nir(c, last[3], nir);
      last[3] = nir;
    }
  }
  void finish_layers() override {
    layers_[kRgb].finish();
    layers_[kNir].finish();
  }
  // The NIR layer only where the item has NIR.
  void write_layer_sizes(std::vector<uint8_t>& out) const override { put_layer_sizes(layers_, nir_ ? 2 : 1, out); }
  void write_layers(std::vector<uint8_t>& out) const override { put_layers(layers_, nir_ ? 2 : 1, out); }

 private:
  void encode_nir(RgbContext& c, uint16_t last, uint16_t nir) {
    Encoder& enc = layers_[kNir].enc;
    const uint32_t sym = uint32_t(byte_of(last, true) != byte_of(nir, true)) |
                         (uint32_t(byte_of(last, false) != byte_of(nir, false)) << 1);
    enc.encode_symbol(c.nir_used, sym);
    if (sym & 1) enc.encode_symbol(c.nir_diff[0], fold_u8(byte_of(nir, true) - byte_of(last, true)));
    if (sym & 2) enc.encode_symbol(c.nir_diff[1], fold_u8(byte_of(nir, false) - byte_of(last, false)));
    layers_[kNir].changed |= sym != 0;
  }
  bool nir_;
  enum { kRgb, kNir };
  LayerOut layers_[2];
  ChannelFollower<RgbContext> contexts_;
};

class Byte14Writer : public ItemWriter {
 public:
  explicit Byte14Writer(uint32_t count) : layers_(count), contexts_(count) {}
  void init(const uint8_t* first, uint32_t& context) override {
    for (LayerOut& l : layers_) l.changed = false;
    contexts_.begin_chunk(context, first);
  }
  void encode(const uint8_t* item, uint32_t& context) override {
    uint8_t* last;
    ByteContext& c = contexts_.follow(context, kVersion, last);
    for (size_t i = 0; i < layers_.size(); ++i) {
      layers_[i].enc.encode_symbol(c.models[i], fold_u8(int32_t(item[i]) - last[i]));
      layers_[i].changed |= item[i] != last[i];
      last[i] = item[i];
    }
  }
  void finish_layers() override {
    for (LayerOut& l : layers_) l.finish();
  }
  void write_layer_sizes(std::vector<uint8_t>& out) const override {
    put_layer_sizes(layers_.data(), layers_.size(), out);
  }
  void write_layers(std::vector<uint8_t>& out) const override { put_layers(layers_.data(), layers_.size(), out); }

 private:
  std::vector<LayerOut> layers_;
  ChannelFollower<ByteContext> contexts_;
};

}  // namespace

std::unique_ptr<ItemWriter> make_rgb14_writer(bool nir) { return std::make_unique<Rgb14Writer>(nir); }
std::unique_ptr<ItemWriter> make_byte14_writer(uint32_t count) { return std::make_unique<Byte14Writer>(count); }

}  // namespace c3d::laz
