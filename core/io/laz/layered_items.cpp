// The RGB14, RGBNIR14 and BYTE14 item decoders (layered, item versions 3 and
// 4). They follow the scanner channel POINT14 decodes. Version 3 has a quirk
// the encoder shares, so decoding must keep it: on switching to a channel
// already used in the chunk, the predictor keeps the previous channel's last
// value (version 4 takes the new channel's).
#include <vector>

#include "core/io/laz/layered.h"
#include "core/io/laz/rgb.h"

namespace c3d::laz {

namespace {

struct RgbContext {
  bool unused = true;
  RgbModels rgb;
  SymbolModel nir_used{4};
  SymbolModel nir_diff[2] = {SymbolModel(256), SymbolModel(256)};
  uint16_t last[4] = {};
};

class Rgb14Reader : public ItemReader {
 public:
  Rgb14Reader(int version, bool nir) : version_(version), nir_(nir) {}
  void read_layer_sizes(ByteCursor& in) override {
    rgb_.size = in.u32("layer sizes");
    if (nir_) nir_layer_.size = in.u32("layer sizes");
  }
  void load_layers(ByteCursor& in) override {
    rgb_.load(in);
    if (nir_) nir_layer_.load(in);
  }
  void init(const uint8_t* first, uint32_t& context) override {
    for (RgbContext& c : contexts_) c.unused = true;
    current_ = context;
    start(contexts_[current_], first);
  }
  void decode(uint8_t* out, uint32_t& context) override;

 private:
  void start(RgbContext& c, const void* from) {
    c.rgb.reset(), c.nir_used.reset(), c.nir_diff[0].reset(), c.nir_diff[1].reset();
    std::memcpy(c.last, from, nir_ ? 8 : 6);
    c.unused = false;
  }
  uint16_t decode_nir(RgbContext& c, uint16_t last);

  int version_;
  bool nir_;
  Layer rgb_, nir_layer_;
  RgbContext contexts_[4];
  uint32_t current_ = 0;
};

uint16_t Rgb14Reader::decode_nir(RgbContext& c, uint16_t last) {
  Decoder& dec = nir_layer_.dec;
  const uint32_t sym = dec.decode_symbol(c.nir_used);
  uint16_t low = last & 0xFF, high = last >> 8;
  if (sym & 1) low = fold_u8(int32_t(dec.decode_symbol(c.nir_diff[0])) + low);
  if (sym & 2) high = fold_u8(int32_t(dec.decode_symbol(c.nir_diff[1])) + high);
  return uint16_t(low | (high << 8));
}

void Rgb14Reader::decode(uint8_t* out, uint32_t& context) {
  uint16_t* last = contexts_[current_].last;
  if (current_ != context) {
    current_ = context;
    RgbContext& now = contexts_[current_];
    if (now.unused) {
      start(now, last);
      last = now.last;
    } else if (version_ >= 4) {
      last = now.last;
    }
  }
  RgbContext& c = contexts_[current_];
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

struct ByteContext {
  bool unused = true;
  std::vector<SymbolModel> models;
  std::vector<uint8_t> last;
};

class Byte14Reader : public ItemReader {
 public:
  Byte14Reader(int version, uint32_t count) : version_(version), layers_(count) {}
  void read_layer_sizes(ByteCursor& in) override {
    for (Layer& l : layers_) l.size = in.u32("layer sizes");
  }
  void load_layers(ByteCursor& in) override {
    for (Layer& l : layers_) l.load(in);
  }
  void init(const uint8_t* first, uint32_t& context) override {
    for (ByteContext& c : contexts_) c.unused = true;
    current_ = context;
    start(contexts_[current_], first);
  }
  void decode(uint8_t* out, uint32_t& context) override;

 private:
  void start(ByteContext& c, const uint8_t* from) {
    if (c.models.empty()) c.models.assign(layers_.size(), SymbolModel(256));
    for (SymbolModel& m : c.models) m.reset();
    c.last.assign(from, from + layers_.size());
    c.unused = false;
  }

  int version_;
  std::vector<Layer> layers_;
  ByteContext contexts_[4];
  uint32_t current_ = 0;
};

void Byte14Reader::decode(uint8_t* out, uint32_t& context) {
  uint8_t* last = contexts_[current_].last.data();
  if (current_ != context) {
    current_ = context;
    ByteContext& now = contexts_[current_];
    if (now.unused) {
      const std::vector<uint8_t> from(last, last + layers_.size());
      start(now, from.data());
      last = now.last.data();
    } else if (version_ >= 4) {
      last = now.last.data();
    }
  }
  ByteContext& c = contexts_[current_];
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
