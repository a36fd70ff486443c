#include "cadastre/batch/plausibility.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "valuation/valuation.h"

namespace c3d {
namespace {

// Cells of the coverage: a fifth of the reach, so the reach is measured to 20 %.
constexpr double kCoverageCellM = kCoverageReachM / 5;

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}



long cell_of(double v) { return long(std::floor(v / kCoverageCellM)); }

std::uint64_t cell_key(long i, long j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

// Why a building lies outside the bounds, or "".
std::string implausible(const Building& b, double frame_z) {
  const double terrain = b.terrain_z + frame_z;
  if (!plausible_elevation(terrain))
    return "terrain at " + num(terrain) + " m lies outside " + elevation_bounds();
  if (!std::isfinite(b.ridge_height) || b.ridge_height > kMaxBuildingHeightM)
    return "ridge " + num(b.ridge_height) + " m above the terrain exceeds " + num(kMaxBuildingHeightM) + " m";
  if (b.ridge_height < kMinBuildingHeightM)
    return "ridge " + num(b.ridge_height) + " m above the terrain: lower than any building (" +
           num(kMinBuildingHeightM) + " m)";
  if (!std::isfinite(b.eave_height) || b.eave_height < kMinEaveHeightM)
    return "eave " + num(b.eave_height) + " m lies more than " + num(-kMinEaveHeightM) + " m below the terrain";
  if (b.storeys < 1 || b.storeys > kMaxStoreys)
    return num(b.storeys) + " storeys, outside 1.." + num(kMaxStoreys);
  if (!std::isfinite(b.volume) || b.volume <= 0 || b.volume > kMaxVolumeM3)
    return "volume " + num(b.volume) + " m3, outside 0.." + num(kMaxVolumeM3) + " m3";
  for (const Element& e : b.elements)
    if (!std::isfinite(e.area) || e.area < 0 || e.area > kMaxElementAreaM2)
      return std::string(to_string(e.type)) + " area " + num(e.area) + " m2, outside 0.." +
             num(kMaxElementAreaM2) + " m2";
  return {};
}

bool money_ok(double v) { return std::isfinite(v) && std::abs(v) <= kMaxMoney; }

bool valuation_ok(const ParcelValuation& v) {
  for (double x : {v.land_value, v.building_cost, v.building_value, v.njop, v.taxable, v.tax, v.sigma_njop})
    if (!money_ok(x)) return false;
  return true;
}

}  // namespace

void PointCoverage::add(const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) continue;
    cells_.insert(cell_key(cell_of(p.x()), cell_of(p.y())));
    lo_x_ = std::min(lo_x_, p.x()), hi_x_ = std::max(hi_x_, p.x());
    lo_y_ = std::min(lo_y_, p.y()), hi_y_ = std::max(hi_y_, p.y());
  }
}

bool PointCoverage::near(const MultiPolygon2& shape) const {
  double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
  for (const auto& poly : shape)
    for (const Vec2& v : poly.outer) lx = std::min(lx, v.x()), hx = std::max(hx, v.x()), ly = std::min(ly, v.y()), hy = std::max(hy, v.y());
  lx -= kCoverageReachM, ly -= kCoverageReachM, hx += kCoverageReachM, hy += kCoverageReachM;
  if (cells_.empty() || lx > hi_x_ || hx < lo_x_ || ly > hi_y_ || hy < lo_y_) return false;
  const long i0 = cell_of(std::max(lx, lo_x_)), i1 = cell_of(std::min(hx, hi_x_));
  const long j0 = cell_of(std::max(ly, lo_y_)), j1 = cell_of(std::min(hy, hi_y_));
  if (double(i1 - i0 + 1) * double(j1 - j0 + 1) > double(cells_.size())) {
    for (std::uint64_t k : cells_) {  // fewer occupied cells than cells under the box
      const long i = long(std::int32_t(k >> 32)), j = long(std::int32_t(k & 0xffffffffu));
      if (i >= i0 && i <= i1 && j >= j0 && j <= j1) return true;
    }
    return false;
  }
  for (long i = i0; i <= i1; ++i)
    for (long j = j0; j <= j1; ++j)
      if (cells_.count(cell_key(i, j))) return true;
  return false;
}

std::string extent_text(double min_x, double max_x, double min_y, double max_y) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x %.1f..%.1f, y %.1f..%.1f", min_x, max_x, min_y, max_y);
  return buf;
}

