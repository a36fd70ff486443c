#pragma once
// A curved building's exact shape (ExactShape, core/types.h): its volume,
// and the JSON (world coordinates) the store keeps it as. Its OpenCASCADE
// solid: exact_solid.h.
#include <string>

#include "core/types.h"

namespace c3d {

// The exact solid's volume, m3; NaN where it cannot be made.
double exact_volume(const ExactShape& shape);

// As JSON, each part's origin moved by `offset` (local to world); "" for no
// parts. The inverse takes `offset` off again; std::invalid_argument saying
// what is wrong with the text.
std::string exact_shape_json(const ExactShape& shape, const Vec3& offset);
ExactShape exact_shape_from_json(const std::string& text, const Vec3& offset);

}  // namespace c3d
