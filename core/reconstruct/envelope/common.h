#pragma once
// What the envelope's sub-stages share: the weld tolerance, the outward
// normal of a counter-clockwise ring's edge and exact edge keys.
#include <utility>

#include "core/types.h"

namespace c3d::envelope {

// Vertices closer than this are one vertex (validators snap at a millimetre);
// the plan rings, the shell and the wall profiles all weld at it.
constexpr double kWeldTol = 1e-3;  // m

inline Vec2 outward(const Vec2& d) { return Vec2(d.y(), -d.x()); }  // for counter-clockwise rings

// An edge in plan by its exact end coordinates: pieces of one planar
// subdivision share edges exactly, so plain keys match across pieces.
using EdgeKey = std::pair<std::pair<double, double>, std::pair<double, double>>;

inline EdgeKey directed(const Vec2& a, const Vec2& b) { return {{a.x(), a.y()}, {b.x(), b.y()}}; }

inline EdgeKey undirected(const Vec2& a, const Vec2& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()) ? directed(a, b) : directed(b, a);
}

}  // namespace c3d::envelope
