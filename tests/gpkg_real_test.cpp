// The GeoPackage's GIS layers on whole batches (issue 36): two generated sample
// towns and the real Cimahi data (skipped when ../shared/data/cimahi is absent).
// Every 2D geometry is valid by GEOS (OGR IsValid), and what a GIS sums over
// the layers equals the store's element totals within 0.5 %.
#include <gdal.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <map>
#include <memory>

#include "cadastre/store/store.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

constexpr double kSumTolerance = 0.005;  // the "within 0.5 %"

struct DataRun {
  std::string store, log;
  int rc = -1;
};

// Each data set's batch runs once for all tests of this file.
const DataRun& run(const std::string& data) {
  static std::map<std::string, DataRun> done;
  auto it = done.find(data);
  if (it != done.end()) return it->second;
  const std::string dir = test::temp_dir(data);
  std::string cloud, parcels, dtm;
  DataRun r;
  if (data == "cimahi") {
    const std::string d = test::cimahi_dir();
    cloud = d + "/cimahi.las", parcels = d + "/parcels.shp", dtm = d + "/dtm.tif";
  } else {
    const std::string seed = data.substr(4);  // "town<seed>"
    EXPECT_EQ(test::run_cli("sample --out " + dir + "/town --parcels 24 --seed " + seed, &r.log), 0) << r.log;
    cloud = dir + "/town/cloud.las", parcels = dir + "/town/parcels.gpkg", dtm = dir + "/town/dtm.tif";
  }
  r.rc = test::run_cli("batch --quiet --cloud " + cloud + " --parcels " + parcels + " --dtm " + dtm + " --out " +
                           dir + "/out --formats cityjson",
                       &r.log);
  r.store = dir + "/out/cadastre.gpkg";
  return done[data] = r;
}

using Dataset = std::unique_ptr<GDALDataset, void (*)(GDALDataset*)>;
Dataset open_ogr(const std::string& path) {
  GDALAllRegister();
  return Dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY),
                 [](GDALDataset* d) { GDALClose(d); });
}

struct LayerSum {
  long features = 0;
  double area = 0;
  std::vector<std::string> invalid;  // "<layer> fid <n>"
};

LayerSum scan(GDALDataset& ds, const char* name) {
  LayerSum s;
  OGRLayer* l = ds.GetLayerByName(name);
  EXPECT_NE(l, nullptr) << name;
  if (!l) return s;
  EXPECT_EQ(l->GetGeomType(), wkbMultiPolygon) << name;  // 2D
  for (auto& f : *l) {
    ++s.features;
    const OGRGeometry* g = f->GetGeometryRef();
    if (!g) continue;
    if (!g->IsValid()) s.invalid.push_back(std::string(name) + " fid " + std::to_string(f->GetFID()));
    s.area += g->toMultiPolygon()->get_Area();
  }
  return s;
}

class GpkgReal : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (GetParam() == "cimahi") C3D_REQUIRE_CIMAHI();
    const DataRun& r = run(GetParam());
    ASSERT_EQ(r.rc, 0) << r.log;
  }
};

}  // namespace

TEST_P(GpkgReal, Every2DGeometryIsValidAndGisSumsEqualTheStore) {
  const DataRun& r = run(GetParam());
  const BatchModel m = load_batch_model(r.store);
  long buildings = 0, roofs = 0;
  double ground = 0, roof_plan = 0;
  for (const ParcelResult& p : m.results)
    for (const Building& b : p.buildings) {
      ++buildings;
      for (const Element& e : b.elements) {
        if (e.type == ElementType::Ground) ground += e.area;
        if (e.type == ElementType::Roof) roof_plan += e.plan_area, ++roofs;
      }
    }
  ASSERT_GT(buildings, 0);
  auto ds = open_ogr(r.store);
  ASSERT_TRUE(ds);
  const LayerSum footprints = scan(*ds, "building_footprint"), parts = scan(*ds, "roof_part"),
                 parcels = scan(*ds, "parcel"), units = scan(*ds, "la_spatialunit");
  for (const LayerSum* s : {&footprints, &parts, &parcels, &units})
    EXPECT_TRUE(s->invalid.empty()) << s->invalid.size() << " invalid, first: " << s->invalid[0];
  EXPECT_EQ(footprints.features, buildings);
  EXPECT_EQ(parts.features, roofs);
  EXPECT_EQ(parcels.features, long(m.parcels.size()));
  EXPECT_NEAR(footprints.area, ground, kSumTolerance * ground) << "GIS footprint sum against the ground elements";
  EXPECT_NEAR(parts.area, roof_plan, kSumTolerance * roof_plan) << "GIS roof plan sum against the roof elements";
  std::cout << GetParam() << ": " << buildings << " footprints " << footprints.area << " m2 (ground " << ground
            << "), " << roofs << " roof parts " << parts.area << " m2 (plan " << roof_plan << ")\n";
}

TEST_P(GpkgReal, ParcelLayerKeepsTheInputLayersFields) {
  auto ds = open_ogr(run(GetParam()).store);
  ASSERT_TRUE(ds);
  OGRLayer* l = ds->GetLayerByName("parcel");
  ASSERT_NE(l, nullptr);
  const OGRFeatureDefn* d = l->GetLayerDefn();
  // The parcel layers' own fields (both carry these; Cimahi has more).
  for (const char* field : {"NIB", "TIPEHAK", "LUASTERTUL"}) EXPECT_GE(d->GetFieldIndex(field), 0) << field;
  if (GetParam() == "cimahi") {
    EXPECT_GE(d->GetFieldIndex("KECAMATAN"), 0);
  }
  for (const char* field : {"njop", "tax", "njop_per_m2", "status"}) EXPECT_GE(d->GetFieldIndex(field), 0) << field;
}

INSTANTIATE_TEST_SUITE_P(Data, GpkgReal, ::testing::Values("town1", "town7", "cimahi"));
