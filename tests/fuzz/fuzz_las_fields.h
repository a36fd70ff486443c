#pragma once
// The `las-fields` target: LAS and LAZ files whose bytes stay well formed but
// whose fields claim something else than the data holds (point counts, the
// bounds, the LASzip chunk size, the chunk table's place, offsets, record
// length), as a broken writer or a damaged header leaves them. A bit flip
// tests that a reader survives; this tests that it does not silently read
// other points: a mutant is refused with InputError or reads as its seed.
#include <cstdint>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_mutate.h"

namespace c3d::fuzz {

// LAZ of three chunks (point-wise, format 1; layered, format 6), written
// here; uncompressed LAS 1.2 and 1.4; simple.laz and the COPC file (variable
// chunks) of ../shared/data/laz where present.
std::vector<SeedInput> las_field_seeds(const std::string& work);

// A header, VLR or chunk-table count set near its true value (off by one, by
// a thousand, doubled, halved, zero), the bounds changed (a side shrunk, the
// box moved, all zero), or both. The same (bytes, seed) gives the same mutant.
std::string mutate_las_fields(const std::string& bytes, uint64_t seed);

// The mutant read whole and streamed in blocks: each must throw InputError
// or give exactly the seed's points and classes. Throws std::runtime_error
// naming the first difference (a silent change: a finding), InputError when
// both ways refused it.
void expect_refused_or_same(const std::string& path, const SeedInput& seed);

}  // namespace c3d::fuzz
