// Polygon operations the stages share (needles, land between parcels).

#include <geos/io/WKTReader.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <random>

#include "core/config/config.h"
#include "core/reconstruct/envelope/envelope.h"
#include "core/evaluate/evaluate.h"
#include "core/geometry/geometry.h"
#include "core/reconstruct/outline/outline.h"
#include "core/reconstruct/planes/planes.h"
#include "core/reconstruct/ownership/ownership.h"
#include "core/reconstruct/reconstruct.h"
#include "core/reconstruct/roof/roof.h"
#include "core/synthetic/sample_town.h"
#include "core/geometry/polygon_ops.h"
#include "core/geometry/geos_util.h"
#include "core/reconstruct/segment/segmentation.h"
#include "core/check/solid_check.h"
#include "ifc_citygml/validate.h"
#include "tests/test_support.h"
#include "tests/reconstruct_fixtures.h"

using namespace c3d;
using namespace c3d::test;

TEST(PolygonOps, NeedleTipsGoSharpCornersStay) {
  // A 10 x 8 m outline with a 0.13 m needle of almost no width at a corner
  // (as subtracting a parcel cut can leave): the tip goes, the area stays.
  // A 5 degree wedge is a real, if sharp, corner and stays.
  const MultiPolygon2 needled{{{{0, 0}, {10, 0}, {10.13, -0.0001}, {10, 0.0001}, {10, 8}, {0, 8}}, {}}};
  const MultiPolygon2 out = poly::drop_needles(needled, 0.0175);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].outer.size(), 5u);  // one tip, and the base vertex left on a straight edge stays
  EXPECT_NEAR(area(out), 80.0, 1e-3);
  for (const Vec2& v : out[0].outer) EXPECT_LE(v.x(), 10.0 + 1e-9);
  const MultiPolygon2 wedge{{{{0, 0}, {10, 0}, {0, 10 * std::tan(5 * M_PI / 180)}}, {}}};
  EXPECT_EQ(poly::drop_needles(wedge, 0.0175)[0].outer.size(), 3u);
}

TEST(PolygonOps, LandBeyondASharedCornerGoesToTheNearerParcel) {
  // Two unit parcels side by side; within 0.5 m of b (a mitred buffer), outside
  // both, the land nearer to b is all of it beyond the line of their shared
  // edge: 2 m^2.
  const MultiPolygon2 a = poly::box({0, 0}, {1, 1}), b = poly::box({1, 0}, {2, 1});
  const MultiPolygon2 land = poly::nearer_to(b, a, 0.5, 0.1);
  EXPECT_NEAR(area(land), 2.0, 1e-6);
  EXPECT_TRUE(poly::covers(land, {1.25, -0.25}));
  EXPECT_TRUE(poly::covers(land, {1.25, 1.25}));
  EXPECT_TRUE(poly::covers(land, {2.25, 0.5}));
  EXPECT_FALSE(poly::covers(land, {0.75, -0.25}));
  EXPECT_TRUE(poly::nearer_to(b, poly::box({5, 0}, {6, 1}), 0.5, 0.1).empty());  // too far apart to split land
}

TEST(PolygonOps, NearZoneFindsTheSharedBoundaryOnceBuilt) {
  // b's zone built once answers for several a: a 1 m edge shared with the
  // square next to it, a 0.5 m stretch with the one offset half a metre, and
  // nothing with one 1 cm away (beyond the 1e-4 m tolerance) or far off.
  const MultiPolygon2 b = poly::box({0, 0}, {1, 1});
  const poly::NearZone zone(b, 1e-4);
  auto length = [](const std::vector<std::vector<Vec2>>& lines) {
    double len = 0;
    for (const auto& l : lines)
      for (size_t i = 1; i < l.size(); ++i) len += (l[i] - l[i - 1]).norm();
    return len;
  };
  const MultiPolygon2 side = poly::box({1, 0}, {2, 1}), offset = poly::box({1, 0.5}, {2, 1.5});
  EXPECT_NEAR(length(zone.shared_with(side)), 1.0, 1e-3);
  EXPECT_NEAR(length(zone.shared_with(offset)), 0.5, 1e-3);
  EXPECT_TRUE(zone.shared_with(poly::box({1.01, 0}, {2, 1})).empty());
  EXPECT_TRUE(zone.shared_with(poly::box({5, 5}, {6, 6})).empty());
  // the same lines as the one-off call
  EXPECT_EQ(zone.shared_with(offset), poly::shared_boundary(offset, b, 1e-4));
}

