#pragma once
// Envelope sub-stage "roof faces": the roof pieces lifted onto their planes,
// with one height per shared vertex where the planes agree (welded), and the
// outer ceilings (soffits) under the hanging pieces.
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "core/reconstruct/envelope/roof_pieces.h"
#include "core/reconstruct/roof/roof.h"
#include "core/types.h"

namespace c3d::envelope {

// z of every (piece, vertex): its plane, welded with the other pieces' heights
// at the same vertex when they agree within 2 mm (numerically the same line).
class Heights {
 public:
  void add(const Vec2& v, double z) { at_[key(v)].push_back(z); }
  // The height at v of a piece whose plane gives z there.
  double get(const Vec2& v, double z) const;
  // Every piece at v takes the mean of their heights, if they lie within 1 cm.
  void meet_at_mean(const Vec2& v);

 private:
  static std::pair<double, double> key(const Vec2& v) { return {v.x(), v.y()}; }
  std::map<std::pair<double, double>, std::vector<double>> at_;
  std::set<std::pair<double, double>> at_mean_;
};

Ring3 lift(const Ring2& r, const Plane& plane, const Heights& h);

// A roof piece on its plane, holes included.
Face lift(const Piece& p, const Plane& plane, const Heights& h);

// The ring at height z; `downward`: reversed, to face down.
Ring3 flat(const Ring2& r, double z, bool downward);

// Where three or more step walls would stand on one vertical edge (planes
// missing one junction by more than the weld), the pieces there meet at the
// mean of their heights.
void meet_at_step_fans(Heights& heights, const std::vector<Piece>& pieces, const std::vector<RoofRegion>& roof);

// The roof as faces: per region all its pieces, the pieces inside the walls
// (the solid's top) with their regions, and under each hanging piece its
// outer ceiling, a horizontal soffit at the lowest height of that piece.
struct RoofFaces {
  std::vector<std::vector<Face>> by_region;  // indexed like the roof regions
  std::vector<Face> inside;
  std::vector<int> inside_region;            // the region of each inside face
  std::vector<Face> soffits;
};
RoofFaces lift_roof(const std::vector<Piece>& pieces, const std::vector<RoofRegion>& roof);

}  // namespace c3d::envelope
