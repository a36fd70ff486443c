#pragma once
// Internal helpers shared by the writers (not part of the public API).
#include <array>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d::exp {

// Triangles of a planar face (holes respected), oriented like the face.
// points = ring vertices, then hole vertices, then any vertices the
// triangulation had to add (self-intersecting rings only).
struct Triangles {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> tris;
};
Triangles triangulate(const Face& face);

// Hole rings oriented opposite to the outer ring, as GML and CityJSON require.
Ring3 hole_oriented(const Face& face, size_t k);

// Index of the element face a solid face reuses (same vertices, same cyclic order,
// within 1 mm): {element, face}, or {-1, -1}.
std::array<int, 2> matching_element_face(const Building& b, const Face& solid_face);
// Element type of a solid face: of the element face it reuses or lies on, else by normal.
ElementType solid_face_type(const Building& b, const Face& solid_face);

// Roof level (BuildingPart) of every element; all zeros when the building has one level.
std::vector<int> element_levels(const Building& b, int* level_count);

// The parcel of a result (by index, else by id), or nullptr.
const Parcel* parcel_of(const BatchModel& m, const ParcelResult& r);

std::string fixed(double v, int decimals);  // "%.*f" without "-0.000"
std::string xml_escape(const std::string& s);
// Percent-encoding of everything but RFC 3986 unreserved characters (URI path safe).
std::string uri_escape(const std::string& s);
const char* citygml_surface(ElementType t);  // "RoofSurface", ...

}  // namespace c3d::exp
