#pragma once
// The report's 3D view (docs/report.md, "3D view"): what its pages hold and
// the data files its script (web/report_viewer.js) draws.
//   report/lib/c3d-viewer.js    three.js and viewer.js, one classic script
//   report/3d/index.js          the summary's cells, value classes and colours
//   report/3d/<cell>-far.js     a 250 m cell's parcels on the ground, coloured
//                               by value per m2, and its buildings' prisms
//   report/3d/<cell>.js         the cell's buildings by element, for a near view
// A parcel page carries its own scene inline. Coordinates are metres in the
// batch's local frame (a parcel page's: from the parcel's centre), to the mm.
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/types.h"
#include "valuation/valuation_types.h"

namespace c3d {

// The bundled viewer script, embedded at build time (report_viewer.cpp).
std::string_view viewer_script();

namespace report_detail {

struct ValueClasses;  // report_parts.h

inline constexpr const char* kViewerScript = "report/lib/c3d-viewer.js";  // relative to OUT
inline constexpr const char* kSummaryData = "report/3d/";
inline constexpr double kCellM = 250;  // side of the summary's cells (m)

// The parcel page's 3D view of its buildings by element, with picking;
// to_report: the page's path back to OUT/report/ ("../").
std::string parcel_view(const Parcel& p, const ParcelResult& r, const ParcelValuation* v,
                        const LocalFrame& frame, const std::string& to_report);
// The parcel's buildings' mesh levels (batch --mesh) that parcel_view offers,
// as the viewer's data files OUT/report/3d/mesh/<level file>.js, read from
// each level's PLY under files_root; levels whose PLY is not there are left
// out (the view then says so).
void write_mesh_levels(const ParcelResult& r, const Parcel& p, const LocalFrame& frame,
                       const std::string& files_root, const std::string& out_dir);
// The summary page's view, loading report/3d/ on demand.
std::string summary_view();

// The summary's cells, spooled to disk as the parcels come and written out
// at the end, when the value classes are known (memory: one parcel).
class SummaryCells {
 public:
  explicit SummaryCells(const std::string& out_dir);  // removes an earlier report's report/3d/
  void add(const Parcel& p, const ParcelResult& r, const ParcelValuation* v, const LocalFrame& frame);
  // Writes report/3d/ and the viewer script; classes as the overview map's.
  void finish(const ValueClasses& classes, const std::string& currency);

 private:
  // A parcel's colour in the viewer's list (index.js): its value class, or
  // failed, suspect, not valued after the classes; `ground`: where parcels
  // without a building lie, the batch's median ground.
  struct Colouring {
    const ValueClasses* classes;
    double ground;
    size_t of(const std::string& status, double value) const;
  };
  void write_cell(std::pair<long, long> cell, Eigen::AlignedBox3d& box, const Colouring& colouring) const;

  std::string out_, dir_;                                      // OUT, OUT/report/3d
  std::map<std::pair<long, long>, Eigen::AlignedBox3d> boxes_;  // each cell's buildings and parcels
  std::vector<double> ground_z_;  // parcels' ground heights, for parcels without a building
};

}  // namespace report_detail
}  // namespace c3d
