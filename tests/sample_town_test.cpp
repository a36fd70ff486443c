// The sample town: exact truth against closed-form formulas, closed solids,
// determinism, points on the faces, files readable through GDAL, the CLI.
#include <Eigen/Geometry>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/geometry/geometry.h"
#include "core/io/point_io.h"
#include "core/synthetic/sample_town.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

constexpr double kTol = 1e-6;
const double kDeg = M_PI / 180;

BuildingParams params(SampleLayout l) {
  BuildingParams p;
  p.layout = l;
  p.length = 12, p.width = 8, p.eave_height = 3.2, p.pitch_deg = 30, p.overhang = 0.5;
  return p;
}

void expect_solid_ok(const TruthBuilding& tb) {
  std::string why;
  EXPECT_TRUE(shell_is_closed(tb.model.solid, &why)) << tb.model.id << ": " << why;
  EXPECT_TRUE(tb.model.solid_valid) << tb.model.id << ": " << tb.model.solid_problem;
  EXPECT_GT(tb.model.volume, 0) << tb.model.id;
}

SampleOptions small_town(std::uint64_t seed = 7) {
  SampleOptions o;
  o.seed = seed;
  o.parcels = 20;
  o.roof_density = 10;
  o.wall_density = 8;
  return o;
}

}  // namespace

TEST(SampleTruth, GableMatchesClosedForm) {
  auto bs = make_truth_buildings(params(SampleLayout::Gable));
  ASSERT_EQ(bs.size(), 1u);
  const double L = 12, W = 8, o = 0.5, he = 3.2, t = std::tan(30 * kDeg), c = std::cos(30 * kDeg);
  BuildingTotals s = totals(bs[0].model);
  EXPECT_NEAR(s.roof, 2 * (L + 2 * o) * (W / 2 + o) / c, kTol);
  EXPECT_NEAR(s.roof_plan, (L + 2 * o) * (W + 2 * o), kTol);
  EXPECT_NEAR(s.wall, 2 * L * he + 2 * (W * he + W * W * t / 4), kTol);
  EXPECT_NEAR(s.ground, L * W, kTol);
  EXPECT_NEAR(s.outer_ceiling, (L + 2 * o) * (W + 2 * o) - L * W, kTol);
  EXPECT_DOUBLE_EQ(s.party_wall, 0);
  EXPECT_EQ(s.roof_planes, 2);
  EXPECT_NEAR(bs[0].model.volume, L * W * he + L * W * W * t / 4, kTol);  // box + prism
  EXPECT_NEAR(bs[0].model.ridge_height, he + W / 2 * t, kTol);
  EXPECT_NEAR(bs[0].model.eave_height, he - o * t, kTol);
  EXPECT_NEAR(bs[0].wall_top_height, he, kTol);
  EXPECT_NEAR(signed_area(bs[0].footprint), L * W, kTol);
  expect_solid_ok(bs[0]);
}

TEST(SampleTruth, HipMatchesClosedForm) {
  auto bs = make_truth_buildings(params(SampleLayout::Hip));
  const double L = 12, W = 8, o = 0.5, he = 3.2, t = std::tan(30 * kDeg), c = std::cos(30 * kDeg);
  BuildingTotals s = totals(bs[0].model);
  EXPECT_NEAR(s.roof, (L + 2 * o) * (W + 2 * o) / c, kTol);  // equal pitch: plan / cos
  EXPECT_NEAR(s.wall, 2 * (L + W) * he, kTol);
  EXPECT_EQ(s.roof_planes, 4);
  // Hip roof over L x W: integral of t * distance to the outline = t W^2 (3L - W) / 12.
  EXPECT_NEAR(bs[0].model.volume, L * W * he + t * W * W * (3 * L - W) / 12, kTol);
  EXPECT_NEAR(bs[0].model.ridge_height, he + W / 2 * t, kTol);
  expect_solid_ok(bs[0]);
}

TEST(SampleTruth, ShedAndFlatMatchClosedForm) {
  auto p = params(SampleLayout::Shed);
  p.pitch_deg = 10;
  auto shed = make_truth_buildings(p);
  const double L = 12, W = 8, o = 0.5, he = 3.2, t = std::tan(10 * kDeg), c = std::cos(10 * kDeg);
  BuildingTotals s = totals(shed[0].model);
  EXPECT_NEAR(s.roof, (L + 2 * o) * (W + 2 * o) / c, kTol);
  EXPECT_NEAR(s.wall, L * he + L * (he + W * t) + 2 * W * (2 * he + W * t) / 2, kTol);
  EXPECT_NEAR(shed[0].model.volume, L * W * (he + W * t / 2), kTol);
  EXPECT_NEAR(shed[0].model.ridge_height, he + (W + o) * t, kTol);
  EXPECT_EQ(s.roof_planes, 1);
  expect_solid_ok(shed[0]);

  auto flat = make_truth_buildings(params(SampleLayout::Flat));
  s = totals(flat[0].model);
  EXPECT_NEAR(s.roof, (L + 2 * o) * (W + 2 * o), kTol);
  EXPECT_NEAR(s.wall, 2 * (L + W) * he, kTol);
  EXPECT_NEAR(flat[0].model.volume, L * W * he, kTol);
  EXPECT_NEAR(flat[0].model.ridge_height, flat[0].model.eave_height, kTol);
  expect_solid_ok(flat[0]);
}

