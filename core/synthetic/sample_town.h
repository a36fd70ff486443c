#pragma once
// The sample town: a synthetic, deterministic data set with exact ground truth
// (`cadastre3d sample`). Parcels (GeoPackage/GeoJSON), a 1 m DTM (GeoTIFF, NoData
// under buildings), a classified LAS 1.4 cloud and truth.json.
//
// Conventions of the truth (DESIGN.md, "Elements and how they are measured"):
//  * Roofs are zero-thickness planar surfaces. Each building is built from blocks
//    (axis-aligned rectangles in the building's own frame); a block roof is the
//    lower envelope (min) of its planes over its roof region (footprint plus
//    overhang); where roof regions of blocks overlap (cross gable) the higher roof
//    wins (max). Truth areas are summed from the exact plane polygons.
//  * ground floor level: one level per building (a row of attached houses shares
//    one) = mean of the DTM cell values (1 m cells) whose centres lie inside the
//    footprint. Walls, ground face and heights start at that level.
//  * roof_area: true sloped area of every roof plane, overhang included.
//    roof_plan_area: its horizontal projection.
//  * wall_area: exterior walls from the ground floor level up to the roof at the
//    wall line (the roof plane height at the wall line, also under an overhang),
//    gable triangles included. A step between two roof levels of one building is
//    an exterior wall from the lower roof up to the higher one (owned by the
//    higher part).
//  * party_wall_area: the wall on the parcel boundary between two attached houses,
//    ground floor level up to the roof. Each of the two houses reports the full
//    face (it closes both solids), so a town-wide sum counts it twice.
//  * ground_area: footprint inside the walls.
//  * outer_ceiling_area: roof plan area minus footprint (plan area of the hanging
//    roof; its faces are the overhang parts of the roof planes, facing down).
//  * volume: closed solid of ground, walls (exterior, step, party) and the roof
//    inside the walls (Building::solid).
//  * eave_height: lowest roof vertex above the ground floor level (drip edge of
//    the overhang, as core/measure.h measures it); wall_top_height: lowest point
//    where an exterior wall meets the roof; ridge_height: highest roof vertex.
//
// Randomness: std::mt19937_64 only, uniform/normal variates derived from its raw
// output here (std::*_distribution differ between standard libraries).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d {

enum class SampleLayout {
  Gable, Hip, CrossGable, Shed, Flat, TwoLevel, RowHouse, Empty,
  // Curved roofs (SampleOptions::curved): a barrel vault on walls, one springing
  // from the ground (end walls only), domes, a shallow dome, a cone and an onion
  // dome on round drums, a square hall with a dome on its flat roof, halls
  // under free-form roofs: a hyperbolic paraboloid (saddle), a wave; and
  // (SampleOptions::curved_plans) flat roofs over curved plans: a round
  // tower, a hall ending in a half-circle apse.
  Vault, GroundVault, Dome, ShallowDome, Cone, OnionDome, DomeOnFlat, Saddle, Wave, RoundTower, ApsedHall
};
const char* to_string(SampleLayout l);

// Dimensions of one truth building (group of attached houses for RowHouse), in the
// building frame: main block [0,length] x [0,width], ridge along +u.
struct BuildingParams {
  SampleLayout layout = SampleLayout::Gable;
  double length = 12, width = 8;    // main block
  double eave_height = 3.2;         // wall top at the eave line above ground floor
  double pitch_deg = 30;            // Shed: the single plane, Flat: ignored
  double overhang = 0.5;            // on every free side
  double wing_length = 5;           // CrossGable: wing [length-width,length] x [-wing_length,0]
  double annex_length = 4;          // TwoLevel: annex [length,length+annex_length] x
  double annex_inset = 1;           //   [annex_inset, width-annex_inset]
  double annex_height = 3.0;        //   its roof height at the step wall
  double annex_pitch_deg = 0;       //   0 = flat, else shed falling away from the step
  std::vector<double> house_widths; // RowHouse: widths along the ridge, one per house
  double rise = 0;                  // curved: height of the vault, dome or cone above its rim
  double dome_radius = 0;           // DomeOnFlat: rim radius of the dome on the flat roof
};

// A recessed window or door in an exterior wall (SampleOptions::openings).
// Its frame is where the reveal meets the wall plane: four corners, bottom
// first, in the building's frame; the pane lies `depth` behind it along
// `inward`. The scan samples the pane and the four reveals; the wall's area
// stays its gross area (an opening is part of the wall it is in).
struct Opening {
  std::string kind;  // "window" or "door"
  Ring3 frame;
  Vec3 inward = Vec3::Zero();
  double depth = 0;
};

struct TruthBuilding {
  Building model;            // elements, solid, volume, heights (frame of the caller)
  BuildingParams params;
  std::string roof_type;     // gable, hip, cross_gable, shed, flat, two_level, row_gable
  double ground_level = 0;   // world z of the ground floor (0 from make_truth_buildings)
  double wall_top_height = 0;
  Ring2 footprint;           // counter-clockwise, same frame as model
  std::vector<std::string> attached_to;  // building ids sharing a party wall
  // Curved: element areas and the volume are the exact surface's; the faces
  // are a tessellation within 2 mm of it (the points are drawn on them).
  bool exact_areas = false;
  std::vector<Opening> openings;  // SampleOptions::openings
};

