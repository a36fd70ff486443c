// CRS identification, comparison, reprojection and reconciliation of inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "core/io/crs.h"
#include "core/error.h"
#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"

namespace c3d {
namespace {

// What the Cimahi LAS carries: ESRI-flavoured WKT without an authority code.
const char* kEsriUtm48S =
    "PROJCS[\"WGS_1984_UTM_Zone_48S\",GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\","
    "SPHEROID[\"WGS_1984\",6378137.0,298.257223563]],PRIMEM[\"Greenwich\",0.0],"
    "UNIT[\"Degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
    "PARAMETER[\"False_Easting\",500000.0],PARAMETER[\"False_Northing\",10000000.0],"
    "PARAMETER[\"Central_Meridian\",105.0],PARAMETER[\"Scale_Factor\",0.9996],"
    "PARAMETER[\"Latitude_Of_Origin\",0.0],UNIT[\"Meter\",1.0]]";

TEST(Crs, EpsgOfOgcEsriAndEmpty) {
  EXPECT_EQ(epsg_of(wkt_from_epsg(32748)), 32748);
  EXPECT_EQ(epsg_of(kEsriUtm48S), 32748);
  EXPECT_EQ(epsg_of(wkt_from_epsg(4326)), 4326);
  EXPECT_EQ(epsg_of(""), 0);
  EXPECT_EQ(epsg_of("LOCAL_CS[\"site grid\",UNIT[\"metre\",1]]"), 0);
}

TEST(Crs, SameCrsIgnoresDialect) {
  EXPECT_TRUE(same_crs(wkt_from_epsg(32748), kEsriUtm48S));
  EXPECT_FALSE(same_crs(wkt_from_epsg(32748), wkt_from_epsg(32749)));
  EXPECT_FALSE(same_crs(wkt_from_epsg(32748), ""));
  EXPECT_TRUE(same_crs("", ""));
}

TEST(Crs, DisplayName) {
  EXPECT_EQ(crs_display_name(wkt_from_epsg(32748)), "WGS 84 / UTM zone 48S (EPSG:32748)");
  EXPECT_EQ(crs_display_name(""), "(none)");
}

TEST(Crs, ReprojectUsesEastingNorthingOrderAndRoundTrips) {
  const std::string utm = wkt_from_epsg(32748), wgs84 = wkt_from_epsg(4326);
  std::vector<Vec3> pts = {{781850.0, 9240000.0, 790.0}, {781900.5, 9240050.25, 785.0}};
  std::vector<Vec3> geo = pts;
  reproject_points(geo, utm, wgs84, "test");
  // Cimahi: longitude ~107.5 E first, latitude ~6.9 S second (traditional GIS order).
  EXPECT_NEAR(geo[0].x(), 107.55, 0.1);
  EXPECT_NEAR(geo[0].y(), -6.87, 0.1);
  reproject_points(geo, wgs84, utm, "test");
  for (size_t i = 0; i < pts.size(); ++i) EXPECT_LT((geo[i] - pts[i]).head<2>().norm(), 1e-6);

  MultiPolygon2 shape = {{{{781850, 9240000}, {781860, 9240000}, {781860, 9240010}}, {}}};
  MultiPolygon2 g = reproject(shape, utm, wgs84, "parcels.shp");
  ASSERT_EQ(g.size(), 1u);
  EXPECT_NEAR(g[0].outer[1].x() - g[0].outer[0].x(), 10.0 / 110000.0, 1e-5);  // ~10 m in degrees
}

TEST(Crs, ReconcileAssumesReprojectsAndRejects) {
  ParcelLayer parcels;
  parcels.source = "parcels.gpkg";
  parcels.crs_wkt = wkt_from_epsg(32748);
  PointCloud none, other, same;
  none.source = "none.ply";
  none.points = {{781850, 9240000, 790}};
  other.source = "geo.las";
  other.crs_wkt = wkt_from_epsg(4326);
  other.points = {{107.55, -6.87, 790}};
  same.source = "same.las";
  same.crs_wkt = kEsriUtm48S;
  same.points = {{781850, 9240000, 790}};
  std::vector<PointCloud> clouds = {none, other, same};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("none.ply: no CRS; assumed"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("geo.las: reprojected"), std::string::npos) << r.warnings[1];
  EXPECT_EQ(clouds[0].points[0], none.points[0]);
  EXPECT_GT(clouds[1].points[0].x(), 700000);  // now UTM metres
  EXPECT_GT(clouds[1].points[0].y(), 9000000);
  EXPECT_EQ(clouds[2].points[0], same.points[0]);  // same CRS, other dialect: untouched
  for (const PointCloud& c : clouds) EXPECT_TRUE(same_crs(c.crs_wkt, parcels.crs_wkt));
}

TEST(Crs, ReconcileImpossibleReprojectionNamesFileAndBothCrs) {
  ParcelLayer parcels;
  parcels.source = "parcels.shp";
  parcels.crs_wkt = wkt_from_epsg(32748);
  PointCloud local;
  local.source = "site_grid.las";
  local.crs_wkt = "LOCAL_CS[\"site grid\",UNIT[\"metre\",1]]";
  local.points = {{10, 20, 30}};
  std::vector<PointCloud> clouds = {local};
  try {
    reconcile_crs(parcels, clouds);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("site_grid.las"), std::string::npos) << m;
    EXPECT_NE(m.find("site grid"), std::string::npos) << m;
    EXPECT_NE(m.find("EPSG:32748"), std::string::npos) << m;
    EXPECT_NE(m.find("cannot reproject"), std::string::npos) << m;
  }
}

// A one-parcel GeoJSON-like layer in WGS 84 (whatever its coordinates are).
ParcelLayer wgs84_layer(const MultiPolygon2& shape) {
  ParcelLayer parcels;
  parcels.source = "parcels.geojson";
  parcels.crs_wkt = wkt_from_epsg(4326);
  parcels.parcels.push_back(Parcel{0, "P1", "", kNaN, shape, ""});
  return parcels;
}

// A one-point cloud in Cimahi's UTM zone, with or without its CRS.
PointCloud cimahi_cloud(const std::string& source, bool with_crs) {
  PointCloud cloud;
  cloud.source = source;
  if (with_crs) cloud.crs_wkt = kEsriUtm48S;
  cloud.points = {{781855, 9240005, 790}};
  return cloud;
}

TEST(Crs, ParcelsInDegreesAreMeasuredInTheCloudsMetres) {
  // A GeoJSON layer is WGS 84 by its standard: a 10 m x 10 m Cimahi parcel in
  // degrees goes into the cloud's UTM zone, where its area is 100 m^2 again.
  const std::string utm = wkt_from_epsg(32748), wgs84 = wkt_from_epsg(4326);
  const MultiPolygon2 square = poly::box({781850, 9240000}, {781860, 9240010});
  ParcelLayer parcels = wgs84_layer(reproject(square, utm, wgs84, "test"));
  const PointCloud cloud = cimahi_cloud("cloud.las", true);
  std::vector<PointCloud> clouds = {cloud};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  EXPECT_TRUE(same_crs(r.crs_wkt, utm));
  EXPECT_TRUE(same_crs(parcels.crs_wkt, utm));
  EXPECT_NEAR(area(parcels.parcels[0].shape), 100.0, 1e-3);
  EXPECT_NEAR(parcels.parcels[0].shape[0].outer[0].y(), 9240000, 1e-3);
  EXPECT_EQ(clouds[0].points[0], cloud.points[0]);  // the cloud stays as it is
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("parcels.geojson: reprojected from WGS 84 (EPSG:4326)"), std::string::npos)
      << r.warnings[0];
  EXPECT_TRUE(is_metric(utm));
  EXPECT_FALSE(is_metric(wgs84));
  EXPECT_FALSE(is_metric(wkt_from_epsg(2227)));  // a state plane in US feet
}

