#include "core/reconstruct/roof/roof_tiles.h"

#include <cmath>

#include "core/geometry/polygon_ops.h"

namespace c3d::roof {

Box box_of(const MultiPolygon2& mp) {
  Box b;
  for (const auto& p : mp)
    for (const auto& v : p.outer) b.lo = b.lo.cwiseMin(v), b.hi = b.hi.cwiseMax(v);
  return b;
}

namespace {
// The pieces as one multipolygon: united where there are several.
MultiPolygon2 united(const std::vector<MultiPolygon2>& pieces) {
  if (pieces.size() == 1) return pieces[0];
  return pieces.empty() ? MultiPolygon2{} : poly::unite_all(pieces);
}
}  // namespace

TiledRegions::TiledRegions(const std::vector<MultiPolygon2>& regions, double tile)
    : tile_(tile), pieces_(regions.size()), boxes_(regions.size()) {
  Box all;
  for (size_t r = 0; r < regions.size(); ++r) all.add(boxes_[r] = box_of(regions[r]));
  origin_ = all.lo;
  for (size_t r = 0; r < regions.size(); ++r) {
    const std::vector<Key> keys = tiles_of(boxes_[r]);
    if (keys.size() == 1) put(r, keys[0], regions[r]);  // within one tile: nothing to cut
    else
      for (const Key& k : keys) put(r, k, poly::intersect(regions[r], tile_box(k)));
  }
}

std::vector<TiledRegions::Key> TiledRegions::tiles_of(const Box& window) const {
  std::vector<Key> keys;
  if (window.empty()) return keys;
  const long x0 = long(std::floor((window.lo.x() - origin_.x()) / tile_));
  const long x1 = long(std::floor((window.hi.x() - origin_.x()) / tile_));
  const long y0 = long(std::floor((window.lo.y() - origin_.y()) / tile_));
  const long y1 = long(std::floor((window.hi.y() - origin_.y()) / tile_));
  for (long y = y0; y <= y1; ++y)
    for (long x = x0; x <= x1; ++x) keys.emplace_back(x, y);
  return keys;
}

MultiPolygon2 TiledRegions::tile_box(const Key& k) const {
  const Vec2 lo = origin_ + tile_ * Vec2(double(k.first), double(k.second));
  return poly::box(lo, lo + Vec2(tile_, tile_));
}

void TiledRegions::put(size_t r, const Key& k, const MultiPolygon2& piece) {
  if (piece.empty()) pieces_[r].erase(k);
  else pieces_[r][k] = piece;
}

MultiPolygon2 TiledRegions::within(size_t r, const Box& window) const {
  std::vector<MultiPolygon2> parts;
  for (const Key& k : tiles_of(window)) {
    auto it = pieces_[r].find(k);
    if (it != pieces_[r].end()) parts.push_back(it->second);
  }
  return united(parts);
}

void TiledRegions::edit_pair(size_t a, size_t b, const Box& window,
                             const std::function<void(MultiPolygon2&, MultiPolygon2&)>& edit) {
  for (const Key& k : tiles_of(window)) {
    auto ia = pieces_[a].find(k), ib = pieces_[b].find(k);
    if (ia == pieces_[a].end() && ib == pieces_[b].end()) continue;
    MultiPolygon2 pa = ia == pieces_[a].end() ? MultiPolygon2{} : ia->second;
    MultiPolygon2 pb = ib == pieces_[b].end() ? MultiPolygon2{} : ib->second;
    edit(pa, pb);
    put(a, k, pa);
    put(b, k, pb);
  }
  update_box(a);
  update_box(b);
}

void TiledRegions::update_box(size_t r) {
  Box b;
  for (const auto& [k, piece] : pieces_[r]) b.add(box_of(piece));
  boxes_[r] = b;
}

MultiPolygon2 TiledRegions::whole(size_t r) const {
  std::vector<MultiPolygon2> parts;
  for (const auto& [k, piece] : pieces_[r]) parts.push_back(piece);
  return united(parts);
}

}  // namespace c3d::roof