TEST(SampleTruth, CrossGableMatchesClosedForm) {
  auto p = params(SampleLayout::CrossGable);
  p.wing_length = 5;
  auto bs = make_truth_buildings(p);
  ASSERT_EQ(bs.size(), 1u);
  const double L = 12, W = 8, Lw = 5, o = 0.5, he = 3.2, t = std::tan(30 * kDeg),
               c = std::cos(30 * kDeg);
  BuildingTotals s = totals(bs[0].model);
  double plan = (L + 2 * o) * (W + 2 * o) + (W + 2 * o) * Lw;
  EXPECT_NEAR(s.roof_plan, plan, kTol);
  EXPECT_NEAR(s.roof, plan / c, kTol);  // one pitch everywhere
  EXPECT_NEAR(s.ground, L * W + W * Lw, kTol);
  // L-shaped outline times eave height plus three gable triangles.
  EXPECT_NEAR(s.wall, 2 * (L + W + Lw) * he + 3 * W * W * t / 4, kTol);
  EXPECT_EQ(s.roof_planes, 4);
  // Two prisms plus the wing roof rising above the main roof between the valleys.
  EXPECT_NEAR(bs[0].model.volume,
              he * (L * W + W * Lw) + t * W * W * (L + Lw) / 4 + t * W * W * W / 24, kTol);
  EXPECT_EQ(bs[0].footprint.size(), 6u);
  expect_solid_ok(bs[0]);
}

TEST(SampleTruth, TwoLevelHasStepWall) {
  auto p = params(SampleLayout::TwoLevel);
  p.eave_height = 6, p.annex_length = 4, p.annex_inset = 1, p.annex_height = 3;
  auto bs = make_truth_buildings(p);
  const double L = 12, W = 8, o = 0.5, he = 6, t = std::tan(30 * kDeg), c = std::cos(30 * kDeg);
  const double La = 4, Wa = 6, ha = 3;
  BuildingTotals s = totals(bs[0].model);
  EXPECT_NEAR(s.roof, 2 * (L + o) * (W / 2 + o) / c + (La + o) * (Wa + 2 * o), kTol);
  // Main walls (the part behind the annex counted as the step wall above it) + annex walls.
  EXPECT_NEAR(s.wall, 2 * (W * he + W * W * t / 4) + 2 * L * he + 2 * La * ha, kTol);
  EXPECT_NEAR(s.ground, L * W + La * Wa, kTol);
  EXPECT_NEAR(bs[0].model.volume, L * W * he + L * W * W * t / 4 + La * Wa * ha, kTol);
  EXPECT_EQ(s.roof_planes, 3);
  EXPECT_NEAR(bs[0].wall_top_height, ha, kTol);
  EXPECT_EQ(bs[0].footprint.size(), 8u);
  expect_solid_ok(bs[0]);
}

TEST(SampleTruth, RowHousesSharePartyWalls) {
  auto p = params(SampleLayout::RowHouse);
  p.house_widths = {6, 7, 6.5};
  auto bs = make_truth_buildings(p);
  ASSERT_EQ(bs.size(), 3u);
  const double W = 8, o = 0.5, he = 3.2, t = std::tan(30 * kDeg), c = std::cos(30 * kDeg);
  const double gable = W * he + W * W * t / 4;
  double roof_sum = 0;
  for (int k = 0; k < 3; ++k) {
    const double w = p.house_widths[k];
    bool end = k != 1;
    BuildingTotals s = totals(bs[k].model);
    EXPECT_NEAR(s.party_wall, (end ? 1 : 2) * gable, kTol) << k;
    EXPECT_NEAR(s.wall, 2 * w * he + (end ? gable : 0), kTol) << k;
    EXPECT_NEAR(s.roof, 2 * (w + (end ? o : 0)) * (W / 2 + o) / c, kTol) << k;
    EXPECT_NEAR(bs[k].model.volume, w * gable, kTol) << k;
    EXPECT_EQ(bs[k].attached_to.size(), end ? 1u : 2u);
    roof_sum += s.roof;
    expect_solid_ok(bs[k]);
  }
  EXPECT_NEAR(roof_sum, 2 * (19.5 + 2 * o) * (W / 2 + o) / c, kTol);
}