TEST(Crs, LayerClaimingDegreesWithMetreCoordinatesTakesTheCloudsCrs) {
  // A GeoJSON in UTM without a "crs" member: GDAL reads it as WGS 84.
  ParcelLayer parcels = wgs84_layer(poly::box({781850, 9240000}, {781860, 9240010}));
  std::vector<PointCloud> clouds = {cimahi_cloud("cloud.las", true)};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  EXPECT_TRUE(same_crs(r.crs_wkt, kEsriUtm48S));
  EXPECT_NEAR(area(parcels.parcels[0].shape), 100.0, 1e-9);  // untouched
  ASSERT_GE(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("not degrees"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("no CRS; assumed"), std::string::npos) << r.warnings[1];
}

TEST(Crs, ParcelsInDegreesWithNoCloudInMetresIsAnError) {
  ParcelLayer parcels = wgs84_layer(poly::box({107.55, -6.87}, {107.5501, -6.8699}));
  std::vector<PointCloud> clouds = {cimahi_cloud("cloud.ply", false)};  // no CRS: it would be taken for degrees
  try {
    reconcile_crs(parcels, clouds);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("parcels.geojson"), std::string::npos) << m;
    EXPECT_NE(m.find("not in metres"), std::string::npos) << m;
    EXPECT_NE(m.find("EPSG:32748"), std::string::npos) << m;  // the UTM zone over the layer
  }
}

// Issue 35: a Web-Mercator layer measured areas 2 % too large at Cimahi.
TEST(CrsPolicy, ArealScaleTellsWebMercatorFromUtm) {
  const double lon = 107.54, lat = -6.87;  // Cimahi
  EXPECT_NEAR(areal_scale_at(wkt_from_epsg(3857), lon, lat), 1.0 / std::pow(std::cos(lat * M_PI / 180), 2), 0.01);
  EXPECT_GT(areal_scale_at(wkt_from_epsg(3857), lon, lat), 1.01);
  EXPECT_NEAR(areal_scale_at(wkt_from_epsg(32748), lon, lat), 1.0, 0.002);
  EXPECT_EQ(areal_scale_at(wkt_from_epsg(4326), lon, lat), 0.0);  // not projected
  EXPECT_EQ(epsg_of(utm_wkt_at(lon, lat)), 32748);
  EXPECT_EQ(epsg_of(utm_wkt_at(5.1, 52.1)), 32631);
  EXPECT_EQ(areas_crs_text(wkt_from_epsg(32748)), "EPSG:32748 (WGS 84 / UTM zone 48S)");
}

