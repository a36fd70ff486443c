#include "core/config/config.h"

#include <toml++/toml.h>

#include <cmath>
#include <set>
#include <sstream>

#include "core/error.h"

namespace c3d {

namespace {

const char* const kElementTypes[] = {"roof", "wall", "party_wall", "ground", "outer_ceiling"};

// Walks one TOML table; every message names the file and the dotted key.
class Section {
 public:
  Section(const std::string& file, const toml::table* table, std::string path)
      : file_(file), table_(table), path_(std::move(path)) {}

  bool present() const { return table_ != nullptr; }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  [[noreturn]] void fail(const std::string& k, const std::string& problem) const {
    throw InputError(file_, "key '" + key(k) + "': " + problem);
  }

  // Rejects keys the reader does not know: a typo must not fall back silently.
  void allow_only(const std::set<std::string>& known) const {
    if (!table_) return;
    for (const auto& [k, v] : *table_) {
      std::string name(k.str());
      if (!known.count(name)) fail(name, "unknown key");
    }
  }

  Section sub(const std::string& k, bool required) const {
    const toml::node* n = table_ ? table_->get(k) : nullptr;
    if (!n) {
      if (required) fail(k, "missing");
      return Section(file_, nullptr, key(k));
    }
    if (!n->is_table()) fail(k, "must be a table");
    return Section(file_, n->as_table(), key(k));
  }

  const toml::node* node(const std::string& k, bool required) const {
    const toml::node* n = table_ ? table_->get(k) : nullptr;
    if (!n && required) fail(k, "missing");
    return n;
  }

  void number(const std::string& k, double& out, bool required, double min = 0.0,
              double max = HUGE_VAL) const {
    const toml::node* n = node(k, required);
    if (!n) return;
    double v;
    if (auto i = n->as_integer()) v = double(i->get());
    else if (auto f = n->as_floating_point()) v = f->get();
    else fail(k, "must be a number");
    if (!std::isfinite(v) || v < min || v > max) {
      std::ostringstream s;
      if (max == HUGE_VAL) s << "must be >= " << min << ", got " << v;
      else s << "must be in [" << min << ", " << max << "], got " << v;
      fail(k, s.str());
    }
    out = v;
  }

  void integer(const std::string& k, int& out, bool required, int min = 0) const {
    const toml::node* n = node(k, required);
    if (!n) return;
    auto i = n->as_integer();
    if (!i) fail(k, "must be an integer");
    if (i->get() < min) fail(k, "must be >= " + std::to_string(min));
    out = int(i->get());
  }

  void boolean(const std::string& k, bool& out, bool required) const {
    const toml::node* n = node(k, required);
    if (!n) return;
    auto b = n->as_boolean();
    if (!b) fail(k, "must be true or false");
    out = b->get();
  }

  void text(const std::string& k, std::string& out, bool required) const {
    const toml::node* n = node(k, required);
    if (!n) return;
    auto s = n->as_string();
    if (!s) fail(k, "must be a string");
    out = s->get();
  }

  void int_list(const std::string& k, std::vector<int>& out, bool required) const {
    const toml::node* n = node(k, required);
    if (!n) return;
    auto a = n->as_array();
    if (!a) fail(k, "must be an array of integers");
    std::vector<int> v;
    for (const auto& e : *a) {
      auto i = e.as_integer();
      if (!i || i->get() < 0 || i->get() > 255) fail(k, "must hold class codes 0..255");
      v.push_back(int(i->get()));
    }
    out = v;
  }

  // A table of name -> non-negative number (zones, quality classes, unit costs).
  std::map<std::string, double> number_map() const {
    std::map<std::string, double> m;
    if (!table_) return m;
    for (const auto& [k, v] : *table_) {
      double x = 0;
      number(std::string(k.str()), x, true);
      m[std::string(k.str())] = x;
    }
    return m;
  }

  template <class F>
  void each_table(F&& f) const {
    if (!table_) return;
    for (const auto& [k, v] : *table_) f(std::string(k.str()), sub(std::string(k.str()), true));
  }

