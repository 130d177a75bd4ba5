// Stage 5 of the subdivision: the paper's edge and face points and its
// marking rules (section 3.2, Figure 6).
//
// Only faces larger than a grid cell count (a projected edge longer than the
// sides of the cells it crosses; in uniform mode, every face). Their edge
// points are where their edges cross the flat grid lines, their face points
// the grid nodes inside them; a grid line inside a face runs from one edge
// point to another through face points: a chord. Marking, to a fixed point
// over the whole mesh:
//  - an edge point is marked where the normal curvature along its grid
//    line(s) exceeds the threshold of its faces (epsilon, or the curvature a
//    tolerance implies for the cells there, 2 e t / c^2), or where the map's
//    kink there exceeds the kink threshold (2 e t / c);
//  - a chord with a marked edge point, or with a face point whose curvature
//    across the chord's line exceeds the face's threshold, is kept whole:
//    its edge points are marked, for both faces of their edges (which may
//    keep a chord of the neighbour; Figure 6 b);
//  - a face point on a kept chord is kept where the chord turns on the sheet
//    or where two kept chords cross.
// One extension: the paper tests face points only on chords already kept,
// which misses a bump inside a large face whose sides lie where the surface
// is flat; here every face point is tested.
#pragma once

#include <vector>

#include "engine/subdivision/cell_estimates.hpp"
#include "engine/subdivision/context.hpp"
#include "engine/subdivision/edge_graph.hpp"
#include "engine/subdivision/grid_points.hpp"

namespace surfdeform::subdivision {

struct EdgePoint {
  GridCrossing crossing;
  double curvature = 0.0;  // |normal curvature| across its grid line(s)
  double kink = 0.0;       // jump of the deformation's derivative along the edge there
  bool marked = false;
};

struct EdgeMarks {
  bool long_edge = false;         // longer than the cells it crosses
  double cell_side = kInf;        // shortest side of the cells near it
  bool candidate = false;         // in a large face: its points count
  double threshold = kInf;        // curvature above which a point is marked
  double kink_threshold = kInf;   // kink above which a point is marked
  std::vector<EdgePoint> points;  // grid crossings, by t
};

struct FacePoint {
  GridNodeInside node;
  // |normal curvature| across the u-line through the node (along Su) and
  // across the v-line (along Sv): how much each line is needed there.
  double across_u_line = 0.0;
  double across_v_line = 0.0;
  bool kept = false;
};

struct FaceMarks {
  bool large = false;
  double threshold = kInf;
  double kink_threshold = kInf;
  std::vector<FacePoint> points;  // grid nodes inside, by (j, i)
};

struct GridMarking {
  IdVector<EdgeId, EdgeMarks> edges;
  IdVector<FaceId, FaceMarks> faces;
};

// One entry of a chord: an edge point (point `ref` of the face's side
// `side`) or a face point (point `ref` of the face), at `along` its line.
struct ChordEntry {
  enum class Kind : uint8_t { kFacePoint, kEdgePoint };
  double along = 0.0;
  Kind kind = Kind::kFacePoint;
  int side = 0;  // edge points only
  int ref = 0;
  bool IsEdgePoint() const { return kind == Kind::kEdgePoint; }
};
struct Chord {
  int line;                         // u-line i as i, v-line j as nu + j
  std::vector<ChordEntry> entries;  // in order along the line
};

// Finds every edge and face point of the large faces, with the curvatures
// and kinks that the marking reads; nothing is marked yet. The edges'
// crossings are counted against the budget (Budget::AddCrossings): past it,
// the search stops, incomplete, with budget->TooManyCrossings().
GridMarking FindGridPoints(const Context& ctx, const EdgeGraph& graph,
                           const IdVector<VertexId, int>& vertex_cell,
                           const CellEstimates& estimates, Budget* budget);

// The first rule alone: marks the edge points of candidate edges whose
// curvature or kink exceeds their edge's thresholds (every one, in uniform
// mode), and unmarks the others.
void SeedEdgePoints(const Context& ctx, GridMarking* marking);

// Applies the marking rules above, to their fixed point.
void MarkGridPoints(const Context& ctx, const EdgeGraph& graph, GridMarking* marking);

// The chords of face `f`, by line. A face point outside any chord stands
// alone (a chord of one entry).
std::vector<Chord> Chords(const Context& ctx, const EdgeGraph& graph, const GridMarking& marking,
                          FaceId f);
// A chord is kept when one of its edge points is marked, or when one of its
// face points bends the surface across it beyond the face's threshold.
bool ChordKept(const Context& ctx, const EdgeGraph& graph, const GridMarking& marking, FaceId f,
               const Chord& chord);

}  // namespace surfdeform::subdivision
