#include "core/config/parameters.h"

#include <cmath>
#include <sstream>

namespace c3d {

// JSON form of a per-parcel override: only the facts it gives.
void to_json(nlohmann::json& j, const ParcelValuationOverride& o) {
  j = nlohmann::json::object();
  if (!o.zone.empty()) j["zone"] = o.zone;
  if (!o.quality.empty()) j["quality"] = o.quality;
  if (!std::isnan(o.age_years)) j["age_years"] = o.age_years;
}

void from_json(const nlohmann::json& j, ParcelValuationOverride& o) {
  o = ParcelValuationOverride{};
  if (j.contains("zone")) o.zone = j["zone"].get<std::string>();
  if (j.contains("quality")) o.quality = j["quality"].get<std::string>();
  if (j.contains("age_years")) o.age_years = j["age_years"].get<double>();
}

namespace {

// `ref` is a generic lambda naming the field once, for const and non-const Config.
template <class Ref>
Accessor field(Ref ref) {
  return {[ref](const Config& c) { return nlohmann::json(ref(c)); },
          [ref](Config& c, const nlohmann::json& v) { v.get_to(ref(c)); }};
}

// Naming the parcel id field in a file makes it required (config.h, ParcelFields).
Accessor parcel_id_field() {
  return {[](const Config& c) { return nlohmann::json(c.fields.id); },
          [](Config& c, const nlohmann::json& v) {
            c.fields.id = v.get<std::string>();
            c.fields.id_required = true;
          }};
}

Range between(double min, double max) { return {min, max, {}, false}; }
Range at_least(double min) { return {min, kUnbounded, {}, false}; }
Range one_of(std::vector<std::string> names) { return {0, kUnbounded, std::move(names), false}; }
// Money per m2 (unit costs, land prices): the costliest land, about 5e5 USD/m2,
// is 2e10 in the currency with the most units per dollar (rial): 1e12 leaves
// room for any price and refuses a typo like 1e308 (an infinite NJOP).
constexpr double kMaxPricePerM2 = 1e12;
// Whole money amounts: a double counts every currency unit only below 2^53.
constexpr double kMaxAmount = 9.0e15;
const Range kPrice = between(0, kMaxPricePerM2);
const Range kCodes = between(0, 255);
const Range kAnyText = {};
const Range kNonEmpty = {0, kUnbounded, {}, true};

std::vector<Parameter> input_parameters() {
  return {
      {"classes.roof", Kind::ClassList, "-", "LAS class codes of the roof points (UAV LiDAR)",
       kCodes, "input", Need::Optional, field([](auto& c) -> auto& { return c.classes.roof; })},
      {"classes.wall", Kind::ClassList, "-",
       "LAS class codes of the exterior-wall points (handheld / terrestrial scans)", kCodes,
       "input", Need::Optional, field([](auto& c) -> auto& { return c.classes.wall; })},
      {"classes.ground", Kind::ClassList, "-",
       "LAS class codes of the ground points (ASPRS ground)", kCodes, "input", Need::Optional,
       field([](auto& c) -> auto& { return c.classes.ground; })},
      {"parcel_fields.id", Kind::Text, "-",
       "Parcel id attribute (\"\" = the OGR feature id); a layer without it is an error", kAnyText,
       "input", Need::Optional, parcel_id_field()},
      {"parcel_fields.right_type", Kind::Text, "-",
       "Right type attribute, e.g. Hak Milik, Hak Guna Bangunan", kAnyText, "input",
       Need::Optional, field([](auto& c) -> auto& { return c.fields.right_type; })},
      {"parcel_fields.official_area", Kind::Text, "-",
       "Certified area attribute, m2 (LUASPETA would be the map area)", kAnyText, "input",
       Need::Optional, field([](auto& c) -> auto& { return c.fields.official_area; })},
      {"clip.overhang_buffer_m", Kind::Real, "m",
       "Points this far outside a parcel are still clipped to it: roof overhangs cross the "
       "boundary and about 10 % of the roof points lie outside",
       at_least(0), "clip", Need::Optional,
       field([](auto& c) -> auto& { return c.clip.overhang_buffer_m; })},
      {"batch.chunk_parcels", Kind::Integer, "parcels",
       "Parcels modelled per chunk: only a chunk's points are in memory at a time (more: fewer "
       "reads of each tile, more memory); changes no result",
       between(1, 1e6), "clip", Need::Optional, field([](auto& c) -> auto& { return c.batch.chunk_parcels; })},
      {"batch.chunk_points", Kind::Integer, "points",
       "A chunk also ends where its region is expected to read this many points (of every class, "
       "from the tiles' header counts): dense areas get smaller chunks; changes no result",
       between(1e4, 1e9), "clip", Need::Optional, field([](auto& c) -> auto& { return c.batch.chunk_points; })},
  };
}

std::vector<Parameter> reconstruction_parameters() {
  return {
      {"reconstruction.outlier_neighbours", Kind::Integer, "points",
       "Statistical outlier removal: neighbours per point", at_least(1), "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.outlier_neighbours; })},
      {"reconstruction.outlier_std", Kind::Real, "-",
       "Statistical outlier removal: standard-deviation multiplier", at_least(0), "segment",
       Need::Optional, field([](auto& c) -> auto& { return c.reconstruction.outlier_std; })},
      {"reconstruction.roof_cluster_m", Kind::Real, "m",
       "Gap that separates individual roofs (0 = 4 x point spacing, at least 0.5)", between(0, 10),
       "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.roof_cluster_m; })},
      {"reconstruction.component_smoothness_deg", Kind::Real, "deg",
       "Region growing of planar roof components: largest angle to the seed normal",
       between(0, 180), "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.component_smoothness_deg; })},
      {"reconstruction.component_curvature", Kind::Real, "-",
       "Region growing: points flatter than this curvature keep a component growing", at_least(0),
       "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.component_curvature; })},
      {"reconstruction.min_component_points", Kind::Integer, "points",
       "Smallest planar roof component kept, in points", at_least(3), "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.min_component_points; })},
      {"reconstruction.min_component_area_m2", Kind::Real, "m2",
       "Smallest planar roof component kept, in area", at_least(0), "segment", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.min_component_area_m2; })},
      {"reconstruction.plane_inlier_m", Kind::Real, "m", "Robust plane fit: inlier distance",
       at_least(0), "planes", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.plane_inlier_m; })},
      {"reconstruction.loose_point_reach_m", Kind::Real, "m",
       "Roof points no plane took (textured strips along eaves) widen the roof outline up to "
       "this far from the planes' points",
       between(0, 10), "outline", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.loose_point_reach_m; })},
      {"reconstruction.partition_cell_m", Kind::Real, "m",
       "Labelling grid of the roof partition (0 = 1.5 x point spacing, within 0.1..0.25)",
       between(0, 1), "roof", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.partition_cell_m; })},
      {"reconstruction.default_overhang_m", Kind::Real, "m",
       "Roof overhang assumed when no wall is seen", at_least(0), "envelope", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.default_overhang_m; })},
      {"reconstruction.storey_height_m", Kind::Real, "m", "Storeys = eave height / storey height",
       at_least(0.5), "measure", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.storey_height_m; })},
      {"reconstruction.shared_roof_depth_m", Kind::Real, "m",
       "A roof reaching this far past the overhang buffer into a neighbour parcel is shared by "
       "attached houses and split at the boundary; otherwise the parcel holding most of it "
       "gets it whole",
       between(0, 10), "ownership", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.shared_roof_depth_m; })},
      {"reconstruction.optimize", Kind::Boolean, "-",
       "Refine with the primitive-constrained optimizer (batch --optimize turns it on too)", {},
       "optimizer", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.optimize; })},
      {"reconstruction.refine_curved", Kind::Boolean, "-",
       "Mesh each curved building's points and snap the mesh onto its exact surfaces, "
       "reporting the effect (docs/curved.md)", {},
       "optimizer", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.refine_curved; })},
      {"reconstruction.optimize_device", Kind::Choice, "-", "Where the optimizer runs",
       one_of({"auto", "cpu", "vulkan"}), "optimizer", Need::Optional,
       field([](auto& c) -> auto& { return c.reconstruction.optimize_device; })},
  };
}