 private:
  std::string file_;
  const toml::table* table_;
  std::string path_;
};

void read_classes(const Section& s, ClassMapping& c) {
  s.allow_only({"roof", "wall", "ground"});
  s.int_list("roof", c.roof, false);
  s.int_list("wall", c.wall, false);
  s.int_list("ground", c.ground, false);
}

void read_fields(const Section& s, ParcelFields& f) {
  s.allow_only({"id", "right_type", "official_area"});
  if (s.node("id", false)) f.id_required = true;  // named by the user: must exist
  s.text("id", f.id, false);
  s.text("right_type", f.right_type, false);
  s.text("official_area", f.official_area, false);
}

void read_reconstruction(const Section& s, ReconstructionParams& r) {
  s.allow_only({"outlier_neighbours", "outlier_std", "roof_cluster_m",
                "component_smoothness_deg", "component_curvature", "min_component_points",
                "min_component_area_m2", "plane_inlier_m", "loose_point_reach_m", "partition_cell_m",
                "default_overhang_m", "storey_height_m", "shared_roof_depth_m", "optimize",
                "optimize_device"});
  s.integer("outlier_neighbours", r.outlier_neighbours, false, 1);
  s.number("outlier_std", r.outlier_std, false);
  s.number("roof_cluster_m", r.roof_cluster_m, false, 0, 10);
  s.number("component_smoothness_deg", r.component_smoothness_deg, false, 0, 180);
  s.number("component_curvature", r.component_curvature, false);
  s.integer("min_component_points", r.min_component_points, false, 3);
  s.number("min_component_area_m2", r.min_component_area_m2, false);
  s.number("plane_inlier_m", r.plane_inlier_m, false);
  s.number("loose_point_reach_m", r.loose_point_reach_m, false, 0, 10);
  s.number("partition_cell_m", r.partition_cell_m, false, 0, 1);
  s.number("default_overhang_m", r.default_overhang_m, false);
  s.number("storey_height_m", r.storey_height_m, false, 0.5);
  s.number("shared_roof_depth_m", r.shared_roof_depth_m, false, 0, 10);
  s.boolean("optimize", r.optimize, false);
  s.text("optimize_device", r.optimize_device, false);
  if (r.optimize_device != "auto" && r.optimize_device != "cpu" && r.optimize_device != "vulkan")
    s.fail("optimize_device", "must be auto, cpu or vulkan");
}

void read_unit_costs(const Section& s, ValuationParams& v) {
  std::set<std::string> types(std::begin(kElementTypes), std::end(kElementTypes));
  s.allow_only(types);  // names the unknown element type
  v.unit_cost.clear();
  for (const char* t : kElementTypes) s.number(t, v.unit_cost[t], true);
}

void read_valuation(const Section& s, ValuationParams& v) {
  s.allow_only({"currency", "building_age_years", "depreciation_per_year", "max_depreciation",
                "default_zone", "default_quality", "gross_floor_cost_per_m2", "unit_cost",
                "quality_factor", "land_price", "tax", "parcels"});
  s.text("currency", v.currency, true);
  if (v.currency.empty()) s.fail("currency", "must not be empty");
  s.number("building_age_years", v.building_age_years, true);
  s.number("depreciation_per_year", v.depreciation_per_year, true, 0, 1);
  s.number("max_depreciation", v.max_depreciation, true, 0, 1);
  s.number("gross_floor_cost_per_m2", v.gross_floor_cost_per_m2, false);
  read_unit_costs(s.sub("unit_cost", true), v);

  v.quality_factor = s.sub("quality_factor", false).number_map();
  v.default_quality.clear();
  s.text("default_quality", v.default_quality, false);
  if (!v.default_quality.empty() && !v.quality_factor.count(v.default_quality))
    s.fail("default_quality", "'" + v.default_quality + "' is not in valuation.quality_factor");

  v.land_price = s.sub("land_price", true).number_map();
  if (v.land_price.empty()) s.fail("land_price", "needs at least one zone");
  s.text("default_zone", v.default_zone, true);
  if (!v.land_price.count(v.default_zone))
    s.fail("default_zone", "'" + v.default_zone + "' is not in valuation.land_price");

  Section tax = s.sub("tax", true);
  tax.allow_only({"rate", "njoptkp"});
  tax.number("rate", v.tax_rate, true, 0, 1);
  tax.number("njoptkp", v.tax_exemption, true);

  v.parcels.clear();
  s.sub("parcels", false).each_table([&](const std::string& id, const Section& p) {
    p.allow_only({"zone", "quality", "age_years"});
    ParcelValuationOverride o;
    p.text("zone", o.zone, false);
    p.text("quality", o.quality, false);
    p.number("age_years", o.age_years, false);
    if (!o.zone.empty() && !v.land_price.count(o.zone))
      p.fail("zone", "'" + o.zone + "' is not in valuation.land_price");
    if (!o.quality.empty() && !v.quality_factor.count(o.quality))
      p.fail("quality", "'" + o.quality + "' is not in valuation.quality_factor");
    v.parcels[id] = o;
  });
}

}  // namespace

ParcelFields parcel_fields(const std::string& id_field) {
  ParcelFields f = default_config().fields;
  if (!id_field.empty()) f.id = id_field, f.id_required = true;
  return f;
}

Config default_config() {
  Config c;
  c.source = "(defaults)";
  c.fields.id = "NIB";
  c.fields.id_required = false;  // the built-in default: other layers fall back to feature ids
  ValuationParams& v = c.valuation;
  v.currency = "IDR";
  v.building_age_years = 10;
  v.depreciation_per_year = 0.015;
  v.max_depreciation = 0.5;
  v.default_zone = "ZNT-B";
  v.default_quality = "permanent";
  v.gross_floor_cost_per_m2 = 0;
  v.unit_cost = {{"roof", 550000},   {"wall", 400000},         {"party_wall", 200000},
                 {"ground", 350000}, {"outer_ceiling", 175000}};
  v.quality_factor = {{"permanent", 1.0}, {"semi_permanent", 0.75}, {"temporary", 0.5}};
  v.land_price = {{"ZNT-A", 6500000}, {"ZNT-B", 4000000}, {"ZNT-C", 2500000}};
  v.tax_rate = 0.001;
  v.tax_exemption = 10000000;
  return c;
}

Config load_config(const std::string& path) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    const auto& b = e.source().begin;
    if (b.line == 0) s << "cannot read config: " << e.description();
    else s << "line " << b.line << ", column " << b.column << ": " << e.description();
    throw InputError(path, s.str());
  }
  Config c = default_config();
  c.source = path;
  Section top(path, &root, "");
  top.allow_only({"classes", "parcel_fields", "clip", "reconstruction", "valuation"});
  read_classes(top.sub("classes", false), c.classes);
  read_fields(top.sub("parcel_fields", false), c.fields);
  Section clip = top.sub("clip", false);
  clip.allow_only({"overhang_buffer_m"});
  clip.number("overhang_buffer_m", c.clip.overhang_buffer_m, false);
  read_reconstruction(top.sub("reconstruction", false), c.reconstruction);
  read_valuation(top.sub("valuation", true), c.valuation);
  return c;
}

}  // namespace c3d
