// What every stage of the subdivision reads: the request (mesh, placed
// coordinates, the sheet-to-surface map, the options as resolved), the
// shares of the tolerance each kind of piece is refined to, and the budget
// (time and output size) that the refining stages spend.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <limits>
#include <span>
#include <vector>

#include "base/status.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/common/mesh.hpp"
#include "engine/sheet/sheet_map.hpp"
#include "engine/subdivision/ids.hpp"
#include "engine/subdivision/subdivide.hpp"

namespace surfdeform::subdivision {

struct WorkEstimate;  // work_estimate.hpp
class TargetEdges;    // target_edges.hpp

constexpr double kInf = std::numeric_limits<double>::infinity();

// Shares of the tolerance: edges are refined until their measured deviation
// is at most kEdgeShare of it, triangles inside faces until theirs is at most
// kFaceShare: what lies between the samples (a quadratic deviation peaks at
// most 4/3 above the largest of a triangle's edge midpoints, and the samples
// include those, the centroid and, on edges, the kinks of the map) stays
// below the tolerance. Edges get the smaller share so that the thin triangles
// along a face's side, whose deviation tends to the side's, can meet theirs.
// An edge or face whose estimated deviation (an estimate with a safety
// factor of two) is below kSkipShare of it is not measured.
constexpr double kEdgeShare = 0.7;
constexpr double kFaceShare = 0.8;
constexpr double kSkipShare = 0.5;
constexpr int kMaxBisections = 40;

// The request, with the options resolved (mode, automatic tolerance, threads).
struct Context {
  Context(const Mesh& mesh, const std::vector<Vec3>& placed, const SheetMap& map,
          OutsideMode outside, const SubdivisionOptions& options);

  const Mesh& mesh;
  const std::vector<Vec3>& placed;  // per input vertex: (a, b, h) on the sheet
  const SheetMap& map;
  const FlatLocator& locator;
  const SubdivisionOptions& options;
  CellGrid grid;
  OutsideMode outside;  // for points the subdivision adds (never kError)
  bool refuse_outside;  // input vertices off the sheet are an error
  int threads;          // 1 for small meshes
  bool uniform;         // every grid point of every face, no refinement
  double tolerance;     // as resolved (0: none)
  bool refine;          // measure and refine to the tolerance
  double sheet_diagonal;
  // FaceExtents(mesh, placed) when the caller measured it already (one per
  // triangle), else empty.
  std::span<const FaceExtent> extents;
  // Where the input vertices lie on the sheet, if known; or to record.
  FootprintUse footprint;
  // A surface given as a mesh: its edges on the sheet, which take the grid's
  // part in the marking (edge points, face points, chords); else null.
  const TargetEdges* target = nullptr;

  const Vec3& Placed(VertexId v) const { return placed[v.value()]; }
  // The placed point at t from a to b, and at barycentric (l1, l2) of corners
  // 1 and 2 in a triangle.
  Vec3 Between(VertexId a, VertexId b, double t) const {
    return Placed(a) + t * (Placed(b) - Placed(a));
  }
  Vec3 InTriangle(const std::array<VertexId, 3>& c, double l1, double l2) const {
    const Vec3& p0 = Placed(c[0]);
    return p0 + l1 * (Placed(c[1]) - p0) + l2 * (Placed(c[2]) - p0);
  }
  // F(a, b, h), points off the sheet continued as `outside` says.
  Vec3 Deformed(const Vec3& abh, int* hint) const { return map.Position(abh, outside, hint); }
  // A piece whose estimated deviation allows it is not measured.
  bool Skippable(double estimate) const { return !refine || estimate <= kSkipShare * tolerance; }
};

// The time budget and the output-size budget, shared by every thread of the
// refining stages: once either is spent, every loop that checks stops. The
// output's size counts the input's vertices and the points added.
class Budget {
 public:
  Budget(const SubdivisionOptions& options, size_t input_vertices);

  bool OutOfTime() {
    if (out_of_time_.load(std::memory_order_relaxed)) return true;
    if (!deadline_.Passed()) return false;
    out_of_time_ = true;
    return true;
  }
  // Counts one added point against max_vertices.
  void AddPoint() {
    if (input_ + added_.fetch_add(1) + 1 > max_vertices_) over_limit_ = true;
  }
  bool OverLimit() const { return over_limit_.load(); }
  // Counts `n` crossings of grid lines (or a mesh surface's edges) found on
  // the model's edges against max_crossings. False once past it.
  bool AddCrossings(size_t n) {
    return crossings_.fetch_add(n, std::memory_order_relaxed) + n <= max_crossings_;
  }
  bool TooManyCrossings() const {
    return crossings_.load(std::memory_order_relaxed) > max_crossings_;
  }
  size_t crossings() const { return crossings_.load(); }
  size_t added() const { return added_.load(); }
  size_t vertices() const { return input_ + added(); }  // the output so far
  // kDeadlineExceeded, with the budget and the time spent.
  Status TimeUp() const;
  // kLimitExceeded for the size limits: `what` ("vertices", ...).
  static Status OverLimitError(const char* what, size_t limit, size_t actual);
  // kLimitExceeded for the crossings (AddCrossings).
  Status TooManyCrossingsError() const;
  // The same, known before the work (work_estimate.hpp) for a model of
  // `input` vertices: it names the footprint's size or the tolerance,
  // whichever asks for more.
  static Status OverLimitError(size_t limit, size_t input, const WorkEstimate& least);

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  Deadline deadline_;
  double budget_ms_ = 0.0;
  size_t max_vertices_;
  size_t max_crossings_;
  size_t input_;
  std::atomic<size_t> added_{0};
  std::atomic<size_t> crossings_{0};
  std::atomic<bool> over_limit_{false};
  std::atomic<bool> out_of_time_{false};
};

// What refining an edge or a face added and measured.
struct Tally {
  size_t refinement = 0;      // points added for the tolerance
  double max_dev = 0.0;       // the largest deviation measured
  double max_estimate = 0.0;  // the largest estimate where nothing was measured
  size_t measured = 0;        // points measured

  void Add(const Tally& o) {
    refinement += o.refinement;
    max_dev = std::max(max_dev, o.max_dev);
    max_estimate = std::max(max_estimate, o.max_estimate);
    measured += o.measured;
  }
};

}  // namespace surfdeform::subdivision
