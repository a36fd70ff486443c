#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "core/config/config.h"
#include "core/error.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

std::string default_file() { return std::string(C3D_SOURCE_DIR) + "/config/cadastre3d.toml"; }

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Writes the default file with one edit (regex replace of the first match).
std::string variant(const std::string& name, const std::string& pattern, const std::string& repl) {
  std::string text = read(default_file());
  std::string edited = std::regex_replace(text, std::regex(pattern), repl,
                                          std::regex_constants::format_first_only);
  EXPECT_NE(edited, text) << "pattern did not match: " << pattern;
  std::string path = test::temp_dir("config_" + name) + "/bad.toml";
  std::ofstream(path) << edited;
  return path;
}

// The message must name the file and the key, on one line.
void expect_error(const std::string& path, const std::string& key, const std::string& problem) {
  try {
    load_config(path);
    ADD_FAILURE() << "no error for " << key;
  } catch (const InputError& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(key), std::string::npos) << msg;
    EXPECT_NE(msg.find(problem), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

}  // namespace

TEST(Config, DefaultFileLoadsAndEqualsBuiltInDefaults) {
  Config f = load_config(default_file());
  Config d = default_config();
  EXPECT_EQ(f.source, default_file());
  EXPECT_EQ(f.classes.roof, d.classes.roof);
  EXPECT_EQ(f.classes.wall, d.classes.wall);
  EXPECT_EQ(f.fields.id, d.fields.id);
  EXPECT_EQ(f.fields.right_type, d.fields.right_type);
  EXPECT_DOUBLE_EQ(f.clip.overhang_buffer_m, d.clip.overhang_buffer_m);
  EXPECT_DOUBLE_EQ(f.reconstruction.plane_inlier_m, d.reconstruction.plane_inlier_m);
  EXPECT_EQ(f.reconstruction.min_component_points, d.reconstruction.min_component_points);
  EXPECT_DOUBLE_EQ(f.reconstruction.storey_height_m, d.reconstruction.storey_height_m);
  const auto &a = f.valuation, &b = d.valuation;
  EXPECT_EQ(a.currency, "IDR");
  EXPECT_EQ(a.unit_cost, b.unit_cost);
  EXPECT_EQ(a.unit_cost.size(), 5u);
  EXPECT_EQ(a.land_price, b.land_price);
  EXPECT_EQ(a.quality_factor, b.quality_factor);
  EXPECT_EQ(a.default_zone, b.default_zone);
  EXPECT_EQ(a.default_quality, b.default_quality);
  EXPECT_DOUBLE_EQ(a.tax_rate, b.tax_rate);
  EXPECT_DOUBLE_EQ(a.tax_exemption, b.tax_exemption);
  EXPECT_DOUBLE_EQ(a.depreciation_per_year, b.depreciation_per_year);
  EXPECT_DOUBLE_EQ(a.max_depreciation, b.max_depreciation);
  EXPECT_DOUBLE_EQ(a.building_age_years, b.building_age_years);
}

TEST(Config, PerParcelOverridesAreRead) {
  std::string path = test::temp_dir("config_parcels") + "/c.toml";
  std::ofstream(path) << read(default_file())
                      << "\n[valuation.parcels.\"P-7\"]\nzone = \"ZNT-A\"\nage_years = 30\n";
  Config c = load_config(path);
  ASSERT_EQ(c.valuation.parcels.count("P-7"), 1u);
  EXPECT_EQ(c.valuation.parcels["P-7"].zone, "ZNT-A");
  EXPECT_DOUBLE_EQ(c.valuation.parcels["P-7"].age_years, 30);
  EXPECT_TRUE(c.valuation.parcels["P-7"].quality.empty());
}

TEST(Config, MissingFileIsOneClearError) {
  expect_error("/nonexistent/c3d.toml", "/nonexistent/c3d.toml", "cannot read");
}

TEST(Config, SyntaxErrorNamesTheLine) {
  expect_error(variant("syntax", "currency = \"IDR\"", "currency = IDR\""), "line", "");
}

TEST(Config, MissingKey) {
  expect_error(variant("missing", "\nwall = 400000[^\n]*", ""), "valuation.unit_cost.wall", "missing");
  expect_error(variant("missing_tax", "\nnjoptkp = [^\n]*", ""), "valuation.tax.njoptkp", "missing");
}

TEST(Config, NegativeCost) {
  expect_error(variant("negative", "roof = 550000", "roof = -550000"), "valuation.unit_cost.roof",
               "must be in [0, 1e+12], got -550000");
}

TEST(Config, UnknownElementType) {
  expect_error(variant("unknown_type", "outer_ceiling = 175000", "outer_ceiling = 175000\nchimney = 9"),
               "valuation.unit_cost.chimney", "unknown key");
}

TEST(Config, WrongType) {
  expect_error(variant("wrong_type", "rate = 0.001", "rate = \"0.1 %\""), "valuation.tax.rate",
               "must be a number");
  expect_error(variant("wrong_list", "roof = \\[6\\]", "roof = 6"), "classes.roof", "array");
}

TEST(Config, UnknownZoneAndTypo) {
  expect_error(variant("zone", "default_zone = \"ZNT-B\"", "default_zone = \"ZNT-X\""),
               "valuation.default_zone", "ZNT-X");
  expect_error(variant("typo", "overhang_buffer_m", "overhang_bufer_m"), "clip.overhang_bufer_m",
               "unknown key");
  expect_error(variant("rate", "rate = 0.001", "rate = 1.5"), "valuation.tax.rate", "must be in");
}

TEST(Config, RangesAndChoices) {
  expect_error(variant("neighbours", "outlier_neighbours = 12", "outlier_neighbours = 0"),
               "reconstruction.outlier_neighbours", "must be >= 1, got 0");
  expect_error(variant("points", "min_component_points = 30", "min_component_points = 30.5"),
               "reconstruction.min_component_points", "must be an integer");
  expect_error(variant("device", "optimize_device = \"auto\"", "optimize_device = \"gpu\""),
               "reconstruction.optimize_device", "must be auto, cpu or vulkan");
  expect_error(variant("optimize", "optimize = false", "optimize = 1"), "reconstruction.optimize",
               "true or false");
  expect_error(variant("class", "roof = \\[6\\]", "roof = [6, 300]"), "classes.roof", "0..255");
  expect_error(variant("currency", "currency = \"IDR\"", "currency = \"\""), "valuation.currency",
               "must not be empty");
}

TEST(Config, UnknownSectionAndSectionThatIsNotATable) {
  expect_error(variant("section", "\n\\[clip\\]", "\n[clipping]"), "clipping", "unknown key");
  std::string path = test::temp_dir("config_not_table") + "/c.toml";
  std::ofstream(path) << "reconstruction = 3\n";
  expect_error(path, "reconstruction", "must be a table");
}

TEST(Config, PerParcelOverrideErrorsNameTheParcel) {
  std::string dir = test::temp_dir("config_override_errors");
  std::ofstream(dir + "/zone.toml") << read(default_file())
                                    << "\n[valuation.parcels.\"P-7\"]\nzone = \"ZNT-X\"\n";
  expect_error(dir + "/zone.toml", "valuation.parcels.P-7.zone", "ZNT-X");
  std::ofstream(dir + "/key.toml") << read(default_file())
                                   << "\n[valuation.parcels.\"P-7\"]\nfloors = 2\n";
  expect_error(dir + "/key.toml", "valuation.parcels.P-7.floors", "unknown key");
  std::ofstream(dir + "/age.toml") << read(default_file())
                                   << "\n[valuation.parcels.\"P-7\"]\nage_years = -1\n";
  expect_error(dir + "/age.toml", "valuation.parcels.P-7.age_years", "must be >= 0");
}

// A fiscal setting a file leaves out is off, never inherited from the built-in
// defaults; reconstruction settings left out keep theirs.
TEST(Config, KeysLeftOut) {
  std::string text = read(default_file());
  text = std::regex_replace(text, std::regex("\ndefault_quality = [^\n]*"), "");
  text = std::regex_replace(text, std::regex("\n\\[valuation.quality_factor\\]\n([^\n]*=[^\n]*\n)*"), "\n");
  text = std::regex_replace(text, std::regex("\nstorey_height_m = [^\n]*"), "");
  std::string path = test::temp_dir("config_left_out") + "/c.toml";
  std::ofstream(path) << text;
  Config c = load_config(path);
  EXPECT_TRUE(c.valuation.quality_factor.empty());
  EXPECT_TRUE(c.valuation.default_quality.empty());
  EXPECT_DOUBLE_EQ(c.reconstruction.storey_height_m, default_config().reconstruction.storey_height_m);
  expect_error(variant("no_currency", "\ncurrency = [^\n]*", ""), "valuation.currency", "missing");
}