TEST(SampleTown, DeterministicPerSeed) {
  auto a = make_sample_town(small_town(7));
  auto b = make_sample_town(small_town(7));
  EXPECT_EQ(truth_json(a), truth_json(b));
  ASSERT_EQ(a.cloud.points.size(), b.cloud.points.size());
  EXPECT_TRUE(a.cloud.points == b.cloud.points);
  EXPECT_EQ(a.cloud.classes, b.cloud.classes);
  auto c = make_sample_town(small_town(8));
  EXPECT_NE(truth_json(a), truth_json(c));
}

TEST(SampleTown, EveryLayoutPresentAndTruthConsistent) {
  auto town = make_sample_town(small_town());
  std::set<std::string> seen;
  int party = 0;
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    seen.insert(to_string(town.layouts[i]));
    if (town.layouts[i] == SampleLayout::Empty) {
      EXPECT_TRUE(town.truth[i].empty());
    }
    for (const auto& tb : town.truth[i]) {
      expect_solid_ok(tb);
      BuildingTotals s = totals(tb.model);
      EXPECT_NEAR(s.ground, std::abs(signed_area(tb.footprint)), 1e-6) << tb.model.id;
      EXPECT_NEAR(s.outer_ceiling, s.roof_plan - s.ground, 1e-6) << tb.model.id;
      EXPECT_GE(s.roof + 1e-9, s.roof_plan);
      EXPECT_GT(tb.model.ridge_height, 2.5);
      if (s.party_wall > 0) ++party;
      // Overhang 0.3-0.8 m; ground level from the DTM.
      EXPECT_GE(tb.params.overhang, 0.3);
      EXPECT_LE(tb.params.overhang, 0.8);
      Vec2 c = town.frame.to_world(tb.footprint.front());
      EXPECT_NEAR(tb.ground_level, town.dtm.height_at(c.x(), c.y()), 2.0);
    }
  }
  for (const char* l : {"gable", "hip", "cross_gable", "shed", "flat", "two_level", "row_gable", "empty"})
    EXPECT_TRUE(seen.count(l)) << l;
  EXPECT_GE(party, 2);
  // Coordinates of real UTM magnitude.
  EXPECT_GT(town.parcels[0].shape[0].outer[0].x(), 700000);
  EXPECT_GT(town.parcels[0].shape[0].outer[0].y(), 9000000);
}

TEST(SampleTown, PointsLieOnTheFaces) {
  auto opt = small_town();
  auto town = make_sample_town(opt);
  ASSERT_FALSE(town.cloud.points.empty());
  std::vector<const Face*> faces;
  for (const auto& p : town.truth)
    for (const auto& tb : p)
      for (const auto& e : tb.model.elements)
        if (e.type == ElementType::Roof || e.type == ElementType::Wall)
          for (const auto& f : e.faces) faces.push_back(&f);
  auto distance = [&](const Vec3& q) {
    double best = 1e9;
    for (const Face* f : faces) {
      Vec3 n = unit_normal(*f);
      double d = std::abs(n.dot(q - f->ring[0]));
      if (d >= best) continue;
      bool inside = true;  // convex faces: within 0.15 m of every edge line
      for (size_t i = 0, k = f->ring.size(); i < k && inside; ++i) {
        Vec3 a = f->ring[i], b = f->ring[(i + 1) % k];
        Vec3 in = n.cross(b - a).normalized();
        inside = in.dot(q - a) > -0.15;
      }
      if (inside) best = d;
    }
    return best;
  };
  long n = 0, near = 0, walls = 0, outliers = 0, roofs = 0;
  for (size_t i = 0; i < town.cloud.points.size(); ++i) {
    int cls = town.cloud.classes[i];
    if (cls == 6) ++roofs;
    if (cls == 64) ++walls;
    if (town.point_tags[i] == PointTag::Outlier) ++outliers;
    if (cls == 2 || town.point_tags[i] != PointTag::Surface) continue;
    double sigma = cls == 6 ? opt.roof_noise : opt.wall_noise;
    ++n;
    if (distance(town.frame.to_local(town.cloud.points[i])) < 5 * sigma) ++near;
  }
  EXPECT_GT(roofs, 1000);
  EXPECT_GT(walls, 1000);
  EXPECT_GT(outliers, 0);
  EXPECT_GE(double(near) / n, 0.999) << near << " of " << n;
  // Some walls are occluded, party walls never have points.
  int occluded = 0;
  for (const auto& p : town.truth)
    for (const auto& tb : p)
      for (const auto& e : tb.model.elements) {
        if (e.type == ElementType::Wall && e.support_points == 0) ++occluded;
        if (e.type == ElementType::PartyWall) {
          EXPECT_EQ(e.support_points, 0);
        }
      }
  EXPECT_GT(occluded, 0);
}