// Exact truth buildings for one parameter set in the building frame (ground floor
// at z = 0). One Building per house (RowHouse: house_widths.size(), else 1).
// Curved layouts: one building, its footprint in [0,length] x [0,width] (round
// ones: a circle of diameter min(length, width)), no overhang.
std::vector<TruthBuilding> make_truth_buildings(const BuildingParams& p);

enum class PointTag : std::uint8_t { Surface = 0, Outlier = 1, Clutter = 2, Vegetation = 3 };

struct SampleOptions {
  std::uint64_t seed = 1;
  int parcels = 24;                 // blocks of 2 x 5 parcels with streets
  double roof_density = 40;         // UAV points per m2 of roof plan area
  double roof_noise = 0.03;         // Gaussian sigma per axis, m
  double wall_density = 20;         // handheld points per m2 of wall
  double wall_noise = 0.02;
  double ground_density = 0.3;      // class 2 points per m2 of open parcel land
  double outlier_share = 0.002;     // of roof points
  double clutter_share = 0.3;       // of buildings with an antenna or a water tank
  double wall_occlusion = 0.25;     // share of exterior walls without any point
  // Trees on open land (class 5, PointTag::Vegetation), drawn from a random stream of
  // their own after every other point: 0 leaves the town exactly as without them.
  double trees_per_parcel = 0;
  // Garden sheds on open land (2-3 m high boxes: roof class 6, facade returns
  // class 64; not in the truth), drawn like the trees from a stream of their own.
  double sheds_per_parcel = 0;
  // A town of curved buildings (every curved layout and a gable house as the
  // planar control) instead of the planar layouts.
  bool curved = false;
  // A town of flat roofs over curved plans (round towers, apsed halls) and
  // gable houses instead.
  bool curved_plans = false;
  // Recessed windows and doors in the scanned exterior walls, their frames
  // in the truth (TruthBuilding::openings): what a mesh keeps of a facade.
  bool openings = false;
  int epsg = 32748;
  double origin_easting = 781000, origin_northing = 9240000;  // south-west of the town
  bool with_points = true;          // false: parcels, DTM and truth only
  // Called now and then while generating (stage name, done, total).
  std::function<void(const char*, int, int)> progress;
};

struct SampleTown {
  std::uint64_t seed = 0;
  int epsg = 0;
  LocalFrame frame;                                // local = world - origin
  std::string crs_wkt;
  std::vector<Parcel> parcels;                     // world coordinates, layer order
  std::vector<SampleLayout> layouts;               // per parcel
  std::vector<std::vector<TruthBuilding>> truth;   // per parcel; local coordinates
  PointCloud cloud;                                // world coordinates, classes 6/64/2 (5: trees)
  std::vector<PointTag> point_tags;                // per point
  Dtm dtm;                                         // complete terrain (no holes), world
  std::vector<std::uint8_t> dtm_nodata;            // 1 where dtm.tif holds NoData
};

SampleTown make_sample_town(const SampleOptions& opt);

enum class ParcelFormat { GeoPackage, GeoJson };
// How the cloud is written: one file or square tiles on a grid (as agencies
// deliver LiDAR), LAS or LAZ. Same points either way.
struct CloudLayout {
  bool laz = false;        // LASzip-compressed (.laz)
  double tile_size = 0;    // metres; 0: one file
};
struct SampleFiles {
  std::string parcels, dtm, cloud, truth;  // cloud: the file, or the folder of tiles
  std::vector<std::string> cloud_tiles;    // tiled: every tile written (none empty)
};
// Writes parcels.gpkg|parcels.geojson, dtm.tif, the cloud (unless the town has
// no points: cloud.las|cloud.laz, or tiles cloud/E<x>_N<y>.las|laz named by
// their south-west corner in metres) and truth.json into dir (created when missing).
SampleFiles write_sample_town(const SampleTown& town, const std::string& dir,
                              ParcelFormat format = ParcelFormat::GeoPackage, const CloudLayout& cloud = {});
// The cloud cut into square tiles of `layout.tile_size` m on a grid of
// multiples of that size, one file per tile that holds points; returns them.
std::vector<std::string> write_cloud_tiles(const PointCloud& cloud, const std::string& dir,
                                           const CloudLayout& layout);
// The truth.json text: deterministic for a given town.
std::string truth_json(const SampleTown& town);

// Every edge of the shell used exactly twice, in opposite directions (vertices
// merged within 1e-6 m, T-junctions split). problem says why not.
bool shell_is_closed(const std::vector<Face>& shell, std::string* problem = nullptr);
// Divergence theorem over an outward-oriented closed shell.
double shell_volume(const std::vector<Face>& shell);

}  // namespace c3d
