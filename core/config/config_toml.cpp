// Writes a Config as a documented TOML file, walking the parameter table:
// config/cadastre3d.toml is default_config_toml(), so the documented default
// file cannot drift from the parser (tests/config_table_test.cpp compares them).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/config/config.h"
#include "core/config/parameters.h"

namespace c3d {

namespace {

using nlohmann::json;

constexpr size_t kCommentWidth = 92;  // wrap comments to stay readable in a 100-column editor
constexpr int kNoteColumn = 25;       // map entries' notes start here when the line is shorter

const char* const kIntro[] = {
    "Cadastre3D - default run configuration.",
    "",
    "Pass another file with `--config FILE`. A file is read on top of these defaults: the "
    "[classes], [parcel_fields], [clip] and [reconstruction] keys may be left out; the "
    "[valuation] keys marked required must be given (a fiscal figure must never come from a "
    "silent default) and the other valuation keys, left out, are off. Unknown keys, wrong types "
    "and values out of range are errors that name the file and the key.",
    "",
    "This file is written from the parameter table (core/config/parameters.cpp); "
    "tests/config_table_test.cpp fails when the two differ."};

// "# " + text; a line longer than kCommentWidth is wrapped at word boundaries
// (shorter lines keep their own spacing: the valuation formulas are aligned).
void comment(std::ostream& out, const std::string& text) {
  if (text.size() <= kCommentWidth) {
    out << (text.empty() ? "#" : "# " + text) << "\n";
    return;
  }
  std::istringstream words(text);
  std::string word, line;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > kCommentWidth) {
      out << "# " << line << "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  out << "# " << line << "\n";
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else out += c;
  }
  return out + "\"";
}

std::string key_text(const std::string& k) {
  bool bare = !k.empty();
  for (char c : k)
    bare = bare && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
  return bare ? k : quoted(k);
}

// Shortest text that reads back to the same double; small whole numbers keep
// a ".0" so they read as reals, amounts of money stay whole.
std::string number_text(double v) {
  char buf[64];
  auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed).ptr;
  std::string s(buf, end);
  if (s.find('.') == std::string::npos && std::fabs(v) < 1e4) s += ".0";
  return s;
}

std::string value_text(const Parameter& p, const json& v) {
  switch (p.kind) {
    case Kind::Integer: return std::to_string(v.get<long long>());
    case Kind::Real: return number_text(v.get<double>());
    case Kind::Boolean: return v.get<bool>() ? "true" : "false";
    case Kind::ClassList: {
      std::string s;
      for (const auto& code : v) s += (s.empty() ? "" : ", ") + std::to_string(code.get<int>());
      return "[" + s + "]";
    }
    default: return quoted(v.get<std::string>());
  }
}

void describe(std::ostream& out, const Parameter& p) {
  comment(out, p.doc + ".");
  std::string facts = "unit: " + p.unit + " | range: " + describe_range(p) + " | stage: " + p.stage;
  if (p.need == Need::Required) facts += " | required";
  if (p.need == Need::OffWhenAbsent) facts += " | left out: off";
  comment(out, facts);
}

void section_header(std::ostream& out, const std::string& name) {
  out << "\n";
  if (name.find('.') == std::string::npos)
    out << "# ---------------------------------------------------------------------------\n";
  for (const SectionDoc& d : section_docs())
    if (d.name == name)
      for (const auto& line : d.comment) comment(out, line);
  out << "[" << name << "]\n";
}

void number_map(std::ostream& out, const Parameter& p, const json& m) {
  out << "\n";
  describe(out, p);
  out << "[" << p.key << "]\n";
  for (const auto& item : m.items()) {
    std::string line = key_text(item.key()) + " = " + number_text(item.value().get<double>());
    auto note = p.notes.find(item.key());
    if (note != p.notes.end())
      line += std::string(std::max<int>(1, kNoteColumn - int(line.size())), ' ') + "# " +
              note->second;
    out << line << "\n";
  }
}

void parcel_overrides(std::ostream& out, const Parameter& p, const json& all) {
  out << "\n";
  describe(out, p);
  if (all.empty()) {
    out << "# For example:\n"
        << "# [" << p.key << ".\"10.25.00.00.00123\"]\n"
        << "# zone = \"ZNT-A\"\n# quality = \"semi_permanent\"\n# age_years = 25\n";
  }
  for (const auto& item : all.items()) {
    const json& o = item.value();
    out << "[" << p.key << "." << quoted(item.key()) << "]\n";
    if (o.contains("zone")) out << "zone = " << quoted(o["zone"].get<std::string>()) << "\n";
    if (o.contains("quality"))
      out << "quality = " << quoted(o["quality"].get<std::string>()) << "\n";
    if (o.contains("age_years"))
      out << "age_years = " << number_text(o["age_years"].get<double>()) << "\n";
  }
}

}  // namespace

std::string config_toml(const Config& c) {
  std::ostringstream out;
  for (const char* line : kIntro) comment(out, line);
  std::string section;
  for (const Parameter& p : parameter_table()) {
    const json value = p.field.get(c);
    if (p.kind == Kind::NumberMap) {
      number_map(out, p, value);
      section = p.key;  // a plain key after this table would need its section reopened
      continue;
    }
    if (p.kind == Kind::ParcelOverrides) {
      parcel_overrides(out, p, value);
      section = p.key;
      continue;
    }
    if (section_of(p.key) != section) section_header(out, section = section_of(p.key));
    out << "\n";
    describe(out, p);
    out << leaf_of(p.key) << " = " << value_text(p, value) << "\n";
  }
  return out.str();
}

std::string default_config_toml() { return config_toml(default_config()); }

}  // namespace c3d