TEST(SampleTown, FilesReadableThroughGdal) {
  GDALAllRegister();
  auto town = make_sample_town(small_town());
  for (auto fmt : {ParcelFormat::GeoPackage, ParcelFormat::GeoJson}) {
    std::string dir = test::temp_dir(fmt == ParcelFormat::GeoJson ? "sample_geojson" : "sample_gpkg");
    SampleFiles f = write_sample_town(town, dir, fmt);
    std::unique_ptr<GDALDataset> vec(
        GDALDataset::Open(f.parcels.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
    ASSERT_TRUE(vec) << f.parcels;
    OGRLayer* layer = vec->GetLayer(0);
    ASSERT_TRUE(layer);
    EXPECT_EQ(layer->GetFeatureCount(), long(town.parcels.size()));
    const OGRSpatialReference* srs = layer->GetSpatialRef();
    ASSERT_TRUE(srs);
    EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "32748");
    for (const char* field : {"NIB", "TIPEHAK", "LUASTERTUL"})
      EXPECT_GE(layer->GetLayerDefn()->GetFieldIndex(field), 0) << field;
    layer->ResetReading();
    std::unique_ptr<OGRFeature> feat(layer->GetNextFeature());
    ASSERT_TRUE(feat);
    EXPECT_EQ(std::string(feat->GetFieldAsString("NIB")), town.parcels[0].id);
    double polygon_area = feat->GetGeometryRef()->toPolygon()->get_Area();
    EXPECT_NEAR(polygon_area, area(town.parcels[0].shape), 1e-3);
    EXPECT_NE(feat->GetFieldAsDouble("LUASTERTUL"), polygon_area);
  }
  std::string dir = test::temp_dir("sample_gpkg");
  SampleFiles f = write_sample_town(town, dir);
  std::unique_ptr<GDALDataset> dtm(GDALDataset::Open(f.dtm.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  ASSERT_TRUE(dtm);
  EXPECT_EQ(dtm->GetRasterXSize(), town.dtm.nx);
  double gt[6];
  ASSERT_EQ(dtm->GetGeoTransform(gt), CE_None);
  EXPECT_DOUBLE_EQ(gt[1], 1.0);
  int has_nodata = 0;
  double nodata = dtm->GetRasterBand(1)->GetNoDataValue(&has_nodata);
  EXPECT_TRUE(has_nodata);
  std::vector<float> z(size_t(town.dtm.nx) * town.dtm.ny);
  ASSERT_EQ(dtm->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, town.dtm.nx, town.dtm.ny, z.data(),
                                            town.dtm.nx, town.dtm.ny, GDT_Float32, 0, 0),
            CE_None);
  long holes = 0;
  for (size_t i = 0; i < z.size(); ++i) {
    if (z[i] == nodata) {
      ++holes;
    } else {
      EXPECT_EQ(z[i], town.dtm.z[i]);
    }
  }
  EXPECT_GT(holes, 100);
  // truth.json parses and lists every parcel.
  std::ifstream in(f.truth);
  auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["parcels"].size(), town.parcels.size());
  EXPECT_EQ(j["parcels"][0]["parcel_id"], town.parcels[0].id);
  // The cloud round-trips through the project's LAS reader.
  ASSERT_FALSE(f.cloud.empty());
  PointCloud back = read_point_cloud(f.cloud);
  ASSERT_EQ(back.points.size(), town.cloud.points.size());
  EXPECT_EQ(back.classes, town.cloud.classes);
  EXPECT_NEAR(back.points[0].x(), town.cloud.points[0].x(), 0.002);
  EXPECT_FALSE(back.crs_wkt.empty());
}

TEST(SampleTown, CliWritesTheTown) {
  std::string out;
  EXPECT_EQ(test::run_cli("sample --help", &out), 0) << out;
  EXPECT_NE(out.find("--parcels"), std::string::npos);
  std::string dir = test::temp_dir("sample_cli");
  ASSERT_EQ(test::run_cli("sample --out " + dir + " --parcels 12 --seed 3 --density 5", &out), 0) << out;
  for (const char* name : {"parcels.gpkg", "dtm.tif", "cloud.las", "truth.json"})
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir) / name)) << name;
  EXPECT_NE(test::run_cli("sample --out " + dir + " --format shp", &out), 0);
}
