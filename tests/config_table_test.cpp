// The parameter table drives the parser, the documented default file and the
// fingerprint that goes into the resume key: these tests hold them together.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <nlohmann/json.hpp>

#include "core/config/config.h"
#include "core/config/parameters.h"
#include "tests/test_support.h"

using namespace c3d;
using nlohmann::json;

namespace {

std::string default_file() { return std::string(C3D_SOURCE_DIR) + "/config/cadastre3d.toml"; }

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string write(const std::string& dir, const std::string& text) {
  std::string path = test::temp_dir(dir) + "/c.toml";
  std::ofstream(path) << text;
  return path;
}

// Another value of the same kind, within the parameter's range where it has one.
json changed(const Parameter& p, json v) {
  switch (p.kind) {
    case Kind::Integer: return v.get<int>() + 1;
    case Kind::Real: {
      double x = v.get<double>();
      return x + 0.125 <= p.range.max ? x + 0.125 : x - 0.125;
    }
    case Kind::Boolean: return !v.get<bool>();
    case Kind::Text: return v.get<std::string>() + "x";
    case Kind::Choice:
      for (const auto& c : p.range.names)
        if (c != v.get<std::string>()) return c;
      break;
    case Kind::ClassList: v.push_back(99); return v;
    case Kind::NumberMap:
      if (v.empty()) v["extra"] = 1.0;
      else v.begin().value() = v.begin().value().get<double>() + 1.0;
      return v;
    case Kind::ParcelOverrides: v["P-1"] = {{"zone", "ZNT-A"}}; return v;
  }
  ADD_FAILURE() << "no other value for " << p.key;
  return v;
}

}  // namespace

TEST(ConfigTable, EveryParameterIsDocumented) {
  ASSERT_FALSE(parameter_table().empty());
  for (const Parameter& p : parameter_table()) {
    EXPECT_FALSE(p.doc.empty()) << p.key;
    EXPECT_EQ(p.doc.find('\n'), std::string::npos) << p.key << ": doc is one line";
    EXPECT_FALSE(p.unit.empty()) << p.key << ": unit, or \"-\"";
    EXPECT_NE(std::find(kStages.begin(), kStages.end(), p.stage), kStages.end())
        << p.key << ": stage '" << p.stage << "'";
    EXPECT_FALSE(describe_range(p).empty()) << p.key;
    EXPECT_FALSE(section_of(p.key).empty()) << p.key << ": every key sits in a section";
  }
}

TEST(ConfigTable, KeysAreUnique) {
  std::set<std::string> seen;
  for (const Parameter& p : parameter_table()) EXPECT_TRUE(seen.insert(p.key).second) << p.key;
}

TEST(ConfigTable, DefaultFileIsTheGeneratedText) {
  const std::string generated = default_config_toml();
  if (read(default_file()) != generated) {
    std::string fresh = test::temp_dir("generated") + "/cadastre3d.toml";
    std::ofstream(fresh) << generated;
    FAIL() << "config/cadastre3d.toml differs from the parameter table; if the table is right:\n"
           << "  cp " << fresh << " " << default_file();
  }
}

TEST(ConfigTable, GeneratedFileLoadsAsTheDefaults) {
  Config f = load_config(write("generated", default_config_toml()));
  EXPECT_EQ(effective_config_json(f), effective_config_json(default_config()));
  EXPECT_EQ(config_fingerprint(f), config_fingerprint(default_config()));
}

TEST(ConfigTable, EffectiveJsonHoldsEveryParameterWithoutThePath) {
  const json j = effective_config_json(load_config(default_file()));
  for (const Parameter& p : parameter_table()) {
    std::string pointer = "/" + p.key;
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    EXPECT_TRUE(j.contains(json::json_pointer(pointer))) << p.key;
  }
  EXPECT_EQ(j.dump().find("cadastre3d.toml"), std::string::npos);
  // The keys the resume key used to miss (issue 33).
  EXPECT_EQ(j["reconstruction"]["outlier_neighbours"], 12);
  EXPECT_EQ(j["reconstruction"]["outlier_std"], 2.5);
  EXPECT_EQ(j["classes"]["roof"], json::array({6}));
  EXPECT_EQ(j["reconstruction"]["optimize"], false);
  EXPECT_TRUE(j["valuation"]["unit_cost"]["roof"].is_number());
}

// No parameter can be left out of the resume key: changing any one entry of
// the table changes the fingerprint, but for [batch], which changes no result
// (how many parcels a chunk holds), so that a store resumes under any.
TEST(ConfigTable, EveryParameterChangesTheFingerprint) {
  const Config base = default_config();
  const std::string fingerprint = config_fingerprint(base);
  for (const Parameter& p : parameter_table()) {
    Config c = base;
    const json other = changed(p, p.field.get(base));
    p.field.set(c, other);
    EXPECT_EQ(p.field.get(c), other) << p.key << ": the accessor reads what it wrote";
    if (p.key.rfind("batch.", 0) == 0) EXPECT_EQ(config_fingerprint(c), fingerprint) << p.key;
    else EXPECT_NE(config_fingerprint(c), fingerprint) << p.key;
  }
}

TEST(ConfigTable, EffectiveOptimizeSettingIsFingerprinted) {
  Config on = default_config();
  on.reconstruction.optimize = true;  // as the batch's --optimize sets it
  EXPECT_NE(config_fingerprint(on), config_fingerprint(default_config()));
  Config vulkan = on;
  vulkan.reconstruction.optimize_device = "vulkan";  // as --device sets it
  EXPECT_NE(config_fingerprint(vulkan), config_fingerprint(on));
}

TEST(ConfigTable, SameSettingsFromAnotherPathOrLayoutSameFingerprint) {
  const std::string text = read(default_file());
  Config a = load_config(write("a", text));
  Config b = load_config(write("b", text));
  EXPECT_NE(a.source, b.source);
  EXPECT_EQ(config_fingerprint(a), config_fingerprint(b));
  // Comments, order and integer-or-real spelling are not settings.
  const char* reordered =
      "[valuation]\ncurrency = \"IDR\"\nbuilding_age_years = 10.0\n"
      "depreciation_per_year = 0.015\nmax_depreciation = 0.5\n"
      "default_zone = \"ZNT-B\"  # a comment\ndefault_quality = \"permanent\"\n"
      "[valuation.tax]\nnjoptkp = 10000000\nrate = 0.001\n"
      "[valuation.land_price]\nZNT-C = 2500000\nZNT-B = 4e6\nZNT-A = 6500000\n"
      "[valuation.quality_factor]\ntemporary = 0.5\nsemi_permanent = 0.75\npermanent = 1\n"
      "[valuation.unit_cost]\nouter_ceiling = 175000\nground = 350000\n"
      "party_wall = 200000\nwall = 400000\nroof = 550000\n";
  Config c = load_config(write("c", reordered));
  EXPECT_EQ(config_fingerprint(c), config_fingerprint(a));
}

TEST(ConfigTable, AnyConfigRoundTripsThroughItsToml) {
  Config c = default_config();
  c.classes.wall = {64, 65};
  c.reconstruction.outlier_std = 3.25;
  c.reconstruction.optimize_device = "cpu";
  c.valuation.land_price["ZNT D/\"x\""] = 1234.5;
  c.valuation.parcels["10.25.00.00.00123"].zone = "ZNT-A";
  c.valuation.parcels["10.25.00.00.00123"].age_years = 25;
  c.valuation.parcels["P-2"].quality = "temporary";
  Config back = load_config(write("roundtrip", config_toml(c)));
  EXPECT_EQ(effective_config_json(back), effective_config_json(c));
}
