// Many tiles as one cloud and the chunked batch (docs/inputs.md "Tiles",
// docs/scale.md "Streaming"): a folder or a glob of tiles gives the store one
// file gives; any chunk size gives the same store; a region read keeps exactly
// the points inside; a file streamed in blocks is the file read whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "cadastre/batch/batch.h"
#include "cadastre/batch/batch_inputs.h"
#include "cadastre/batch/run_fit.h"
#include "cadastre/batch/store_sink.h"
#include "cadastre/batch/tile_extents.h"
#include "cadastre/batch/tiles.h"
#include "cadastre/store/store.h"
#include "core/config/config.h"
#include "core/error.h"
#include "core/geometry/unique_points.h"
#include "core/io/point_io.h"
#include "core/io/sha256.h"
#include "tests/test_support.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

const test::SampleTown& town() { return test::sample_town("--parcels 12 --seed 11 --density 25"); }

// The town's cloud cut into four LAS tiles by quadrant of its extent.
std::string four_tiles() {
  static const std::string dir = [] {
    const std::string d = test::temp_dir("tiles");
    const PointCloud whole = read_point_cloud(town().inputs.clouds[0]);
    Box all;
    for (const Vec3& p : whole.points) all.add(p.x(), p.y());
    const double mx = (all.min_x + all.max_x) / 2, my = (all.min_y + all.max_y) / 2;
    std::vector<PointCloud> tiles(4);
    for (size_t i = 0; i < whole.points.size(); ++i) {
      const Vec3& p = whole.points[i];
      PointCloud& t = tiles[size_t(p.x() >= mx) + 2 * size_t(p.y() >= my)];
      t.points.push_back(p);
      t.classes.push_back(whole.classes[i]);
    }
    for (size_t k = 0; k < 4; ++k) {
      tiles[k].crs_wkt = whole.crs_wkt;
      write_las(d + "/tile_" + std::to_string(k) + ".las", tiles[k]);
    }
    return d;
  }();
  return dir;
}

BatchReport run_into(const BatchInputs& in, const std::string& store, int chunk_parcels) {
  Config cfg = default_config();
  cfg.batch.chunk_parcels = chunk_parcels;
  StoreSink sink(store);
  BatchSettings s;
  s.jobs = 2;
  return run_batch(in, cfg, sink, s);
}

// Same parcels, statuses, reasons, buildings, element areas and valuations.
void expect_same_store(const std::string& a, const std::string& b) {
  const BatchModel ma = load_batch_model(a), mb = load_batch_model(b);
  ASSERT_EQ(ma.results.size(), mb.results.size());
  size_t elements = 0;
  for (size_t i = 0; i < ma.results.size(); ++i) {
    const ParcelResult &ra = ma.results[i], &rb = mb.results[i];
    EXPECT_EQ(ra.parcel_id, rb.parcel_id);
    EXPECT_EQ(ra.status, rb.status) << ra.parcel_id;
    EXPECT_EQ(ra.reason, rb.reason) << ra.parcel_id;
    EXPECT_EQ(ra.roof_points, rb.roof_points) << ra.parcel_id;
    ASSERT_EQ(ra.buildings.size(), rb.buildings.size()) << ra.parcel_id;
    for (size_t k = 0; k < ra.buildings.size(); ++k) {
      ASSERT_EQ(ra.buildings[k].elements.size(), rb.buildings[k].elements.size()) << ra.parcel_id;
      for (size_t e = 0; e < ra.buildings[k].elements.size(); ++e, ++elements)
        EXPECT_EQ(ra.buildings[k].elements[e].area, rb.buildings[k].elements[e].area) << ra.parcel_id;
    }
  }
  EXPECT_GT(elements, 20u);
  const auto va = load_valuations(a), vb = load_valuations(b);
  ASSERT_EQ(va.size(), vb.size());
  for (size_t i = 0; i < va.size(); ++i) {
    EXPECT_EQ(va[i].njop, vb[i].njop);
    EXPECT_EQ(va[i].tax, vb[i].tax);
  }
}

void expect_same_figures(const BatchReport& a, const BatchReport& b) {
  EXPECT_EQ(a.any_model_roof.n, b.any_model_roof.n);
  EXPECT_NEAR(a.any_model_roof.rmse, b.any_model_roof.rmse, 1e-12);
  EXPECT_NEAR(a.any_model_roof.max, b.any_model_roof.max, 1e-9);  // faces paged otherwise: last bits
  EXPECT_EQ(a.any_model_wall.n, b.any_model_wall.n);
  EXPECT_NEAR(a.any_model_wall.mean, b.any_model_wall.mean, 1e-12);
  EXPECT_EQ(a.roof_ruler.n, b.roof_ruler.n);
  EXPECT_EQ(a.roof_ruler.median, b.roof_ruler.median);  // the same histogram, whatever the chunks
  EXPECT_EQ(a.wall_ruler.p95, b.wall_ruler.p95);
  EXPECT_EQ(a.wall_points_measured, b.wall_points_measured);
  EXPECT_EQ(a.held, b.held);
}

