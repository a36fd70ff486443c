#pragma once
// The roof partition's internal thresholds (roof.cpp, roof_snap.cpp), each
// with its reason. Lengths in m, areas in m^2, heights in m.

namespace c3d::roof {

// Label grid -> regions (roof.cpp).
constexpr int kSmoothMajority = 5;           // of a 3x3 window's 9 cells: a strict majority relabels the middle
constexpr double kMinCoverPart = 0.3;        // region parts smaller than this go to a neighbour before snapping...
constexpr double kMinCoverPartFine = 0.05;   // ...and this after simplifying and snapping, which leave only slivers
constexpr double kOrphanDust = 1e-6;         // orphans smaller than this are numerical dust, given to no one
constexpr double kBoxMargin = 1e-3;          // regions whose boxes are further apart share no boundary
constexpr double kSharedTol = 1e-4;          // edges this close count as one shared boundary
constexpr double kLengthTie = 1e-6;          // shared lengths this close are equal (their last digits decide nothing)
constexpr double kCornerTouchTol = 0.02;     // an orphan touching a region only at a corner still joins it
constexpr double kSimplifyTol = 0.02;        // the label grid's staircase simplified away, corners kept
constexpr double kFragment = 1.5;            // a detached bit smaller than this is a cut's leftover, not a roof part

// Cutting two regions apart along their shared boundary (roof.cpp).
constexpr double kMinPlaneAngleDeg = 8.0;    // planes nearer parallel than this meet too far off to be a ridge
constexpr double kMinPlanDir = 0.2;          // a meeting line with less horizontal extent than this is near vertical
constexpr double kMaxCutDistance = 1.2;      // a ridge runs at most this far from the shared boundary on average...
constexpr double kMaxCutHeightGap = 0.35;    // ...where the two planes are at most this far apart in height
constexpr double kMaxStepRms = 0.3;          // a step boundary straighter than this is one straight line
constexpr double kMinSharedLength = 0.4;     // shorter shared boundaries are touches, not lines to cut along
constexpr double kSampleCells = 0.5;         // the shared boundary sampled every half cell
constexpr double kStaircaseCells = 2.0;      // the label grid's staircase steps are one cell: two absorb them
constexpr double kCorridor = 1.0;            // a cut reassigns the strip this wide either side of the boundary
constexpr double kFarBox = 1e4;              // a half-plane as a box larger than any roof
constexpr double kTileCells = 32;            // regions are cut in tiles this many cells wide (roof_tiles.h)
constexpr double kCutOverrun = 0.25;         // a cut may reach this far past the ends of the shared boundary

// Snapping shared vertices onto the planes' meeting lines (roof_snap.cpp).
constexpr double kNodeTol = 1e-3;            // vertices of neighbouring rings this close are one vertex
constexpr double kJunctionWeld = 0.01;       // vertices snapped to different triples of one junction land this close
constexpr double kOnOutlineTol = 1e-5;       // a vertex this near an outline edge lies on it
constexpr double kMaxMeetHeightGap = 0.3;    // planes further apart in height at a vertex are a step, not a meeting
constexpr double kMaxSnapMove = 0.35;        // a vertex moves at most this far: further, the planes meet elsewhere
constexpr double kOnePointGap = 1e-3;        // four planes this close in height at a vertex already meet in one point
constexpr double kMinShortRidge = 2e-3;      // a shorter ridge would be welded back into one point
constexpr double kFoldAreaChange = 0.01;     // a region whose valid area differs by more folded over itself
constexpr double kOverlapDust = 1e-4;        // overlap left-overs smaller than this are dropped

}  // namespace c3d::roof