std::vector<std::string> element_type_names() {
  std::vector<std::string> names;
  for (ElementType t : {ElementType::Roof, ElementType::Wall, ElementType::PartyWall,
                        ElementType::Ground, ElementType::OuterCeiling})
    names.push_back(to_string(t));
  return names;
}

std::vector<Parameter> valuation_scalars() {
  return {
      {"valuation.currency", Kind::Text, "-", "Currency of every amount", kNonEmpty, "valuation",
       Need::Required, field([](auto& c) -> auto& { return c.valuation.currency; })},
      {"valuation.building_age_years", Kind::Real, "years",
       "Building age used when a parcel has no override", at_least(0), "valuation",
       Need::Required, field([](auto& c) -> auto& { return c.valuation.building_age_years; })},
      {"valuation.depreciation_per_year", Kind::Real, "1/year",
       "Straight-line depreciation: share of the replacement cost per year of age", between(0, 1),
       "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.depreciation_per_year; })},
      {"valuation.max_depreciation", Kind::Real, "-",
       "Depreciation cap (0.5: the residual value never falls below 50 %)", between(0, 1),
       "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.max_depreciation; })},
      {"valuation.default_zone", Kind::Text, "-",
       "Land value zone of a parcel without override; one of [valuation.land_price]", kNonEmpty,
       "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.default_zone; })},
      {"valuation.default_quality", Kind::Text, "-",
       "Quality class of a parcel without override; one of [valuation.quality_factor] "
       "(\"\" = factor 1)",
       kAnyText, "valuation", Need::OffWhenAbsent,
       field([](auto& c) -> auto& { return c.valuation.default_quality; })},
      {"valuation.gross_floor_cost_per_m2", Kind::Real, "currency/m2",
       "Extra cost per m2 of gross floor area (0 = element costs only)", kPrice, "valuation",
       Need::OffWhenAbsent,
       field([](auto& c) -> auto& { return c.valuation.gross_floor_cost_per_m2; })},
  };
}

std::vector<Parameter> valuation_tables() {
  return {
      {"valuation.unit_cost", Kind::NumberMap, "currency/m2",
       "Replacement cost per m2 of element area (DBKB-style component costs, 2024 level)",
       {0, kMaxPricePerM2, element_type_names(), false}, "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.unit_cost; }),
       {{"roof", "clay-tile roof incl. timber/steel truss, per m2 sloped area"},
        {"wall", "plastered, painted brick wall, per m2 (both sides finished)"},
        {"party_wall", "shared wall: half the cost belongs to this owner"},
        {"ground", "ground slab with ceramic floor tiles"},
        {"outer_ceiling", "eave soffit (gypsum / GRC board)"}}},
      {"valuation.quality_factor", Kind::NumberMap, "-",
       "Construction quality classes: factor on the unit costs", between(0, 100), "valuation",
       Need::OffWhenAbsent, field([](auto& c) -> auto& { return c.valuation.quality_factor; }),
       {{"permanent", "brick / concrete"},
        {"semi_permanent", "half brick, half timber"},
        {"temporary", "timber, bamboo"}}},
      {"valuation.land_price", Kind::NumberMap, "currency/m2",
       "Zona Nilai Tanah (land value zones): land price per m2", kPrice, "valuation",
       Need::Required, field([](auto& c) -> auto& { return c.valuation.land_price; }),
       {{"ZNT-A", "main road frontage"},
        {"ZNT-B", "residential street"},
        {"ZNT-C", "alley (gang) access"}}},
      {"valuation.tax.rate", Kind::Real, "-",
       "Tax rate, a share of the taxable NJOP (UU 1/2022 HKPD allows at most 0.5 %)",
       between(0, 1), "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.tax_rate; })},
      {"valuation.tax.njoptkp", Kind::Real, "currency", "Non-taxable NJOP per taxpayer",
       between(0, kMaxAmount), "valuation", Need::Required,
       field([](auto& c) -> auto& { return c.valuation.tax_exemption; })},
      {"valuation.parcels", Kind::ParcelOverrides, "-",
       "Per-parcel facts the parcel layer does not carry: zone, quality, age_years", at_least(0),
       "valuation", Need::OffWhenAbsent,
       field([](auto& c) -> auto& { return c.valuation.parcels; })},
  };
}

std::vector<Parameter> mesh_parameters() {
  return {
      {"mesh.ladder", Kind::Boolean, "-",
       "Mesh each modelled building's own points at four levels of detail and check the element "
       "model against the closed level (batch --mesh; docs/meshes.md)", {}, "mesh", Need::Optional,
       field([](auto& c) -> auto& { return c.mesh.ladder; })},
      {"mesh.method", Kind::Choice, "-",
       "Level 4's dense method: advancing front, ball pivoting, screened Poisson or alpha shapes",
       one_of({"front", "pivot", "poisson", "alpha"}), "mesh", Need::Optional,
       field([](auto& c) -> auto& { return c.mesh.method; })},
      {"mesh.simplify", Kind::Choice, "-",
       "Levels 3 and 2: boundary-aware edge collapse by regions (seed 002), or for comparison plain "
       "Lindstrom-Turk, Garland-Heckbert or vertex clustering (docs/meshes.md)",
       one_of({"boundary", "qem", "garland", "clustering"}), "mesh", Need::Optional,
       field([](auto& c) -> auto& { return c.mesh.simplify; })},
  };
}

std::vector<Parameter> build_table() {
  std::vector<Parameter> all;
  for (auto part : {input_parameters(), reconstruction_parameters(), mesh_parameters(), valuation_scalars(),
                    valuation_tables()})
    all.insert(all.end(), part.begin(), part.end());
  return all;
}

}  // namespace

const std::vector<std::string> kStages = {"input",   "clip",  "segment",  "ownership",
                                          "planes",  "outline", "roof",   "envelope",
                                          "measure", "optimizer", "mesh", "valuation"};

const std::vector<Parameter>& parameter_table() {
  static const std::vector<Parameter> table = build_table();
  return table;
}

const std::vector<SectionDoc>& section_docs() {
  static const std::vector<SectionDoc> docs = {
      {"classes", {"Point classes: which raw LAS classification codes mean what."}},
      {"parcel_fields", {"Attribute names in the parcel layer (Cimahi BPN schema)."}},
      {"clip", {"Clipping the point clouds to each parcel."}},
      {"batch", {"How the batch runs through the clouds; no setting here changes a result or the resume key."}},
      {"reconstruction", {"Roof and wall reconstruction, stage by stage."}},
      {"mesh", {"Meshes of each building's own points at four levels of detail (docs/meshes.md)."}},
      {"valuation",
       {"Valuation: cost approach (SPOP / PBB-P2 practice).",
        "  building = sum(element area x unit cost x quality factor) x (1 - depreciation)",
        "  land     = parcel area (certified if known, else computed) x zone land price",
        "  NJOP     = land + building",
        "  tax      = rate x max(0, NJOP - NJOPTKP)"}},
      {"valuation.tax", {"PBB-P2: tax = rate x max(0, NJOP - NJOPTKP)."}},
  };
  return docs;
}

std::string section_of(const std::string& key) {
  size_t dot = key.rfind('.');
  return dot == std::string::npos ? std::string() : key.substr(0, dot);
}

std::string leaf_of(const std::string& key) { return key.substr(key.rfind('.') + 1); }

namespace {
std::string bounds(const Range& r) {
  std::ostringstream s;
  if (r.max == kUnbounded) s << ">= " << r.min;
  else s << "[" << r.min << ", " << r.max << "]";
  return s.str();
}

std::string joined(const std::vector<std::string>& names, const std::string& sep) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : sep) + n;
  return s;
}
}  // namespace

std::string describe_range(const Parameter& p) {
  const Range& r = p.range;
  switch (p.kind) {
    case Kind::Integer:
    case Kind::Real: return bounds(r);
    case Kind::Boolean: return "true or false";
    case Kind::Text: return r.non_empty ? "non-empty text" : "text";
    case Kind::Choice: {
      std::vector<std::string> first(r.names.begin(), r.names.end() - 1);
      return r.names.size() < 2 ? joined(r.names, "")
                                : joined(first, ", ") + " or " + r.names.back();
    }
    case Kind::ClassList: return "class codes " + bounds(r);
    case Kind::NumberMap:
      return (r.names.empty() ? "" : "keys " + joined(r.names, ", ") + "; ") + "values " +
             bounds(r);
    case Kind::ParcelOverrides:
      return "zone in [valuation.land_price], quality in [valuation.quality_factor], "
             "age_years " + bounds(r);
  }
  return "";
}

}  // namespace c3d