std::string PointCoverage::extent() const {
  return cells_.empty() ? "no points" : extent_text(lo_x_, hi_x_, lo_y_, hi_y_);
}

std::string elevation_bounds() { return num(kMinElevationM) + ".." + num(kMaxElevationM) + " m"; }

bool plausible_elevation(double z) { return std::isfinite(z) && z >= kMinElevationM && z <= kMaxElevationM; }

void keep_plausible_elevations(PointCloud& cloud, std::vector<std::string>& warnings) {
  size_t kept = 0;
  const bool classes = cloud.classes.size() == cloud.points.size();
  double first_bad = 0;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    if (!plausible_elevation(cloud.points[i].z())) {
      if (kept + 1 > i) first_bad = cloud.points[i].z();  // the first one only
      continue;
    }
    cloud.points[kept] = cloud.points[i];
    if (classes) cloud.classes[kept] = cloud.classes[i];
    ++kept;
  }
  const size_t dropped = cloud.points.size() - kept;
  if (dropped == 0) return;
  if (kept == 0)
    throw InputError(cloud.source, "no point's height lies within " + elevation_bounds() + " (e.g. z = " +
                                       num(first_bad) + "): check the Z scale, offset and unit");
  cloud.points.resize(kept);
  if (classes) cloud.classes.resize(kept);
  warnings.push_back(cloud.source + ": " + std::to_string(dropped) + " points with a height outside " +
                     elevation_bounds() + " left out");
}

namespace {

void report_dtm_elevations(const std::string& source, size_t bad, size_t cells, float example,
                           std::vector<std::string>& warnings) {
  if (bad == 0) return;
  if (bad == cells)
    throw InputError(source, "no cell's height lies within " + elevation_bounds() + " (e.g. " +
                                     num(example) + " m): check the vertical unit and offset");
  warnings.push_back(source + ": " + std::to_string(bad) + " cells with a height outside " +
                     elevation_bounds() + " (e.g. " + num(example) + " m); buildings on them are suspect");
}

}  // namespace

void check_dtm_elevations(const Dtm& dtm, std::vector<std::string>& warnings) {
  size_t bad = 0;
  float example = 0;
  for (float z : dtm.z)
    if (!plausible_elevation(z)) example = bad++ ? example : z;
  report_dtm_elevations(dtm.source, bad, dtm.z.size(), example, warnings);
}

void check_dtm_elevations(const DtmSource& dtm, std::vector<std::string>& warnings) {
  float example = 0;
  const size_t bad = dtm.count_cells([](float z) { return !plausible_elevation(z); }, &example);
  const Dtm& h = dtm.header();
  report_dtm_elevations(h.source, bad, size_t(h.nx) * size_t(h.ny) - dtm.nodata_cells(), example, warnings);
}

ParcelResult failed_parcel(size_t index, const std::string& id, const std::string& reason) {
  ParcelResult r;
  r.parcel_index = int(index);
  r.parcel_id = id;
  r.status = ParcelStatus::Failed;
  r.reason = reason;
  return r;
}

void check_model(ParcelResult& r, double frame_z) {
  if (r.status != ParcelStatus::Ok) return;
  for (const Building& b : r.buildings) {
    const std::string why = implausible(b, frame_z);
    if (why.empty()) continue;
    r.status = ParcelStatus::Suspect;
    r.reason = "implausible model: building " + b.id + ": " + why + (r.reason.empty() ? "" : "; " + r.reason);
    return;
  }
}

ParcelValuation value_checked(const Parcel& parcel, ParcelResult& r, const ValuationParams& params) {
  ParcelValuation v = value_parcel(parcel, r, params);
  if (valuation_ok(v)) return v;
  const std::string why = "implausible value: NJOP " + num(v.njop) + ", tax " + num(v.tax) + " " + params.currency +
                          " (finite and at most " + num(kMaxMoney) + " expected)";
  if (r.status == ParcelStatus::Ok || r.status == ParcelStatus::Empty) r.status = ParcelStatus::Suspect;
  r.reason = why + (r.reason.empty() ? "" : "; " + r.reason);
  v = value_parcel(parcel, r, params);  // land only
  if (valuation_ok(v)) return v;
  v.building_cost = v.building_value = v.njop = v.taxable = v.tax = v.sigma_njop = v.sigma_tax = kNaN;
  if (!money_ok(v.land_value)) v.land_value = kNaN;
  v.items.clear();
  v.note = "not valued: " + why;
  return v;
}

}  // namespace c3d
