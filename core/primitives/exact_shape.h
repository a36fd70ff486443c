#pragma once
// A curved building's exact shape (ExactShape, core/types.h) as the store
// keeps it: JSON in world coordinates.
#include <string>

#include "core/types.h"

namespace c3d {

// As JSON, each part's origin moved by `offset` (local to world); "" for no
// parts. The inverse takes `offset` off again; std::invalid_argument saying
// what is wrong with the text.
std::string exact_shape_json(const ExactShape& shape, const Vec3& offset);
ExactShape exact_shape_from_json(const std::string& text, const Vec3& offset);

}  // namespace c3d
