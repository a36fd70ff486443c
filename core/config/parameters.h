#pragma once
// The parameter table: every key of the config file declared once. The loader
// (config.cpp), the documented default file (config_toml.cpp), the run record
// and the resume key (config_json.cpp) all walk this table, so a key added here
// is parsed, documented, recorded and fingerprinted without further edits.
// The defaults themselves are the Config struct's member initializers.
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/config/config.h"

namespace c3d {

enum class Kind {
  Integer,
  Real,
  Boolean,
  Text,
  Choice,           // one of range.names
  ClassList,        // array of LAS class codes
  NumberMap,        // table of name -> number; range.names, when given, are exactly its keys
  ParcelOverrides,  // table of parcel id -> {zone, quality, age_years}
};

// When a file leaves the key out.
enum class Need {
  Optional,      // the built-in default stays
  Required,      // an error: a fiscal figure must never come from a silent default
  OffWhenAbsent  // none / zero (an optional valuation setting is never inherited)
};

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

struct Range {
  double min = 0.0;  // numbers, map values and class codes: inclusive bounds
  double max = kUnbounded;
  std::vector<std::string> names;  // Choice: the choices; NumberMap: the keys it must hold
  bool non_empty = false;          // Text: may not be ""
};

// Reads and writes one Config field as JSON (the value the table's kind describes).
struct Accessor {
  std::function<nlohmann::json(const Config&)> get;
  std::function<void(Config&, const nlohmann::json&)> set;
};

struct Parameter {
  std::string key;    // dotted: "reconstruction.outlier_std"
  Kind kind;
  std::string unit;   // "m", "deg", "currency/m2", ...; "-" when it has none
  std::string doc;    // one line
  Range range;
  std::string stage;  // the stage that reads it (see kStages)
  Need need;
  Accessor field;
  std::map<std::string, std::string> notes = {};  // NumberMap: a comment per default key
};

// The stages a parameter can belong to, in pipeline order.
extern const std::vector<std::string> kStages;

// A [section] of the file and the comment lines written above it.
struct SectionDoc {
  std::string name;
  std::vector<std::string> comment;
};

// In file order: a section's plain keys come before its tables (TOML cannot
// return to [valuation] after [valuation.unit_cost]).
const std::vector<Parameter>& parameter_table();
const std::vector<SectionDoc>& section_docs();

// The section of a dotted key ("valuation.tax.rate" -> "valuation.tax") and its last part.
std::string section_of(const std::string& key);
std::string leaf_of(const std::string& key);
// "[0, 10]", ">= 1", "auto, cpu or vulkan", "class codes [0, 255]", ...
std::string describe_range(const Parameter& p);

}  // namespace c3d
