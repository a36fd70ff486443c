#pragma once
// The item encoders of the LAZ writer, the inverses of the item decoders
// (item_reader.h): a chunk starts with the raw record that init() sees; each
// later record is encode()d. Layered items (point formats 6-10) write each
// attribute into a layer of its own, flushed at the chunk's end.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/io/laz/arithmetic_encoder.h"

namespace c3d::laz {

class ItemWriter {
 public:
  virtual ~ItemWriter() = default;
  virtual void init(const uint8_t* first, uint32_t& context) = 0;
  virtual void encode(const uint8_t* item, uint32_t& context) = 0;
  // Layered items only: flush the layers; their sizes, then their bytes.
  virtual void finish_layers() {}
  virtual void write_layer_sizes(std::vector<uint8_t>&) const {}
  virtual void write_layers(std::vector<uint8_t>&) const {}
};

// Point formats 0-5, compressor version 2: all items share the chunk's encoder.
std::unique_ptr<ItemWriter> make_point10_writer(Encoder& enc);
std::unique_ptr<ItemWriter> make_gpstime11_writer(Encoder& enc);
std::unique_ptr<ItemWriter> make_rgb12_writer(Encoder& enc);
std::unique_ptr<ItemWriter> make_byte_writer(Encoder& enc, uint32_t count);

// Point formats 6-8, layered (item version 3; nir: RGBNIR14).
std::unique_ptr<ItemWriter> make_point14_writer();
std::unique_ptr<ItemWriter> make_rgb14_writer(bool nir);
std::unique_ptr<ItemWriter> make_byte14_writer(uint32_t count);

// One layer of a layered chunk: its encoder, and whether any value changed
// (an unchanged layer is written empty and the decoder keeps the value).
struct LayerOut {
  Encoder enc;
  bool changed = false;
  std::vector<uint8_t> bytes;
  void finish(bool always = false) {
    bytes = enc.finish();
    if (!changed && !always) bytes.clear();
  }
};

void put_u32(std::vector<uint8_t>& out, uint32_t v);

// A layered chunk's tail: the byte counts of `n` layers, then their bytes.
inline void put_layer_sizes(const LayerOut* layers, size_t n, std::vector<uint8_t>& out) {
  for (size_t i = 0; i < n; ++i) put_u32(out, uint32_t(layers[i].bytes.size()));
}
inline void put_layers(const LayerOut* layers, size_t n, std::vector<uint8_t>& out) {
  for (size_t i = 0; i < n; ++i) out.insert(out.end(), layers[i].bytes.begin(), layers[i].bytes.end());
}

}  // namespace c3d::laz