// The Cimahi square of 100 m^2 as a layer in `epsg`.
ParcelLayer square_layer(int epsg) {
  const MultiPolygon2 square = poly::box({781850, 9240000}, {781860, 9240010});
  ParcelLayer parcels;
  parcels.source = "parcels.gpkg";
  parcels.crs_wkt = wkt_from_epsg(epsg);
  parcels.parcels.push_back(
      Parcel{0, "P1", "", kNaN, reproject(square, wkt_from_epsg(32748), parcels.crs_wkt, "test"), ""});
  return parcels;
}

TEST(CrsPolicy, WebMercatorLayerIsMeasuredInTheCloudsUtm) {
  ParcelLayer parcels = square_layer(3857);
  EXPECT_GT(area(parcels.parcels[0].shape), 101.0);  // what the layer claims: 1.5 % too much
  std::vector<PointCloud> clouds = {cimahi_cloud("cloud.las", true)};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  EXPECT_EQ(epsg_of(r.crs_wkt), 32748);
  EXPECT_NEAR(area(parcels.parcels[0].shape), 100.0, 0.01);
  EXPECT_EQ(clouds[0].points[0], cimahi_cloud("cloud.las", true).points[0]);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("Pseudo-Mercator"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("off true at the data"), std::string::npos) << r.warnings[0];
}

TEST(CrsPolicy, EverythingInWebMercatorGoesToTheLocalUtmZone) {
  ParcelLayer parcels = square_layer(3857);
  PointCloud cloud = cimahi_cloud("cloud.las", true);
  reproject(cloud, wkt_from_epsg(3857));
  std::vector<PointCloud> clouds = {cloud};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  EXPECT_EQ(epsg_of(r.crs_wkt), 32748);
  EXPECT_NEAR(area(parcels.parcels[0].shape), 100.0, 0.01);
  EXPECT_NEAR(clouds[0].points[0].x(), 781855, 1e-3);
  // A DTM left in Web Mercator is not warped here: the error says how.
  ParcelLayer again = square_layer(3857);
  std::vector<PointCloud> clouds2 = {cloud};
  Dtm dtm;
  dtm.source = "dtm.tif";
  dtm.crs_wkt = wkt_from_epsg(3857);
  try {
    reconcile_crs(again, clouds2, &dtm);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gdalwarp -t_srs EPSG:32748"), std::string::npos) << e.what();
  }
}

TEST(CrsPolicy, DegreesEverywhereGoToTheLocalUtmZoneAndTheUserMayNameOne) {
  ParcelLayer parcels = square_layer(4326);
  PointCloud cloud = cimahi_cloud("cloud.las", true);
  reproject(cloud, wkt_from_epsg(4326));
  std::vector<PointCloud> clouds = {cloud};
  CrsReconciliation r = reconcile_crs(parcels, clouds);
  EXPECT_EQ(epsg_of(r.crs_wkt), 32748);
  EXPECT_NEAR(area(parcels.parcels[0].shape), 100.0, 0.01);
  // --crs: DGN95 / Indonesia TM-3 zone 48.2 (k = 0.9999, 1 degree off its meridian)
  ParcelLayer named = square_layer(3857);
  std::vector<PointCloud> clouds2 = {cimahi_cloud("cloud.las", true)};
  r = reconcile_crs(named, clouds2, nullptr, user_crs_wkt("EPSG:23834", "--crs"));
  EXPECT_EQ(epsg_of(r.crs_wkt), 23834);
  EXPECT_NEAR(area(named.parcels[0].shape), 100.0, 0.2);  // the square is 100 m^2 in UTM, whose scale is 1.0011 here
  for (const std::string& w : r.warnings) EXPECT_NE(w.rfind("--crs", 0), 0u) << w;
  // Zone 49.2 is 5 degrees away: used as named, with a warning.
  ParcelLayer far = square_layer(32748);
  std::vector<PointCloud> clouds3 = {cimahi_cloud("cloud.las", true)};
  r = reconcile_crs(far, clouds3, nullptr, user_crs_wkt("EPSG:23836", "--crs"));
  EXPECT_EQ(epsg_of(r.crs_wkt), 23836);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("% off true at the data"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.warnings[0].rfind("--crs DGN95 / Indonesia TM-3 zone 49.2", 0), 0u) << r.warnings[0];
  EXPECT_THROW(user_crs_wkt("EPSG:4326", "--crs"), InputError);
  EXPECT_THROW(user_crs_wkt("not a crs", "--crs"), InputError);
}

}  // namespace
}  // namespace c3d
