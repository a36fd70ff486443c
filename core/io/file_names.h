#pragma once
// File names made from identifiers in the data (parcel and building ids): one
// rule for every per-parcel or per-building file (previews, OBJ, STEP), so an
// id can neither reach outside the output folder nor share a file with another.
#include <string>

namespace c3d {

// The id itself when it is 1-80 characters of [A-Za-z0-9._-] and starts with
// neither '.' (hidden, "..") nor '-' (read as an option by tools); otherwise its safe characters (others become '_', at most
// 60), '~' and 16 hex digits of the id's SHA-256. A kept id has no '~', so a
// kept name never equals a changed one, and two changed ids share a name only
// if their SHA-256 share 64 bits.
std::string file_stem_for_id(const std::string& id);

}  // namespace c3d