struct Run {
  std::string store;
  BatchReport report;
};

// The town from its one file in one chunk: what every other run must equal.
const Run& whole_file_run() {
  static const Run r = [] {
    const std::string store = test::temp_dir("whole") + "/cadastre.gpkg";
    return Run{store, run_into(town().inputs, store, 1000)};
  }();
  return r;
}

TEST(StreamBatch, ChunkSizeChangesNothing) {
  const BatchReport& all = whole_file_run().report;
  EXPECT_EQ(all.held, 12u);
  EXPECT_GT(all.any_model_roof.n, 1000);
  for (int chunk : {1, 7}) {
    const std::string store = test::temp_dir("chunk" + std::to_string(chunk)) + "/cadastre.gpkg";
    const BatchReport r = run_into(town().inputs, store, chunk);
    expect_same_store(whole_file_run().store, store);
    expect_same_figures(all, r);
  }
}

TEST(StreamBatch, FolderOrGlobOfTilesIsTheFile) {
  const BatchReport& all = whole_file_run().report;
  for (const std::string& cloud : {four_tiles(), four_tiles() + "/tile_*.las"}) {
    BatchInputs in = town().inputs;
    in.clouds = {cloud};
    const std::string store = test::temp_dir(cloud == four_tiles() ? "folder" : "glob") + "/cadastre.gpkg";
    const BatchReport r = run_into(in, store, 5);
    expect_same_store(whole_file_run().store, store);
    expect_same_figures(all, r);
    EXPECT_EQ(load_runs(store).back().inputs.size(), 4u + 2u) << "each tile hashed, the parcels and the DTM";
  }
}

// A tile beyond the parcels' reach (5 km off, past the roof-density block
// around them) is neither read nor hashed: a --bbox or a shard of a national
// cloud reads its own area. The store is the one the town alone gives.
TEST(StreamBatch, ATileOutOfTheParcelsReachIsNotRead) {
  const std::string dir = test::temp_dir("far");
  for (int k = 0; k < 4; ++k) {
    const std::string name = "/tile_" + std::to_string(k) + ".las";
    fs::copy_file(four_tiles() + name, dir + name);
  }
  PointCloud far = read_point_cloud(four_tiles() + "/tile_0.las");
  for (Vec3& p : far.points) p.x() += 5000;
  write_las(dir + "/far.las", far);
  BatchInputs in = town().inputs;
  in.clouds = {dir};
  const std::string store = test::temp_dir("far_out") + "/cadastre.gpkg";
  const BatchReport r = run_into(in, store, 5);
  expect_same_store(whole_file_run().store, store);
  expect_same_figures(whole_file_run().report, r);
  const auto inputs = load_runs(store).back().inputs;
  EXPECT_EQ(inputs.size(), 4u + 2u);
  for (const InputFile& f : inputs) EXPECT_EQ(f.path.find("far.las"), std::string::npos) << f.path;

  // No parcel's resume key changed: the far file is in none's reach.
  BatchInputs four = town().inputs;
  four.clouds = {four_tiles()};
  const std::string four_store = test::temp_dir("four_out") + "/cadastre.gpkg";
  run_into(four, four_store, 5);
  const auto jobs = load_jobs(store), four_jobs = load_jobs(four_store);
  ASSERT_EQ(jobs.size(), four_jobs.size());
  for (size_t i = 0; i < jobs.size(); ++i) EXPECT_EQ(jobs[i].inputs_key, four_jobs[i].inputs_key) << jobs[i].parcel_id;
  // The whole-run fit takes every file given, the far one too: the store's
  // run read only files among them, and every parcel's key is theirs.
  Config cfg = default_config();
  cfg.batch.chunk_parcels = 5;  // as run_into ran it
  try {
    load_run_inputs(RunInputs{in, cfg}, {store});
  } catch (const InputError& e) {
    ADD_FAILURE() << e.what();
  }
  BatchInputs other = in;
  other.clouds = {four_tiles() + "/tile_0.las", four_tiles() + "/tile_1.las", four_tiles() + "/tile_2.las"};
  EXPECT_THROW(load_run_inputs(RunInputs{other, cfg}, {store}), InputError);  // tile_3 missing
}

