#pragma once
// The ownership stage's internal thresholds, each with its reason. The rules
// must reach the same answer from either side of a boundary, so none of them
// hangs on which parcel asks.
#include <cstddef>

namespace c3d::ownership {

// Deciding who models a roof (ownership.cpp).
constexpr size_t kMinPointsAcross = 10;      // fewer points on a neighbour's land say nothing about it
constexpr double kRunsHullSpacings = 5.0;    // a component's plan hull bridges gaps of 5 point spacings...
constexpr double kRunsHullMinAlphaM = 1.0;   // ...and of 1 m at least, so a sparse scan's hull holds together
constexpr double kRoofCellM = 0.5;           // the ownership grid's cell
constexpr size_t kMinRoofCells = 4;          // 1 m^2: a metre of roof along the boundary, a metre deep
constexpr int kTypicalShareOfCell = 5;       // a cell is roof with a fifth of the typical count (3 of Cimahi's 15)
constexpr double kClipRoundingM = 0.05;      // the clip buffer's rounding at corners, off the context width
constexpr double kNearerStepM = 0.25;        // the step the split line is carried on beyond a shared corner
constexpr double kGridCellM = 2.0;           // the queries' point index: few cells per edge, few on a large parcel

// Questions about an outline at the boundary (boundary.cpp).
constexpr double kBoundaryStripM = 0.3;      // an edge this near the parcel line lies on it
constexpr double kLineProbeM = 0.15;         // just inside and just outside the parcel line, past its noise
constexpr double kEdgeFrom = 0.1;            // an edge's points are counted from a tenth along it...
constexpr double kEdgeTo = 0.9;              // ...to nine tenths: its ends belong to the corners
constexpr double kEdgeMiddle = 0.8;          // the share of an edge between kEdgeFrom and kEdgeTo
constexpr double kOwnStripM = 0.6;           // this roof just inside an edge: its height there
constexpr double kAcrossNearM = 0.5;         // the first half-metre across the line: a gutter or an eave tip reaches it
constexpr double kAcrossFarM = 1.0;          // the metre across the line a neighbour's house fills
constexpr double kMinPartyEdgeM = 1.0;       // shorter edges are jogs, decided by the party edges beside them
constexpr double kMinAcrossPoints = 10.0;    // roof points across a party edge: at least this many...
constexpr double kAcrossPointsPerM = 2.0;    // ...and this many per metre of edge
constexpr double kMinFurtherPoints = 5.0;    // of them beyond kAcrossNearM: at least this many...
constexpr double kFurtherPointsPerM = 0.5;   // ...and this many per metre of edge
constexpr double kMaxJogTurnDeg = 20.0;      // a jog continues a party edge it turns from by less
constexpr double kMinSeenPartyEdgeM = 3.0;   // a wall seen under a shorter edge may be a facade running past the corner
constexpr size_t kMinEdgeRoofPoints = 10;    // fewer roof points along an edge give no height there
constexpr double kLowQuantile = 0.1;         // a height sample's low end, a tenth of stray points below it
constexpr double kHighQuantile = 0.9;        // a height sample's high end, a tenth of stray points above it
constexpr double kAnyHeight = -1e9;          // no lower limit on the wall points a wall is fitted to
constexpr double kPartyBinM = 0.5;           // stretch of an edge counted at a time
constexpr double kMinStretchM = 2.0;         // shortest party or free stretch a split leaves
constexpr int kMinPointsInBin = 2;           // roof points 0.5-1 m across in a bin that say "a house"
constexpr size_t kMaxGapBins = 2;            // a gap of 1 m in those points (a skylight, a shadow) is no end
constexpr double kMaxFreeShare = 0.1;        // a free stretch has roof across in at most a tenth of its bins
constexpr double kMinHiddenEdgeM = 2.0;      // a shorter edge is a corner's, not one a neighbour's eave hides
constexpr double kMaxHiddenGapM = 0.8;       // the widest gap to the boundary an eave above hides
constexpr double kMinHiddenGapM = 0.1;       // a narrower gap: the edge is on the boundary already
constexpr double kMaxGapSpreadM = 0.2;       // a gap varying more along the edge: the edge runs askew to the line
constexpr double kGapStepM = 0.02;           // the step the gap is measured in
constexpr double kAcrossProbeM = 0.2;        // beyond the gap, where the neighbour's land is looked for
constexpr double kGapMarginM = 0.05;         // a point's noise either side of the edge and of the boundary
constexpr double kCoverBinM = 0.5;           // the neighbour's roof over the gap, counted per half-metre
constexpr double kMinOverCoverage = 0.7;     // of those bins, the share the roof above must cover
constexpr size_t kMinOverPoints = 10;        // fewer points of the roof above give no height for it
constexpr int kMinWallPointsInGap = 10;      // a wall seen in the gap: the house stands free
constexpr double kHigherEaveM = 1.0;         // a storey or a roof pitch higher, not a step of this roof
constexpr double kPastBoundaryM = 0.3;       // the grown strip reaches past the boundary, then is cut back to it
constexpr double kGrownSimplifyM = 0.005;    // the grown outline's vertices within this of a line go
constexpr double kWallFitReachM = 2.0;       // fit_wall reads wall points up to 1.8 m inside an edge and 0.6 m out
constexpr double kBoxPadM = 0.01;            // a point on a searched strip's border is read despite rounding

}  // namespace c3d::ownership
