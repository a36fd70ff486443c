#pragma once
// The LAZ writer: LAS point records compressed as LASzip does (the public
// LAZ specification), the inverse of laz_reader.h. Point formats 0-3 use the
// point-wise chunked compressor (items POINT10, GPSTIME11, RGB12 and BYTE,
// version 2); formats 6-8 the layered one (POINT14, RGB14, RGBNIR14 and
// BYTE14, version 3). Chunks of a fixed number of points, then the chunk
// table. Throws laz::FormatError on what it cannot write.
#include <cstdint>
#include <vector>

#include "core/io/laz/laz_reader.h"

namespace c3d::laz {

// LASzip's default: a chunk restarts the models, so a reader can seek to it.
constexpr uint32_t kDefaultChunkSize = 50000;

// The items of a LAS point format (0-3, 6-8) and its extra bytes.
LaszipVlr laszip_vlr_for(int point_format, uint32_t record_length, uint32_t chunk_size = kDefaultChunkSize);
// The VLR's payload (without the 54-byte VLR header).
std::vector<uint8_t> laszip_vlr_payload(const LaszipVlr& vlr);

// The compressed point data: the chunk table offset (absolute, so the data's
// own offset in the file is needed), the chunks, the chunk table.
std::vector<uint8_t> encode_points(const uint8_t* records, uint64_t count, uint32_t record_length,
                                   const LaszipVlr& vlr, uint64_t data_offset);

// A whole uncompressed LAS file turned into its LAZ: the LASzip VLR added
// after the others, the compressed bit set on the point format, the points
// compressed, EVLRs moved behind them.
std::vector<uint8_t> compress_las(const std::vector<uint8_t>& las, uint32_t chunk_size = kDefaultChunkSize);

}  // namespace c3d::laz