// A tile whose header's bounds do not hold its points (issue 49: a writer
// left them stale, moved them, or wrote zeros) looked out of the parcels'
// reach and was not read: its parcels came out empty or short, exit 0. A
// sample of its points now shows the bounds wrong; its extent is read from
// its points, a warning names it, and the store is the one the town gives.
TEST(StreamBatch, ATileWhoseHeaderBoundsAreWrongIsStillRead) {
  const CloudExtent good = read_cloud_extent(four_tiles() + "/tile_2.las");
  ASSERT_TRUE(good.from_header);
  const double w = good.max_x - good.min_x, h = good.max_y - good.min_y;
  const std::vector<std::array<double, 4>> wrong = {  // max x, min x, max y, min y as the header holds them
      {good.min_x + w / 4, good.min_x, good.min_y + h / 4, good.min_y},
      {good.max_x + 10000, good.min_x + 10000, good.max_y, good.min_y},
      {0, 0, 0, 0}};
  for (size_t k = 0; k < wrong.size(); ++k) {
    const std::string dir = test::temp_dir("bounds_" + std::to_string(k));
    for (int t = 0; t < 4; ++t) {
      const std::string name = "/tile_" + std::to_string(t) + ".las";
      fs::copy_file(four_tiles() + name, dir + name);
    }
    // The same tile as LAZ (its first chunk is read); the LAS one in the folder.
    write_laz(dir + "/tile_2.laz", read_point_cloud(dir + "/tile_2.las"));
    for (const std::string& name : {"/tile_2.las", "/tile_2.laz"}) {
      {
        std::fstream f(dir + name, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(179);
        f.write(reinterpret_cast<const char*>(wrong[k].data()), 32);
      }
      const CloudExtent e = read_cloud_extent(dir + name);
      EXPECT_FALSE(e.from_header) << k << name;
      EXPECT_NE(e.note.find("outside the header's bounds"), std::string::npos) << k << name << ": " << e.note;
      EXPECT_DOUBLE_EQ(e.min_x, good.min_x) << k << name;
      EXPECT_DOUBLE_EQ(e.max_y, good.max_y) << k << name;
    }
    fs::remove(dir + "/tile_2.laz");
    BatchInputs in = town().inputs;
    in.clouds = {dir};
    const std::string store = test::temp_dir("bounds_out_" + std::to_string(k)) + "/cadastre.gpkg";
    const BatchReport r = run_into(in, store, 5);
    expect_same_store(whole_file_run().store, store);
    expect_same_figures(whole_file_run().report, r);
    bool named = false;
    for (const std::string& warning : r.warnings) named |= warning.find("tile_2.las") != std::string::npos;
    EXPECT_TRUE(named) << k;
  }
}

// A header only a little too small fools the sample: the records it reads
// all lie inside. Here tile 3's header holds only the points nearest its
// south-west corner, and those come first in the file, where the sample
// reads. Before, the tile was indexed by that box, and a region beyond it
// did not read the tile; its points are now decoded once for its true box
// (tile_extents.h), and a warning names the tile.
TEST(StreamBatch, AHeaderTooSmallForPointsTheSampleMissesIsCaught) {
  const std::string dir = test::temp_dir("short_header");
  for (int t = 0; t < 3; ++t) {
    const std::string name = "/tile_" + std::to_string(t) + ".las";
    fs::copy_file(four_tiles() + name, dir + name);
  }
  const PointCloud tile = read_point_cloud(four_tiles() + "/tile_3.las");
  const size_t n = tile.points.size(), samples = 4096;
  ASSERT_GT(n, samples);
  Box all;
  for (const Vec3& p : tile.points) all.add(p.x(), p.y());
  std::vector<size_t> by_corner(n);  // nearest the tile's south-west corner first
  std::iota(by_corner.begin(), by_corner.end(), size_t(0));
  const auto to_corner = [&](size_t i) { return tile.points[i].x() - all.min_x + tile.points[i].y() - all.min_y; };
  std::sort(by_corner.begin(), by_corner.end(), [&](size_t a, size_t b) { return to_corner(a) < to_corner(b); });
  PointCloud ordered = tile;
  Box header;
  for (size_t r = 0; r < n; ++r) {
    ordered.points[r] = tile.points[by_corner[r]], ordered.classes[r] = tile.classes[by_corner[r]];
    if (r < samples) header.add(ordered.points[r].x(), ordered.points[r].y());
  }
  ASSERT_LT(header.max_x + 1, all.max_x);
  ASSERT_LT(header.max_y + 1, all.max_y);
  const std::string path = dir + "/tile_3.las";
  write_las(path, ordered);
  {
    const std::array<double, 4> bounds = {header.max_x, header.min_x, header.max_y, header.min_y};
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(179);
    f.write(reinterpret_cast<const char*>(bounds.data()), 32);
  }
  ASSERT_TRUE(read_cloud_extent(path).from_header) << "the sample should find nothing wrong";
  BatchInputs in = town().inputs;
  in.clouds = {dir};
  const LoadedInputs loaded = load_fit_inputs(in, default_config());
  ASSERT_EQ(loaded.tiles.size(), 4u);
  const Box& indexed = loaded.tiles[3].extent;
  EXPECT_EQ(loaded.tiles[3].path, path);
  EXPECT_EQ(indexed.max_x, all.max_x);
  EXPECT_EQ(indexed.max_y, all.max_y);
  EXPECT_EQ(indexed.min_x, all.min_x);
  bool named = false;
  for (const std::string& warning : loaded.warnings) named |= warning.find("tile_3.las: the points reach") != std::string::npos;
  EXPECT_TRUE(named);
}

// The index gives back the box it recorded, for the same content (SHA-256)
// wherever the file is, and a row whose checksum fails is decoded again.
TEST(StreamBatch, TheTileIndexRecordsADecodedBoxOnce) {
  const std::string tile = four_tiles() + "/tile_1.las", db = test::temp_dir("tile_index") + "/extents.sqlite";
  const CloudExtent header = read_cloud_extent(tile);
  const std::string sha = describe_input_file(tile).sha256;
  const CloudExtent first = TileExtentIndex(db).decoded(tile, sha, header);
  const CloudExtent points = decoded_cloud_extent(tile);
  EXPECT_EQ(first.points, points.points);
  EXPECT_EQ(first.max_x, points.max_x);
  EXPECT_EQ(first.min_y, points.min_y);
  // Read back without the file: the path is not opened again.
  const CloudExtent again = TileExtentIndex(db).decoded("/nonexistent/tile_1.las", sha, header);
  EXPECT_EQ(again.min_x, points.min_x);
  EXPECT_EQ(again.max_y, points.max_y);
  EXPECT_EQ(again.points, points.points);
  test::sql_exec(db, "UPDATE tile_extent SET max_x = max_x + 100");
  EXPECT_THROW(TileExtentIndex(db).decoded("/nonexistent/tile_1.las", sha, header), InputError);
  // No index, or one that cannot be written: decoded, the run goes on.
  EXPECT_EQ(TileExtentIndex("").decoded(tile, sha, header).points, points.points);
  EXPECT_EQ(TileExtentIndex("/proc/none/extents.sqlite").decoded(tile, sha, header).points, points.points);
}

// The CLI keeps the index in the user's cache folder ($XDG_CACHE_HOME).
TEST(StreamBatch, TheCliKeepsTheTileIndexInTheCacheFolder) {
  const std::string cache = test::temp_dir("xdg_cache"), out = test::temp_dir("xdg_out");
  const std::string args = "batch --quiet --cloud " + four_tiles() + " --parcels " + town().inputs.parcels +
                           " --dtm " + town().inputs.dtm + " --out " + out + " --formats cityjson";
  ASSERT_EQ(setenv("XDG_CACHE_HOME", cache.c_str(), 1), 0);
  std::string output;
  const int rc = test::run_cli(args, &output);
  unsetenv("XDG_CACHE_HOME");
  ASSERT_TRUE(rc == 0 || rc == 3) << output;  // 3: some parcel not ok
  EXPECT_EQ(test::sql_number(cache + "/cadastre3d/tile-extents.sqlite", "SELECT count(*) FROM tile_extent"), 4);
}

TEST(StreamBatch, FolderWithoutCloudsAndUnmatchedGlobAreErrors) {
  const std::string empty = test::temp_dir("empty");
  EXPECT_THROW(expand_point_files({empty}), InputError);
  EXPECT_THROW(expand_point_files({empty + "/*.laz"}), InputError);
  const auto files = expand_point_files({four_tiles()});
  ASSERT_EQ(files.size(), 4u);
  EXPECT_TRUE(std::is_sorted(files.begin(), files.end()));
}

// The points of a file inside a region, split and folded as read_region promises, from the whole file.
RegionPoints expected_region(const std::string& path, const Region& region, const ClassMapping& m) {
  const PointCloud c = read_point_cloud(path);
  RegionPoints r;
  for (size_t i = 0; i < c.points.size(); ++i) {
    if (!region.holds(c.points[i])) continue;
    if (c.classes.empty() || m.is_roof(c.classes[i])) r.roof.push_back(c.points[i]);
    else if (m.is_wall(c.classes[i])) r.wall.push_back(c.points[i]);
  }
  r.roof = one_per_place(r.roof);
  r.wall = one_per_place(r.wall);
  return r;
}

void expect_region_read_exact(const std::string& path, const ClassMapping& m) {
  const CloudExtent e = read_cloud_extent(path);
  ASSERT_TRUE(e.from_header) << path;
  Tile t{path, false, e.crs_wkt, e.crs_wkt, {}, nullptr};
  t.extent = {e.min_x, e.min_y, e.max_x, e.max_y};
  const Box box{e.min_x + 0.3 * (e.max_x - e.min_x), e.min_y + 0.2 * (e.max_y - e.min_y),
                e.min_x + 0.7 * (e.max_x - e.min_x), e.min_y + 0.6 * (e.max_y - e.min_y)};
  // The box, and its west and east thirds as a region of two parts.
  const double w = (box.max_x - box.min_x) / 3;
  const Region whole{box}, sides = region_of({{box.min_x, box.min_y, box.min_x + w, box.max_y},
                                              {box.max_x - w, box.min_y, box.max_x, box.max_y}});
  size_t in_whole = 0;
  for (const Region* region : {&whole, &sides}) {
    const RegionPoints got = read_region({t}, *region, m), want = expected_region(path, *region, m);
    EXPECT_GT(got.roof.size() + got.wall.size(), 0u) << path;
    EXPECT_EQ(got.roof, want.roof) << path;
    EXPECT_EQ(got.wall, want.wall) << path;
    if (region == &whole) in_whole = got.roof.size() + got.wall.size();
    else EXPECT_LT(got.roof.size() + got.wall.size(), in_whole) << path << ": the gap between the parts is left out";
  }
}

TEST(StreamBatch, ARegionHoldsItsPartsAndLeavesTheGapsBetween) {
  const Box a{100, 200, 130, 210}, b{180, 260, 190, 300};
  const Region r = region_of({a, b});
  EXPECT_EQ(r.box.min_x, 100);
  EXPECT_EQ(r.box.max_y, 300);
  for (const Box& part : {a, b})  // corners, edges and inside of each part
    for (double fx : {0.0, 0.37, 1.0})
      for (double fy : {0.0, 0.61, 1.0}) {
        const Vec3 p(part.min_x + fx * (part.max_x - part.min_x), part.min_y + fy * (part.max_y - part.min_y), 0);
        EXPECT_TRUE(r.holds(p)) << p.transpose();
      }
  EXPECT_FALSE(r.holds(Vec3(160, 230, 0)));  // between the parts, cells away from both
  EXPECT_FALSE(r.holds(Vec3(195, 230, 0)));
  EXPECT_FALSE(r.holds(Vec3(99, 205, 0)));   // outside the box
  EXPECT_TRUE(Region{a}.holds(Vec3(115, 205, 0)));
}

TEST(StreamBatch, RegionReadKeepsExactlyThePointsInside) {
  expect_region_read_exact(town().inputs.clouds[0], default_config().classes);
  const std::string laz = test::laz_dir();
  C3D_NEED(!laz.empty(), "../shared/data/laz absent: LAZ region reads not checked");
  ClassMapping everything;  // every class a roof class: all points count
  for (int c = 0; c < 256; ++c) everything.roof.push_back(c);
  for (const char* f : {"autzen_trim.laz", "simple.laz", "1.2-with-color.copc.laz"})
    expect_region_read_exact(laz + "/" + f, everything);
}

TEST(StreamBatch, BlocksOfAFileAreTheFileReadWhole) {
  std::vector<std::string> files = {town().inputs.clouds[0]};
  if (!test::laz_dir().empty())
    for (const char* f : {"autzen_trim.laz", "las_with_several_extra_byte_bloc.laz", "1.2-with-color.copc.laz"})
      files.push_back(test::laz_dir() + "/" + f);
  for (const std::string& f : files) {
    const PointCloud whole = read_point_cloud(f);
    PointCloud joined;
    size_t blocks = 0;
    for_each_point_block(f, [&](const PointCloud& b) {
      ++blocks;
      EXPECT_EQ(b.crs_wkt, whole.crs_wkt);
      joined.points.insert(joined.points.end(), b.points.begin(), b.points.end());
      joined.classes.insert(joined.classes.end(), b.classes.begin(), b.classes.end());
    });
    EXPECT_GE(blocks, 1u);
    EXPECT_EQ(joined.points, whole.points) << f;
    EXPECT_EQ(joined.classes, whole.classes) << f;
  }
}

}  // namespace
}  // namespace c3d