namespace {
// The land a LoD 1.3 layer leaves of the one below it in a generated town
// (parcel 10280503004535 of /tmp/c3d/b1k/t10k, local metres): a staircase of
// 0.274 m cells against a slanted outline, with wedges narrower than a cell
// along it, one of them touching the next at a point.
const char* const kStairRest = R"(
MULTIPOLYGON(((64.820463666445477 75.953646610189139, 64.820463666445477 75.229829732834332,
65.094348980901373 75.229829732834332, 65.094348980901373 73.860403160554782,
65.368234295357283 73.860403160554782, 65.368234295357283 73.038747217187066,
65.642119609813193 73.038747217187066, 65.642119609813193 72.217091273819335,
65.916004924269103 72.217091273819335, 65.916004924269103 71.943205959363425,
65.642119609813193 71.943205959363425, 65.642119609813193 71.669320644907515,
65.916004924269103 71.669320644907515, 65.916004924269103 70.573779387083874,
66.189890238725013 70.573779387083874, 66.189890238725013 69.478238129260248,
66.463775553180923 69.478238129260248, 66.463775553180923 68.382696871436607,
66.737660867636833 68.382696871436607, 66.737660867636833 68.108811556980697,
66.463775553180923 68.108811556980697, 66.463775553180923 67.834926242524787,
66.737660867636833 67.834926242524787, 66.737660867636833 67.561040928068877,
67.011546182092744 67.561040928068877, 67.011546182092744 67.287155613612981,
66.737660867636833 67.287155613612981, 66.737660867636833 66.739384984701161,
67.011546182092744 66.739384984701161, 67.011546182092744 66.191614355789341,
66.737660867636833 66.191614355789341, 66.737660867636833 66.036149871555338,
74.018987764400748 67.787900832095787, 71.658671148516518 77.598791333799426,
64.820463666445477 75.953646610189139)), ((64.088709945319039 75.777600361746153,
64.546578351989567 75.777600361746153, 64.546578351989567 75.887754930076639,
64.088709945319039 75.777600361746153)), ((65.368234295357283 69.563892279873926,
65.368234295357283 69.752123443716158, 65.642119609813193 69.752123443716158,
65.642119609813193 70.026008758172068, 65.368234295357283 70.026008758172068,
65.368234295357283 71.121550015995695, 65.094348980901373 71.121550015995695,
65.094348980901373 71.943205959363425, 64.820463666445477 71.943205959363425,
64.820463666445477 73.586517846098872, 64.546578351989567 73.586517846098872,
64.546578351989567 74.134288475010692, 64.820463666445477 74.134288475010692,
64.820463666445477 74.408173789466602, 64.546578351989567 74.408173789466602,
64.546578351989567 74.682059103922512, 64.272693037533656 74.682059103922512,
64.272693037533656 74.955944418378422, 64.546578351989567 74.955944418378422,
64.546578351989567 75.229829732834332, 64.272693037533656 75.229829732834332,
64.272693037533656 75.503715047290243, 63.998807723077746 75.503715047290243,
63.998807723077746 75.755971569851653, 63.885116306311161 75.72861954303707,
65.368234295357283 69.563892279873926)), ((66.180107462825603 66.189260803020517,
66.189890238725013 67.561040928068877, 65.916004924269103 67.561040928068877,
65.916004924269103 68.656582185892518, 65.642119609813193 68.656582185892518,
65.642119609813193 69.478238129260248, 65.388841080732959 69.478238129260248,
66.180107462825603 66.189260803020517)), ((66.463775553180923 65.970258191442852,
66.463775553180923 66.191614355789341, 66.180107462825603 66.189260803020517,
66.245432922195377 65.91772904133343, 66.463775553180923 65.970258191442852))))";

MultiPolygon2 read_wkt(const char* wkt) {
  return c3d::from_geos(*geos::io::WKTReader().read(wkt));
}
}  // namespace

TEST(PolygonOps, ErodingValidPartsNeverMeetsAnotherPartsCurves) {
  // GEOS 3.11 buffers all parts at once: the big part's offset curves and a
  // wedge's met, and it threw "unable to assign hole to a shell" on this valid
  // input, failing the parcel. Eroded by half a cell (as flush_with opens it),
  // the result is valid, inside the land, and within the mitre corners of the
  // disc erosion (the land less a strip along its rings, 66.56 m^2).
  const MultiPolygon2 rest = read_wkt(kStairRest);
  ASSERT_EQ(rest.size(), 5u);
  ASSERT_TRUE(poly::is_valid(rest));
  const double half_cell = 0.5 * 0.273885;
  MultiPolygon2 eroded;
  ASSERT_NO_THROW(eroded = poly::buffer(rest, -half_cell));
  EXPECT_TRUE(poly::is_valid(eroded));
  MultiPolygon2 disc = rest;
  for (const auto& p : rest) {
    std::vector<Vec2> ring = p.outer;
    ring.push_back(ring.front());
    disc = poly::subtract(disc, poly::buffer_line(ring, half_cell));
  }
  EXPECT_NEAR(area(disc), 66.56, 0.01);
  EXPECT_LT(area(poly::subtract(eroded, disc)), 1e-6);
  EXPECT_NEAR(area(eroded), area(disc), 0.1);
  // opened again: the strips narrower than a cell are the rest
  MultiPolygon2 opened;
  ASSERT_NO_THROW(opened = poly::buffer(eroded, half_cell));
  EXPECT_TRUE(poly::is_valid(opened));
  EXPECT_LT(area(poly::subtract(opened, rest)), 1e-6);
  EXPECT_GT(area(opened), area(eroded));
}
