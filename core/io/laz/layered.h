#pragma once
// LAZ item decoders of point formats 6-10 (layered compressor, item versions
// 3 and 4): each attribute of a chunk is its own arithmetic stream ("layer"),
// and up to four model sets follow the scanner channel.
#include <memory>

#include "core/io/laz/arithmetic_decoder.h"
#include "core/io/laz/item_reader.h"

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
};

std::unique_ptr<ItemReader> make_point14(int version);
std::unique_ptr<ItemReader> make_rgb14(int version, bool nir);
std::unique_ptr<ItemReader> make_byte14(int version, uint32_t count);

}  // namespace c3d::laz
