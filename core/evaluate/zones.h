#pragma once
// The deviation of a cloud from a model, zone by zone: a zone is a parcel (or
// the whole model) with its model faces and the points it measures. Roof points
// are measured against the zone's roofs (3D and vertical distance), wall points
// against its walls, and each wall point is placed under the zone's own roof,
// another zone's roof or none (see WallCover).
#include <string>
#include <vector>

#include "core/evaluate/evaluate.h"
#include "core/evaluate/model_surfaces.h"
#include "core/io/mesh_io.h"
#include "core/types.h"

namespace c3d {

// A zone before measuring.
struct ZoneInput {
  std::string id;
  std::vector<Face> roof_faces, wall_faces;
  std::vector<Vec3> roof_points, wall_points;
};

// One kind of surface (roof or wall) of a measured zone.
struct SurfaceMeasure {
  size_t faces = 0;
  std::vector<Vec3> points;      // measured points (none where the zone has no face of the kind)
  std::vector<double> distance;  // per point: 3D distance to the nearest face of the kind, m
  long unmodelled = 0;           // the zone's points of the kind that had no face to measure against
};

struct ZoneMeasure {
  std::string id;
  SurfaceMeasure roof, wall;
  std::vector<double> roof_vertical;         // per roof point: to the roof above or below, NaN: none
  std::vector<double> own_roof, other_roof;  // per wall point: see WallCover
};

// Measures every zone. Zones are taken by value: their points move into the result.
std::vector<ZoneMeasure> measure_zones(std::vector<ZoneInput> zones);

// A model measured against a cloud (per parcel, or as one zone).
struct ModelEvaluation {
  std::vector<ZoneMeasure> zones;
  bool per_parcel = false;
  size_t roof_points = 0, wall_points = 0;  // of the cloud, by class
  long points_outside = 0;                  // roof and wall points no zone measures
  long faces_outside = 0;                   // model faces no zone owns
};

// The whole model as one zone "all": every roof and wall face, every roof and wall point.
ModelEvaluation evaluate_as_one_zone(const std::vector<MeshGroup>& model, const RoofWallPoints& points);

// The statistics of a measured zone (or of several, pooled).
struct ZoneSummary {
  std::string id;
  Deviation roof, roof_vertical, wall;
  RoofCover roof_cover;
  WallCover wall_cover;
  size_t roof_faces = 0, wall_faces = 0;
  long unmodelled_roof = 0, unmodelled_wall = 0;
};
ZoneSummary summarize(const ZoneMeasure& zone);
// Exact statistics of the union of the zones (id "pooled").
ZoneSummary pool_zones(const std::vector<ZoneSummary>& zones);

// Every zone's statistics and the pooled ones.
struct EvaluationSummary {
  std::vector<ZoneSummary> zones;
  ZoneSummary pooled;
};
EvaluationSummary summarize(const ModelEvaluation& evaluation);

}  // namespace c3d
