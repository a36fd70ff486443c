#pragma once
// Point-to-model deviation as the plane-intersection paper measures it: every
// roof-class point against the roof surfaces of its building model (3D distance
// to the nearest surface, and vertical distance), wall-class points against the
// walls. A CGAL AABB tree over the triangulated faces answers the queries (CGAL
// stays in evaluate.cpp).
#include <memory>
#include <vector>

#include "core/types.h"

namespace c3d {

struct SurfaceHit {
  double distance = kNaN;  // unsigned, m; NaN: no face (vertical: none above/below)
  int owner = -1;          // owner tag of the face hit (see FaceIndex)
  Vec3 point = Vec3::Constant(kNaN);  // closest point on the surface
};

// Nearest-surface queries over a set of planar faces. Builds in a local origin
// (the faces' bounding-box minimum) so world coordinates keep their precision.
class FaceIndex {
 public:
  // owner[i] tags faces[i] (e.g. the building index); empty: every face is 0.
  explicit FaceIndex(const std::vector<Face>& faces, const std::vector<int>& owner = {});
  ~FaceIndex();
  FaceIndex(FaceIndex&&) noexcept;
  FaceIndex& operator=(FaceIndex&&) noexcept;

  bool empty() const;
  // Closest point on any face (3D Euclidean distance).
  SurfaceHit nearest(const Vec3& p) const;
  // Along the vertical through p: the face crossing it closest in z;
  // distance = |p.z - z_surface|. Vertical faces never count.
  SurfaceHit vertical(const Vec3& p) const;
  // Both for many points, on all hardware threads.
  std::vector<SurfaceHit> nearest(const std::vector<Vec3>& pts) const;
  std::vector<SurfaceHit> vertical(const std::vector<Vec3>& pts) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Statistics of |d| over the finite values: n, max, mean, std (population, so
// that rmse^2 = mean^2 + std^2 and pooling is exact), rmse.
Deviation deviation(const std::vector<double>& distances);
// Exact statistics of the union of the parts from their n, max, mean, std.
Deviation pool(const std::vector<Deviation>& parts);

// The roof deviation split by what the model holds on the vertical through
// each point: a roof within `near` above or below it (on the model), a roof
// further off (another roof level, clutter standing on a roof, a misfit), or
// none (a point the model leaves out: vegetation, a neighbour's eave, a roof
// not modelled). `distance` (3D) and `vertical` run over the same points;
// vertical is NaN where no roof lies above or below.
struct RoofCover {
  Deviation on_model, off_model, uncovered;
  std::vector<Deviation> parts() const { return {on_model, off_model, uncovered}; }
};
constexpr double kOnModelM = 0.3;  // a roof this near above or below: the point is on the model
RoofCover split_by_cover(const std::vector<double>& distance, const std::vector<double>& vertical,
                         double near = kOnModelM);
// The part of RoofCover one point falls in: 0 on_model, 1 off_model, 2 uncovered.
int roof_cover_part(double vertical, double near = kOnModelM);

// The wall deviation split by where each wall point stands: within `near` of
// a wall of the parcel's model; under (or over) the parcel's own roof
// elsewhere (an inner or courtyard wall, a wall the model places off); under
// another parcel's roof (a neighbour's facade within the ruler's reach); under
// no roof at all (a fence, a garden wall, a building nobody models). `own_roof`
// and `other_roof` are the vertical distances to the nearest roof of this
// parcel's model and of any other parcel's, NaN where none lies above or below.
struct WallCover {
  Deviation on_wall, under_own_roof, under_other_roof, under_no_roof;
  std::vector<Deviation> parts() const { return {on_wall, under_own_roof, under_other_roof, under_no_roof}; }
};
WallCover split_wall_cover(const std::vector<double>& distance, const std::vector<double>& own_roof,
                           const std::vector<double>& other_roof, double near = kOnModelM);
// The part of WallCover one point falls in: 0 on_wall, 1 under_own_roof,
// 2 under_other_roof, 3 under_no_roof.
int wall_cover_part(double distance, double own_roof, double other_roof, double near = kOnModelM);

// Deviation of the points from the faces: 3D nearest distance, or the vertical
// distance (points with no face above or below them are left out of n).
Deviation deviation_to_faces(const std::vector<Vec3>& points, const std::vector<Face>& faces,
                             bool vertical = false);

// Wall points this far outside a parcel count for its walls (the ruler's reach).
constexpr double kWallPointReachM = 2.0;

// Faces of the given element types of one building.
std::vector<Face> faces_of(const Building& b, const std::vector<ElementType>& types);

// Fills roof_deviation (3D distance of the roof points to the Roof faces) and
// wall_deviation (wall points to the Wall and PartyWall faces) of each building;
// each point counts for the building whose surface is nearest. Pass the points
// of one parcel (roof points inside it, every one of them, including those
// segmentation discarded; wall points within kWallPointReachM of it),
// in the buildings' coordinates. Buildings with no surface of a kind get n = 0.
void evaluate_buildings(std::vector<Building>& buildings, const std::vector<Vec3>& roof_points,
                        const std::vector<Vec3>& wall_points);

}  // namespace c3d
