#pragma once
// Small text helpers shared by the writers (report HTML, CityGML XML).
#include <string>

namespace c3d {

// Escapes &, <, >, " and ' for XML and HTML text and attribute values.
inline std::string escape_markup(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace c3d
