// The batch-wide fit a chunk at a time (cadastre/batch/batch_deviation.cpp):
// the models it reads are held a page of parcels at a time, however far a
// chunk's points are from the nearest model, and the figures equal those of
// one chunk over the whole town.
#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/store_sink.h"
#include "core/config/config.h"
#include "core/io/point_io.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

constexpr double kFarM = 400;  // east of the town: beyond every ring a chunk searches

// A copy of the raster `from` with `metres` more to the east, each row
// carrying its last height on.
void extend_dtm_east(const std::string& from, const std::string& to, double metres) {
  std::unique_ptr<GDALDataset> in(GDALDataset::Open(from.c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(in);
  double gt[6];
  ASSERT_EQ(in->GetGeoTransform(gt), CE_None);
  const int nx = in->GetRasterXSize(), ny = in->GetRasterYSize(), wide = nx + int(metres / gt[1]) + 1;
  std::vector<float> row(size_t(wide), 0);
  GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  std::unique_ptr<GDALDataset> out(tiff->Create(to.c_str(), wide, ny, 1, GDT_Float32, nullptr));
  out->SetGeoTransform(gt);
  out->SetProjection(in->GetProjectionRef());
  int has_nodata = 0;
  const double nodata = in->GetRasterBand(1)->GetNoDataValue(&has_nodata);
  if (has_nodata) out->GetRasterBand(1)->SetNoDataValue(nodata);
  for (int y = 0; y < ny; ++y) {
    ASSERT_EQ(in->GetRasterBand(1)->RasterIO(GF_Read, 0, y, nx, 1, row.data(), nx, 1, GDT_Float32, 0, 0), CE_None);
    std::fill(row.begin() + nx, row.end(), row[size_t(nx) - 1]);
    ASSERT_EQ(out->GetRasterBand(1)->RasterIO(GF_Write, 0, y, wide, 1, row.data(), wide, 1, GDT_Float32, 0, 0),
              CE_None);
  }
}

// The sample town plus one parcel kFarM east of it holding a few scattered
// roof points (too few for a building): points whose nearest face is far
// from their chunk. The town's DTM is carried on east (each row's last
// height) to cover the far parcel.
BatchInputs town_with_far_parcel() {
  static const BatchInputs in = [] {
    const std::string dir = test::sample_town("--parcels 12 --seed 11 --density 25").dir;
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(
        GDALDataset::Open((dir + "/parcels.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
    OGRLayer* layer = ds->GetLayer(0);
    OGREnvelope town;
    EXPECT_EQ(layer->GetExtent(&town), OGRERR_NONE);
    layer->ResetReading();
    std::unique_ptr<OGRFeature> far(layer->GetNextFeature());
    const double x0 = town.MaxX + kFarM, y0 = town.MinY;
    OGRLinearRing ring;
    for (auto [dx, dy] : {std::pair{0, 0}, {20, 0}, {20, 20}, {0, 20}, {0, 0}}) ring.addPoint(x0 + dx, y0 + dy);
    OGRPolygon square;
    square.addRing(&ring);
    far->SetGeometry(&square);
    far->SetFID(OGRNullFID);
    far->SetField("NIB", "far");
    EXPECT_EQ(layer->CreateFeature(far.get()), OGRERR_NONE);
    ds.reset();
    PointCloud cloud = read_point_cloud(dir + "/cloud.las");
    const double z = cloud.points[0].z();
    for (int k = 0; k < 4; ++k) {
      cloud.points.push_back(Vec3(x0 + 3 + 4 * k, y0 + 5 + 3 * k, z + 4));
      cloud.classes.push_back(6);
      cloud.points.push_back(Vec3(x0 + 2 + 5 * k, y0 + 2 + 4 * k, z));
      cloud.classes.push_back(2);
    }
    write_las(dir + "/cloud.las", cloud);
    extend_dtm_east(dir + "/dtm.tif", dir + "/dtm_far.tif", kFarM + 40);
    return BatchInputs{{dir + "/cloud.las"}, {}, dir + "/parcels.gpkg", dir + "/dtm_far.tif"};
  }();
  return in;
}

// A store that remembers the most parcels whose models were asked for at once.
class CountingSink : public StoreSink {
 public:
  using StoreSink::StoreSink;
  BatchModel models(const std::vector<int>& layer_indices) override {
    most = std::max(most, layer_indices.size());
    return StoreSink::models(layer_indices);
  }
  size_t most = 0;
};

struct Measured {
  BatchReport report;
  size_t most_models = 0;
};

Measured run(int chunk_parcels, const std::string& name) {
  Config cfg = default_config();
  cfg.batch.chunk_parcels = chunk_parcels;
  CountingSink sink(test::temp_dir(name) + "/cadastre.gpkg");
  BatchSettings s;
  s.jobs = 2;
  Measured r;
  r.report = run_batch(town_with_far_parcel(), cfg, sink, s);
  r.most_models = sink.most;
  return r;
}

TEST(BatchDeviation, ModelsHeldAPageAtATimeAndFiguresAsOneChunk) {
  const Measured whole = run(1000, "far_whole"), paged = run(2, "far_paged");
  ASSERT_EQ(whole.report.parcels, 13u);
  EXPECT_GT(whole.report.any_model_roof.n, 1000);
  // The far parcel's roof points are the farthest from any roof face.
  EXPECT_GT(whole.report.any_model_roof.max, kFarM);
  EXPECT_LE(paged.most_models, 2u);  // the rings and the far pass: a page at a time
  const BatchReport &a = whole.report, &b = paged.report;
  EXPECT_EQ(a.any_model_roof.n, b.any_model_roof.n);
  EXPECT_EQ(a.any_model_roof.max, b.any_model_roof.max);
  EXPECT_NEAR(a.any_model_roof.rmse, b.any_model_roof.rmse, 1e-9);
  EXPECT_NEAR(a.any_model_roof.mean, b.any_model_roof.mean, 1e-9);
  EXPECT_EQ(a.any_model_wall.n, b.any_model_wall.n);
  EXPECT_NEAR(a.any_model_wall.max, b.any_model_wall.max, 1e-9);  // other faces in the search tree: last bits
  EXPECT_NEAR(a.any_model_wall.mean, b.any_model_wall.mean, 1e-9);
  EXPECT_EQ(a.roof_ruler.n, b.roof_ruler.n);
  EXPECT_EQ(a.roof_ruler.median, b.roof_ruler.median);
  EXPECT_EQ(a.roof_ruler.max, b.roof_ruler.max);
  EXPECT_EQ(a.wall_ruler.p95, b.wall_ruler.p95);
  EXPECT_EQ(a.wall_points_measured, b.wall_points_measured);
}

}  // namespace
}  // namespace c3d
