#pragma once
// Shard K of N of a batch (docs/scale.md, "Sharding and Slurm"): the parcels
// at positions part_range(n, K, N) of the Hilbert order of the WHOLE layer's
// bounding-box centres, so every shard is a compact area and the N shards
// cover the layer once. A shard run loads the whole layer (neighbours and
// roof ownership see everything) and, with --dtm, only the tiles within reach
// of its parcels; it models and stores only its own parcels.
#include <cstddef>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

struct Shard {
  int k = 0, n = 0;  // 1 <= k <= n; n == 0: no sharding (every parcel)
  bool active() const { return n > 0; }
};

// "K/N" -> Shard; throws InputError("--shard", ...) unless 1 <= K <= N.
Shard parse_shard(const std::string& text);
// Why text is no K/N for parse_shard ("" when it is).
std::string shard_problem(const std::string& text);
// "K/N", or "" when not sharded.
std::string to_string(const Shard& s);

// Layer positions of the shard's parcels, ascending (all when !s.active()).
std::vector<size_t> shard_parcels(const std::vector<Parcel>& parcels, const Shard& s);

}  // namespace c3d
