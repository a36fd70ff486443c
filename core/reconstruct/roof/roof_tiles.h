#pragma once
// Regions held in tiles for the roof partition's cuts (roof_tiles.cpp);
// internal to core/reconstruct/roof/.
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "core/types.h"

namespace c3d::roof {

// An axis-aligned box; empty until something is added.
struct Box {
  Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
  bool near(const Box& o, double margin) const {
    return lo.x() <= o.hi.x() + margin && o.lo.x() <= hi.x() + margin &&
           lo.y() <= o.hi.y() + margin && o.lo.y() <= hi.y() + margin;
  }
  bool empty() const { return lo.x() > hi.x() || lo.y() > hi.y(); }
  void add(const Box& o) { lo = lo.cwiseMin(o.lo), hi = hi.cwiseMax(o.hi); }
  Box grown(double margin) const { return {lo - Vec2(margin, margin), hi + Vec2(margin, margin)}; }
  Box meet(const Box& o) const { return {lo.cwiseMax(o.lo), hi.cwiseMin(o.hi)}; }
};

Box box_of(const MultiPolygon2& mp);

// The regions cut on a fixed grid of square tiles. A label-grid region holds
// thousands of staircase vertices, and a cut changes it only within a small
// corridor: held in tiles, the cut overlays the few tiles it touches instead
// of the whole region. Pieces of one region meet on the tile lines; whole()
// unites them again.
class TiledRegions {
 public:
  TiledRegions(const std::vector<MultiPolygon2>& regions, double tile);
  // Region r over the tiles `window` touches (its edges there on tile lines).
  MultiPolygon2 within(size_t r, const Box& window) const;
  // Edits regions a and b tile by tile over the tiles `window` touches:
  // edit(piece of a, piece of b) where either has one. Set operations done
  // so need no union of the tiles and no cutting apart again.
  void edit_pair(size_t a, size_t b, const Box& window,
                 const std::function<void(MultiPolygon2&, MultiPolygon2&)>& edit);
  MultiPolygon2 whole(size_t r) const;
  const Box& box(size_t r) const { return boxes_[r]; }

 private:
  using Key = std::pair<long, long>;
  std::vector<Key> tiles_of(const Box& window) const;
  MultiPolygon2 tile_box(const Key& k) const;
  void put(size_t r, const Key& k, const MultiPolygon2& piece);
  void update_box(size_t r);

  double tile_;
  Vec2 origin_;
  std::vector<std::map<Key, MultiPolygon2>> pieces_;
  std::vector<Box> boxes_;
};

}  // namespace c3d::roof
