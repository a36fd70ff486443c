#include "core/config/config.h"

#include <toml++/toml.h>

#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include "core/config/parameters.h"
#include "core/error.h"

namespace c3d {

namespace {

using nlohmann::json;

// Every message names the file and the dotted key, on one line.
struct Where {
  const std::string& file;
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const {
    throw InputError(file, "key '" + key + "': " + problem);
  }
};

toml::table parse_file(const std::string& path) {
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    const auto& b = e.source().begin;
    if (b.line == 0) s << "cannot read config: " << e.description();
    else s << "line " << b.line << ", column " << b.column << ": " << e.description();
    throw InputError(path, s.str());
  }
}

// The table's keys and the sections above them ("valuation", "valuation.tax").
struct KnownKeys {
  std::set<std::string> keys, sections;
  KnownKeys() {
    for (const Parameter& p : parameter_table()) {
      keys.insert(p.key);
      for (std::string s = section_of(p.key); !s.empty(); s = section_of(s)) sections.insert(s);
    }
  }
};

// Rejects keys the table does not know: a typo must not fall back silently.
void reject_unknown(const toml::table& t, const std::string& prefix, const KnownKeys& known,
                    const Where& w) {
  for (const auto& [k, node] : t) {
    std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (known.keys.count(key)) continue;
    if (!known.sections.count(key)) w.fail(key, "unknown key");
    if (!node.is_table()) w.fail(key, "must be a table");
    reject_unknown(*node.as_table(), key, known, w);
  }
}

// The node at a dotted key, or null; reject_unknown has checked that sections are tables.
const toml::node* find(const toml::table& root, const std::string& key) {
  const toml::table* t = &root;
  size_t start = 0;
  for (size_t dot = key.find('.'); dot != std::string::npos; dot = key.find('.', start)) {
    const toml::node* n = t->get(key.substr(start, dot - start));
    if (!n || !n->is_table()) return nullptr;
    t = n->as_table();
    start = dot + 1;
  }
  return t->get(key.substr(start));
}

double read_number(const toml::node& n, const Range& r, const std::string& key, const Where& w) {
  double v;
  if (auto i = n.as_integer()) v = double(i->get());
  else if (auto f = n.as_floating_point()) v = f->get();
  else w.fail(key, "must be a number");
  if (!std::isfinite(v) || v < r.min || v > r.max) {
    std::ostringstream s;
    if (r.max == kUnbounded) s << "must be >= " << r.min << ", got " << v;
    else s << "must be in [" << r.min << ", " << r.max << "], got " << v;
    w.fail(key, s.str());
  }
  return v;
}

json read_integer(const toml::node& n, const Range& r, const std::string& key, const Where& w) {
  auto i = n.as_integer();
  if (!i) w.fail(key, "must be an integer");
  if (i->get() < std::numeric_limits<int>::min() || i->get() > std::numeric_limits<int>::max())
    w.fail(key, "integer " + std::to_string(i->get()) + " is beyond the 32-bit range");
  return int(read_number(n, r, key, w));
}

std::string read_text(const toml::node& n, const std::string& key, const Where& w) {
  auto s = n.as_string();
  if (!s) w.fail(key, "must be a string");
  return s->get();
}

json read_class_list(const toml::node& n, const Range& r, const std::string& key, const Where& w) {
  auto a = n.as_array();
  if (!a) w.fail(key, "must be an array of integers");
  std::vector<int> codes;
  for (const auto& e : *a) {
    auto i = e.as_integer();
    if (!i || i->get() < r.min || i->get() > r.max) w.fail(key, "must hold class codes 0..255");
    codes.push_back(int(i->get()));
  }
  return codes;
}

// name -> number; when the range names keys, exactly those (every element type priced).
json read_number_map(const toml::node& n, const Range& r, const std::string& key, const Where& w) {
  if (!n.is_table()) w.fail(key, "must be a table");
  const toml::table& t = *n.as_table();
  std::set<std::string> named(r.names.begin(), r.names.end());
  json m = json::object();
  for (const auto& [k, v] : t) {
    std::string name(k.str());
    if (!named.empty() && !named.count(name)) w.fail(key + "." + name, "unknown key");
    m[name] = read_number(v, r, key + "." + name, w);
  }
  for (const auto& name : r.names)
    if (!m.contains(name)) w.fail(key + "." + name, "missing");
  return m;
}

// parcel id -> {zone, quality, age_years}; the references are checked with the rest.
json read_overrides(const toml::node& n, const Range& r, const std::string& key, const Where& w) {
  if (!n.is_table()) w.fail(key, "must be a table");
  json all = json::object();
  for (const auto& [id, node] : *n.as_table()) {
    std::string at = key + "." + std::string(id.str());
    if (!node.is_table()) w.fail(at, "must be a table");
    json o = json::object();
    for (const auto& [k, v] : *node.as_table()) {
      std::string name(k.str());
      if (name == "zone" || name == "quality") o[name] = read_text(v, at + "." + name, w);
      else if (name == "age_years") o[name] = read_number(v, r, at + "." + name, w);
      else w.fail(at + "." + name, "unknown key");
    }
    all[std::string(id.str())] = o;
  }
  return all;
}

json read_value(const Parameter& p, const toml::node& n, const Where& w) {
  const std::string& key = p.key;
  switch (p.kind) {
    case Kind::Integer: return read_integer(n, p.range, key, w);
    case Kind::Real: return read_number(n, p.range, key, w);
    case Kind::Boolean:
      if (!n.as_boolean()) w.fail(key, "must be true or false");
      return n.as_boolean()->get();
    case Kind::Text: {
      std::string s = read_text(n, key, w);
      if (p.range.non_empty && s.empty()) w.fail(key, "must not be empty");
      return s;
    }
    case Kind::Choice: {
      std::string s = read_text(n, key, w);
      for (const auto& c : p.range.names)
        if (s == c) return s;
      w.fail(key, "must be " + describe_range(p) + ", got '" + s + "'");
    }
    case Kind::ClassList: return read_class_list(n, p.range, key, w);
    case Kind::NumberMap: return read_number_map(n, p.range, key, w);
    case Kind::ParcelOverrides: return read_overrides(n, p.range, key, w);
  }
  w.fail(key, "has a kind the reader does not know");
}

// What an OffWhenAbsent key means when a file leaves it out.
json off_value(Kind k) {
  switch (k) {
    case Kind::Integer: return 0;
    case Kind::Real: return 0.0;
    case Kind::Boolean: return false;
    case Kind::Text:
    case Kind::Choice: return "";
    case Kind::ClassList: return json::array();
    case Kind::NumberMap:
    case Kind::ParcelOverrides: return json::object();
  }
  return nullptr;
}

// The valuation's names must point at zones and quality classes that exist.
void check_references(const ValuationParams& v, const Where& w) {
  if (v.land_price.empty()) w.fail("valuation.land_price", "needs at least one zone");
  if (!v.land_price.count(v.default_zone))
    w.fail("valuation.default_zone", "'" + v.default_zone + "' is not in valuation.land_price");
  if (!v.default_quality.empty() && !v.quality_factor.count(v.default_quality))
    w.fail("valuation.default_quality",
           "'" + v.default_quality + "' is not in valuation.quality_factor");
  for (const auto& [id, o] : v.parcels) {
    const std::string at = "valuation.parcels." + id;
    if (!o.zone.empty() && !v.land_price.count(o.zone))
      w.fail(at + ".zone", "'" + o.zone + "' is not in valuation.land_price");
    if (!o.quality.empty() && !v.quality_factor.count(o.quality))
      w.fail(at + ".quality", "'" + o.quality + "' is not in valuation.quality_factor");
  }
}

}  // namespace

ParcelFields parcel_fields(const std::string& id_field) {
  ParcelFields f = default_config().fields;
  if (!id_field.empty()) f.id = id_field, f.id_required = true;
  return f;
}

Config default_config() { return Config{}; }

Config load_config(const std::string& path) {
  const toml::table root = parse_file(path);
  const Where where{path};
  static const KnownKeys known;
  reject_unknown(root, "", known, where);
  Config c = default_config();
  c.source = path;
  for (const Parameter& p : parameter_table()) {
    const toml::node* n = find(root, p.key);
    if (n) p.field.set(c, read_value(p, *n, where));
    else if (p.need == Need::Required) where.fail(p.key, "missing");
    else if (p.need == Need::OffWhenAbsent) p.field.set(c, off_value(p.kind));
  }
  check_references(c.valuation, where);
  return c;
}

}  // namespace c3d
