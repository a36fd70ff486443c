#pragma once
// Hard limits every reader enforces before it trusts a file, so that a damaged
// or hostile input is an InputError naming the file, never a crash or a
// runaway allocation (docs/testing.md, "Reader limits").
#include <cmath>
#include <cstddef>
#include <string>

namespace c3d {

// What a reader can hold at all: the k-d trees work in float, where squared
// distances between coordinates within 1e17 stay finite ((2e17)^2 * 3 <
// 3.4e38); a point at z = 3.5e38 tripped PCL's k-d tree assertion. What is
// representable but off the Earth (z = 1e15) is plausibility's to judge:
// such heights are left out with a count (cadastre/batch/plausibility.h).
constexpr double kMaxAbsCoordinate = 1e17;

inline bool coordinate_ok(double v) { return std::isfinite(v) && std::fabs(v) <= kMaxAbsCoordinate; }

// "" when x, y, z are usable, else why not: "NaN/inf coordinate at <where> (z = inf)"
// or "coordinate beyond +-1e17 at <where> (z = 3.5e+38)".
std::string coordinate_problem(double x, double y, double z, const std::string& where);

// The largest DTM the reader loads: 2^28 cells (1 GiB of heights, e.g. 16 x 16
// km at 1 m); filling NoData needs about kDtmBytesPerCell per cell at its peak.
constexpr size_t kMaxDtmCells = size_t(1) << 28;
constexpr size_t kDtmBytesPerCell = 16;

// Throws InputError unless path names a regular file: "file not found", "not
// a regular file" (a directory named x.las reported a size of 2^63 and became
// std::bad_alloc), "cannot read (File name too long)".
void check_regular_file(const std::string& path);

// Physical memory of this machine in bytes (0 when unknown).
size_t physical_memory_bytes();

}  // namespace c3d
