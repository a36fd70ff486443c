#pragma once
// What a modelled building carries besides its primary model, after 3DBAG:
// attributes from its own roof points (roof type, roof heights, density, data
// quality) and its valid lower LoDs as closed shells with the RMSE of those
// points against each shell's roof (docs/design.md, "Building attributes").
#include <string>
#include <vector>

#include "core/reconstruct/planes/planes.h"
#include "core/types.h"

namespace c3d {

// A roof plane flatter than this is horizontal: flat roofs drain at 1-3
// degrees, and a fitted plane's normal wobbles by about a degree more.
constexpr double kHorizontalSlopeDeg = 5;
// Horizontal planes within this height of each other are one roof level (a
// flat roof the segmentation split); further apart they are separate levels
// (the least step the LoD 1.3 layers keep, lod13.cpp's kMinStepM).
constexpr double kSameLevelM = 0.5;

// The points over `footprint` (in plan), all of them where the footprint is
// empty. Houses cut apart under one roof share its planes, and so each
// other's points: only those over its own footprint are a house's.
std::vector<Vec3> over_footprint(const std::vector<Vec3>& points, const Polygon2& footprint);

// The plan of a building's ground faces (where its walls stand): their union,
// its largest part; empty without ground faces.
Polygon2 ground_footprint(const Building& b);

// 3DBAG's roof type: "no points" without roof points, "could not detect"
// without a plane, "slanted" with any plane steeper than kHorizontalSlopeDeg,
// else "horizontal" (one level) or "multiple horizontal".
std::string roof_type_of(const std::vector<PlaneFit>& planes, long roof_points);

// The fewest roof points per m2 of roof plan area a good LoD 2.2 model rests
// on: the smallest plane the segmentation keeps (min_component_area_m2) must
// hold the fewest points a plane is judged on (kMinPlanePoints).
double min_good_density(double min_component_area_m2);

// "good", or why not, "; "-joined: no roof points, fewer than `min_density`
// roof points per m2, or a model below LoD 2.2 (a fallback).
std::string data_quality_of(const Building& b, const BuildingAttributes& a, double min_density);

// The attributes of modelled building `b` from its own roof points (those
// over `plan_area` m2) and its roof planes; roof_rmse against b's own roof
// elements.
BuildingAttributes roof_attributes(const Building& b, const std::vector<Vec3>& own_roof_points,
                                   const std::vector<PlaneFit>& planes, double plan_area, double min_density);

// RMSE of the 3D distances of `points` to the nearest of `roof_faces` (3DBAG's
// b3_rmse_lod*); NaN without points or faces.
double roof_rmse(const std::vector<Face>& roof_faces, const std::vector<Vec3>& points);

// The shell of a valid LoD 1.2 or 1.3 building (lod12_prism, lod13_layers:
// its elements' faces are its closed shell), each face with its element's type.
LodShell lod_shell_of(const Building& lower, const std::vector<Vec3>& own_roof_points);

}  // namespace c3d
