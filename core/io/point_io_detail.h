#pragma once
// Pieces shared by the point-cloud readers and the LAS writer (internal to
// core/io/point_io.cpp, las_io.cpp, ply_reader.cpp and pcd_reader.cpp).
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/io/point_io.h"
#include "core/types.h"

namespace c3d::point_io_detail {

std::string lower(std::string s);
// The whole file in memory: one fread is the fastest way through the page cache.
std::vector<char> slurp(const std::string& path);

template <typename T>
T get(const char* p) {  // unaligned little-endian load (x86 and ARM are little-endian)
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

template <typename T>
void put(std::string& out, size_t pos, T v) {
  std::memcpy(&out[pos], &v, sizeof(T));
}

// Throws InputError naming the point when a coordinate is NaN/inf or beyond
// kMaxAbsCoordinate (core/io/read_limits.h).
void check_coordinates(const std::string& path, double x, double y, double z, size_t index);
// A class value read as a number: a whole number 0-255, else InputError naming the point.
uint8_t class_code(const std::string& path, double c, size_t index);
// A column or property that holds the point class.
bool is_class_name(const std::string& name);

PointCloud read_las(const std::string& path);
// LAS and LAZ a block (a LASzip chunk) at a time: for_each_point_block.
void stream_las(const std::string& path, size_t block_points, const std::function<void(const PointCloud&)>& block);
// The header's bounds; nullopt when they are not usable (NaN, min over max).
std::optional<CloudExtent> las_header_extent(const std::string& path);
PointCloud read_ply(const std::string& path);
PointCloud read_pcd(const std::string& path);

}  // namespace c3d::point_io_detail
