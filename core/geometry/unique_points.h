#pragma once
// Stacked points (a writer that repeats records, overlapping strips merged
// twice, coordinates rounded onto a grid) as one: a neighbourhood of k points
// that are four copies of four places fixes no normal, and a nearest
// neighbour at 0 m is no point spacing.
#include <vector>

#include "core/types.h"

namespace c3d {

// Points closer than this are one place scanned (or written) twice: far below
// any airborne scanner's noise (2-3 cm), far above float rounding.
constexpr double kSamePlaceM = 0.005;

struct UniquePoints {
  std::vector<int> unique;  // the points kept, one per place, in input order
  std::vector<int> of;      // per input point: the index into `unique` of its place
};

// The points of `points` closer than `tol` to an earlier kept point fold into
// it (first come, first kept: the same input gives the same result).
UniquePoints unique_points(const std::vector<Vec3>& points, double tol);

// one_per_place taken a point at a time: each point given is kept unless an
// earlier kept point lies within kSamePlaceM. Only the kept points are held
// (24 bytes each, in blocks: no doubling copy) and a table of their indices
// (4 bytes a slot, at most half full), so a region's points can be folded as
// they are read, never held unfolded.
class PlaceFolder {
 public:
  void add(const Vec3& p);
  size_t size() const { return size_; }
  // The kept points, in the order given; the folder is empty afterwards.
  std::vector<Vec3> take();

 private:
  const Vec3& at(size_t i) const { return blocks_[i >> kBlockBits][i & (kBlock - 1)]; }
  bool near_kept(const Vec3& p) const;
  void insert(int i);
  void grow();

  static constexpr unsigned kBlockBits = 16;  // 1.5 MB blocks: small next to a region
  static constexpr size_t kBlock = size_t(1) << kBlockBits;
  std::vector<std::vector<Vec3>> blocks_;
  std::vector<int> slots_;  // kept point indices by their cell's hash, -1: empty
  size_t size_ = 0;
};

// The kept points of unique_points(points, kSamePlaceM): one per place, in
// input order. The batch measures and models these, and `evaluate` measures
// these, so that both count the same points.
std::vector<Vec3> one_per_place(const std::vector<Vec3>& points);

}  // namespace c3d
