#pragma once
// The true extent of a LAS/LAZ tile. A header's bounds decide which tiles a
// region reads, and a writer may leave them a little too small: the points
// beyond them were then never read. Each tile is decoded once for its true
// box, recorded in an index keyed by the file's SHA-256, so a later run on the
// same content reads the box back instead of decoding again.
#include <string>

#include "core/io/point_io.h"

namespace c3d {

// Where the index lives, from $XDG_CACHE_HOME and $HOME as the caller read
// them (either may be null): XDG_CACHE_HOME/cadastre3d/tile-extents.sqlite,
// or HOME/.cache/...; "" when neither is usable.
std::string tile_index_path(const char* xdg_cache_home, const char* home);

class TileExtentIndex {
 public:
  // "" keeps no index: every tile is decoded each run.
  explicit TileExtentIndex(std::string db_path);
  // The extent of the file's points as decoded (count, box; CRS from `header`),
  // from the index or one pass over the points. An index that cannot be read
  // or written is passed by: the points are decoded, never the run stopped.
  CloudExtent decoded(const std::string& path, const std::string& sha256, const CloudExtent& header);

 private:
  std::string db_path_;
};

// Where the decoded box reaches beyond the header's bounds (more than 1 mm):
// a warning naming how far, "" when the header holds the points.
std::string header_short_note(const CloudExtent& header, const CloudExtent& decoded);

}  // namespace c3d
