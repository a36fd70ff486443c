#pragma once
// Points per parcel. Each parcel polygon is buffered by the overhang buffer (a
// roof edge hangs over the boundary; registration error adds more) so a point
// can go to several parcels; which parcel finally owns a roof segment is decided
// by the reconstruction. GEOS does the work: an STRtree over the buffered
// parcels and prepared-geometry point locators.
#include <cstddef>
#include <memory>
#include <vector>

#include "core/config/config.h"
#include "core/types.h"

namespace c3d {

class ParcelClipper {
 public:
  using IndexLists = std::vector<std::vector<std::size_t>>;  // per parcel: point indices

  explicit ParcelClipper(const ParcelLayer& layer, const ClipParams& params = {});
  // Only the parcels `only` (layer indices) hold points; the others hold none
  // and cost nothing: a chunk's clipper, whatever the layer's size.
  ParcelClipper(const ParcelLayer& layer, const ClipParams& params, const std::vector<std::size_t>& only);
  ~ParcelClipper();
  ParcelClipper(ParcelClipper&&) noexcept;
  ParcelClipper& operator=(ParcelClipper&&) noexcept;

  std::size_t parcel_count() const;
  double buffer_m() const;

  // Streaming: feed the cloud chunk by chunk. Appends first_index + i to
  // lists[p] for every point i of pts[0, n) within the buffered parcel p
  // (boundary included); lists is resized to parcel_count(). The lists are the
  // only per-parcel state, so memory grows with the clipped points only.
  void clip(const Vec3* pts, std::size_t n, IndexLists& lists, std::size_t first_index = 0) const;
  IndexLists clip(const std::vector<Vec3>& pts) const;

  // True when (x, y) lies strictly inside the unbuffered parcel (not on its boundary).
  // clip() and inside() only read state built by the constructor, so threads
  // may clip different chunks concurrently (each into its own lists).
  bool inside(std::size_t parcel, double x, double y) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace c3d
