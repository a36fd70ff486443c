#pragma once
// Small text helpers shared by the writers (report HTML and CSV, CityGML XML).
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

// A CSV cell: quoted (inner quotes doubled) when it holds a comma, quote, CR or LF.
inline std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// A CSV cell of text from the data (ids, reasons, names): a spreadsheet runs a
// cell that starts with = + - @ TAB or CR as a formula, so such a cell gets a
// leading single quote (OWASP's rule against CSV injection). Numbers go
// through csv_cell and stay numbers.
inline std::string csv_text_cell(const std::string& s) {
  const bool formula = !s.empty() && std::string("=+-@\t\r").find(s[0]) != std::string::npos;
  return csv_cell(formula ? "'" + s : s);
}

}  // namespace c3d
