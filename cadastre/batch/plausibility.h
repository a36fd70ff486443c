#pragma once
// Bounds no real terrain, building or price leaves (docs/plausibility.md).
// Inputs outside them are errors naming the file; a parcel the data do not
// reach is `failed`; a model or value outside them is `suspect`: stored and
// reported with its reason, valued as land only, never `ok`.
#include <cstdint>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/io/dtm_io.h"
#include "core/types.h"
#include "core/config/config.h"
#include "valuation/valuation_types.h"

namespace c3d {

// The Earth's land surface in any orthometric or ellipsoidal datum: Dead Sea
// shore -430 m, geoid low -106 m; Everest 8,849 m, geoid high +85 m.
constexpr double kMinElevationM = -1000, kMaxElevationM = 10000;
// Height above the terrain: the tallest building is 828 m (Burj Khalifa), the
// tallest planned about 1,000 m (Jeddah Tower).
constexpr double kMaxBuildingHeightM = 1200;
// A ridge less than a metre above the terrain is no building any officer
// would value (a garden shed stands 2 m): a terrace or a ground patch in the
// building class (AHN3 03102: its ridge 0.10 m up).
constexpr double kMinBuildingHeightM = 1.0;
// A roof edge a little under the DTM occurs where a low height layer meets
// sloping ground (AHN3 03038: -0.01 m); a storey under it, the terrain or the
// cloud's heights are off.
constexpr double kMinEaveHeightM = -3;
// Burj Khalifa has 163 storeys.
constexpr int kMaxStoreys = 300;
// The largest building by volume holds 13.3 million m3 (Boeing Everett); the
// largest footprints are about 1 km2.
constexpr double kMaxVolumeM3 = 1e9, kMaxElementAreaM2 = 1e7;
// A double holds every whole currency unit only below 2^53 (9.0e15): beyond it
// a tax figure is not exact in any currency.
constexpr double kMaxMoney = 9.0e15;
// A parcel with no point of any class within this reach lies outside the
// survey (a lake gives no returns, but its banks do).
constexpr double kCoverageReachM = 50;

// "x a..b, y c..d": an extent in an error message.
std::string extent_text(double min_x, double max_x, double min_y, double max_y);

// Where the clouds have points (any class), as occupied cells.
class PointCoverage {
 public:
  void add(const std::vector<Vec3>& points);
  bool empty() const { return cells_.empty(); }
  // True when a point lies within kCoverageReachM of the shape's bounding box.
  bool near(const MultiPolygon2& shape) const;
  std::string extent() const;  // "x a..b, y c..d" of the points, for messages

 private:
  std::unordered_set<std::uint64_t> cells_;
  double lo_x_ = 1e300, lo_y_ = 1e300, hi_x_ = -1e300, hi_y_ = -1e300;
};

// A z within the elevation bounds.
bool plausible_elevation(double z);
// The text of the bounds, for messages.
std::string elevation_bounds();

// Drops the points whose z is not finite or outside the elevation bounds (with
// a warning); throws InputError naming the file when none is left.
void keep_plausible_elevations(PointCloud& cloud, std::vector<std::string>& warnings);

// Throws InputError naming the DTM when no cell lies within the elevation
// bounds; warns when some do not (parcels on them come out suspect).
void check_dtm_elevations(const Dtm& dtm, std::vector<std::string>& warnings);
// The same, a pass over the raster's blocks (nothing held), over its valid
// (not NoData) cells.
void check_dtm_elevations(const DtmSource& dtm, std::vector<std::string>& warnings);

// A parcel the batch cannot model: `failed` with the reason.
ParcelResult failed_parcel(size_t index, const std::string& id, const std::string& reason);

// An `ok` parcel whose buildings leave the bounds becomes `suspect` with the
// reason. frame_z: the local frame's origin height (local z + frame_z = world z).
void check_model(ParcelResult& result, double frame_z);

// value_parcel with bounds on money: a value not finite or beyond kMaxMoney
// makes the parcel `suspect`, valued as land only; where even the land's
// value leaves them, NJOP and tax are left out (NULL), never stored as 0.
ParcelValuation value_checked(const Parcel& parcel, ParcelResult& result, const ValuationParams& params);

}  // namespace c3d
