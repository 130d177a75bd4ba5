#include "engine/subdivide.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <tuple>
#include <unordered_map>

#include "engine/face_triangulation.hpp"
#include "engine/grid_points.hpp"
#include "engine/parallel.hpp"

namespace surfdeform {
namespace {

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

// What the refinement of an edge or a face added and measured.
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

struct EdgePoint {
  GridCrossing crossing;
  double curvature = 0.0;  // |normal curvature| across its grid line(s)
  double kink = 0.0;       // jump of the deformation's derivative along the edge there
  bool marked = false;
};

// An edge of the mesh, matched by position: its two ends are welded vertex ids.
struct Edge {
  uint32_t w0 = 0, w1 = 0;                  // welded ends, w0 < w1; t runs from w0 to w1
  uint32_t v0 = 0, v1 = 0;                  // an input vertex at each end
  uint32_t faces_begin = 0, faces_end = 0;  // into the face list of edges
  bool long_edge = false;                   // longer than the cells it crosses
  double cell_side = kInf;                  // shortest side of the cells near it
  bool candidate = false;                   // in a large face: its points count
  double threshold = kInf;                  // curvature above which a point is kept
  double kink_threshold = kInf;             // kink above which a point is kept
  std::vector<EdgePoint> points;            // grid crossings, by t
  std::vector<double> kept_t;               // final points: kept crossings and refinement
  std::vector<Vec3> kept_f;                 // their deformed positions
  Tally tally;
};

struct FacePoint {
  GridNodeInside node;
  // |normal curvature| across the u-line through the node (along Su) and
  // across the v-line (along Sv): how much each line is needed there.
  double across_u_line = 0.0;
  double across_v_line = 0.0;
  bool kept = false;
};

struct Face {
  std::array<uint32_t, 3> corner{};  // input vertex ids
  std::array<uint32_t, 3> edge{};    // edge k joins corner k and corner k + 1
  std::array<bool, 3> reversed{};    // edge k's t runs from corner k + 1 to corner k
  bool degenerate = false;           // two corners at one position: left as it is
  bool large = false;
  double threshold = kInf;
  double kink_threshold = kInf;
  std::vector<FacePoint> points;
};

// A point of a face's re-triangulation beyond its corners.
struct LocalPoint {
  int side = -1;              // on side k (edge k), the index-th of the edge's kept points ...
  int index = -1;             // ... in the edge's own order
  double l1 = 0.0, l2 = 0.0;  // barycentric coordinates of corners 1 and 2
};

struct FaceOutput {
  std::vector<std::array<int, 3>> triangles;  // local ids (0-2 corners); empty: as it is
  std::vector<LocalPoint> points;             // local ids 3, 4, ...
  size_t face_points_kept = 0;
  Tally tally;
};

// One chord: the entries of a grid line inside a face, in order along it.
struct ChordEntry {
  double along;
  int side;  // >= 0: an edge point on side `side`, point `ref` of that edge
  int ref;   // < 0 side: face point `ref`
};
struct Chord {
  int line;
  std::vector<ChordEntry> entries;
};

// The terms of the deviation estimate of small edges and faces, for a cell
// or a 2 x 2 block of cells: the largest curvature at their corners, their
// twist (how far from a parallelogram a flat quad is, which bends the inverse
// map), and the largest kink across the sides inside the block (the jump of
// the deformation's derivative there: the cell-wise map is only continuous
// across grid lines).
struct CellEstimate {
  double curvature = -1.0;  // < 0: not computed
  double twist = 0.0;
  double kink = 0.0;      // 0 for a single cell
  double min_side = 0.0;  // the shortest cell side on the sheet
};

// An estimate, with a safety factor of two, of how far a straight segment or
// a triangle in these cells strays from the exact deformation: the second
// derivatives of F(a, b, h) = S + h N there are about the surface's
// curvature (of the offset surface at height h) plus the bending of the
// cells' inverse bilinear maps, and d2F/(da dh) = dN/da about the curvature;
// a straight piece of size l then strays (F'' l^2) / 8, plus j l / 4 for a
// kink j of the map where it crosses from one cell to the next. `t`: the
// terms of the cell or block the piece lies in.
double EstimateOf(const CellEstimate& t, double length, double dh, double h) {
  const double k = t.curvature;
  const double second = k * (1.0 + std::abs(h) * k) + 2.0 * t.twist;
  return 2.0 * ((second * length * length + 2.0 * k * length * std::abs(dh)) / 8.0 +
                t.kink * length / 4.0);
}

// kLimitExceeded: the refinement would pass an output-size limit.
Status OverLimit(const char* what, size_t limit, size_t actual) {
  return Status::LimitExceeded(
      "the subdivision would produce more than " + std::to_string(limit) + " " + what +
          " (the server's limit) at this tolerance; raise "
          "subdivision.tolerance or epsilon, or use a coarser grid",
      "subdivision.tolerance", static_cast<double>(limit), static_cast<double>(actual));
}

class Subdivider {
 public:
  Subdivider(const Mesh& mesh, const std::vector<Vec3>& placed, const SheetMap& map,
             OutsideMode outside, const SubdivisionOptions& o)
      : mesh_(mesh), placed_(placed), map_(map), locator_(map.locator()), options_(o) {
    refuse_outside_ = outside == OutsideMode::kError;
    outside_ = refuse_outside_ ? OutsideMode::kExtrapolate : outside;
    threads_ = mesh.triangles.size() >= 2048 ? ResolveThreads(o.threads) : 1;
    uniform_ = o.mode == SubdivisionMode::kUniform;
    if (o.time_budget_ms > 0.0) {
      deadline_ = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                               std::chrono::duration<double, std::milli>(o.time_budget_ms));
    }
    tolerance_ = o.tolerance;
    if (!uniform_ && tolerance_ == 0.0 && o.epsilon == 0.0) {
      tolerance_ = 1e-3 * locator_.bounds().diagonal().norm();
    }
    refine_ = !uniform_ && tolerance_ > 0.0;
    positions_reused_ = mesh.normals.empty() && mesh.tangents.empty();
  }

  Result<SubdivisionResult> Run();

 private:
  Vec3 Placed(const Face& f, double l1, double l2) const {
    const Vec3& p0 = placed_[f.corner[0]];
    return p0 + l1 * (placed_[f.corner[1]] - p0) + l2 * (placed_[f.corner[2]] - p0);
  }
  Vec3 EdgePlaced(const Edge& e, double t) const {
    return placed_[e.v0] + t * (placed_[e.v1] - placed_[e.v0]);
  }
  Vec3 Deformed(const Vec3& abh, int* hint) const { return map_.Position(abh, outside_, hint); }

  void Weld();
  void BuildEdges();
  void FindEdgePoints();
  void ClassifyFaces();
  void FindFacePoints();
  void Mark();
  std::vector<Chord> Chords(const Face& f) const;
  Status LocateVertices();
  void DeformVertices();
  std::vector<Vec3> InputPositions();
  bool ChordKept(const Face& f, const Chord& chord) const;
  bool ChordTurns(const Chord& chord, const GridNodeInside& node) const;
  void ComputeCellEstimates();
  // Cells a piece with corners in cells a, b, c lies in, when they are
  // within one 2 x 2 block (then the block), else an empty list.
  bool Block(int a, int b, int c, std::array<int, 4>* cells) const;
  // The terms of a block: the largest curvature and twist of its cells, the
  // largest kink across the sides inside it, the shortest side.
  CellEstimate BlockTerms(const std::array<int, 4>& cells) const;
  // The terms of the cell or block a piece with corners in cells a, b, c lies
  // in; false when they are not within one 2 x 2 block (or off the sheet).
  bool Terms(int a, int b, int c, CellEstimate* terms) const;
  // A face's extent for its estimate: its longest side on the sheet, squared,
  // and the spread and the largest magnitude of its corners' heights.
  struct Extent {
    double longest2, dh, h;
  };
  Extent FaceExtent(const std::array<uint32_t, 3>& corners) const;
  bool Screen();  // true when no face needs anything: the mesh stays as it is
  // True once the time budget is spent (then every loop that checks stops).
  bool OutOfTime() {
    if (out_of_time_.load(std::memory_order_relaxed)) return true;
    if (std::chrono::steady_clock::now() <= deadline_) return false;
    out_of_time_ = true;
    return true;
  }
  Status TimeUp() const;
  void RefineEdges();
  void RefineFace(size_t fi, FaceOutput* out, int* hint);
  Result<SubdivisionResult> Assemble();

  const Mesh& mesh_;
  const std::vector<Vec3>& placed_;
  const SheetMap& map_;
  const FlatLocator& locator_;
  const SubdivisionOptions& options_;
  OutsideMode outside_;          // for points the subdivision adds
  bool refuse_outside_ = false;  // input vertices off the sheet are an error
  int threads_ = 1;
  bool uniform_ = false;
  bool refine_ = false;
  double tolerance_ = 0.0;

  std::vector<uint32_t> weld_;  // input vertex -> welded id (smallest index at its position)
  // The deformation reuses the input vertices' positions (it has no normals
  // or tangents to carry, which need the map's Jacobian too).
  bool positions_reused_ = false;
  std::vector<Vec3> deformed_;    // input vertex -> deformed position
  std::vector<Vec2> vertex_uv_;   // input vertex -> its parameters, when not reused
  std::vector<int> vertex_cell_;  // input vertex -> its sheet cell, -1 outside
  std::vector<char> on_sheet_;    // input vertex -> on the sheet
  std::vector<Edge> edges_;
  std::vector<uint32_t> edge_faces_;
  std::vector<Face> faces_;
  std::vector<CellEstimate> cells_;
  // The kink across each interior side of the grid, sides numbered as in
  // ComputeCellEstimates; 0 where not computed.
  std::vector<double> side_kink_;
  std::vector<FaceOutput> outputs_;
  std::atomic<size_t> added_{0};  // points added so far, for the size limit
  std::atomic<bool> over_limit_{false};
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
  std::atomic<bool> out_of_time_{false};
  std::atomic<bool> failed_{false};  // an invariant of the triangulation broke (a bug)
  SubdivisionStats stats_;
};

void Subdivider::Weld() {
  const size_t n = mesh_.positions.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  const auto& p = mesh_.positions;
  std::sort(order.begin(), order.end(), [&p](uint32_t a, uint32_t b) {
    if (p[a].x() != p[b].x()) return p[a].x() < p[b].x();
    if (p[a].y() != p[b].y()) return p[a].y() < p[b].y();
    if (p[a].z() != p[b].z()) return p[a].z() < p[b].z();
    return a < b;
  });
  weld_.resize(n);
  for (size_t k = 0; k < n;) {
    size_t e = k + 1;
    while (e < n && p[order[e]] == p[order[k]]) ++e;
    for (size_t q = k; q < e; ++q) weld_[order[q]] = order[k];
    k = e;
  }
}

void Subdivider::BuildEdges() {
  const size_t nf = mesh_.triangles.size();
  faces_.resize(nf);
  // Edges grouped by their smaller welded end (CSR), then matched by the other.
  const size_t n = mesh_.positions.size();
  std::vector<uint32_t> count(n + 1, 0);
  for (size_t f = 0; f < nf; ++f) {
    Face& face = faces_[f];
    for (int k = 0; k < 3; ++k) face.corner[k] = mesh_.triangles[f][k];
    const uint32_t w[3] = {weld_[face.corner[0]], weld_[face.corner[1]], weld_[face.corner[2]]};
    face.degenerate = w[0] == w[1] || w[1] == w[2] || w[2] == w[0];
    if (face.degenerate) continue;
    for (int k = 0; k < 3; ++k) ++count[std::min(w[k], w[(k + 1) % 3]) + 1];
  }
  for (size_t v = 0; v < n; ++v) count[v + 1] += count[v];
  struct Slot {
    uint32_t other, face, k;
  };
  std::vector<Slot> slots(count[n]);
  std::vector<uint32_t> fill(count.begin(), count.end() - 1);
  for (size_t f = 0; f < nf; ++f) {
    const Face& face = faces_[f];
    if (face.degenerate) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = weld_[face.corner[k]], b = weld_[face.corner[(k + 1) % 3]];
      slots[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<uint32_t>(f), k};
    }
  }
  // Each vertex's slots, by the other end (then face, for determinism): a run
  // of equal ends is one edge, and its faces are the run's.
  edges_.reserve(nf * 3 / 2 + 16);
  edge_faces_.reserve(slots.size());
  for (size_t v = 0; v < n; ++v) {
    const auto begin = slots.begin() + count[v], end = slots.begin() + count[v + 1];
    std::sort(begin, end, [](const Slot& x, const Slot& y) {
      return x.other != y.other ? x.other < y.other
             : x.face != y.face ? x.face < y.face
                                : x.k < y.k;
    });
    for (auto run = begin; run != end;) {
      auto stop = run;
      while (stop != end && stop->other == run->other) ++stop;
      const uint32_t id = static_cast<uint32_t>(edges_.size());
      Edge& e = edges_.emplace_back();
      e.w0 = static_cast<uint32_t>(v);
      e.w1 = run->other;
      e.faces_begin = static_cast<uint32_t>(edge_faces_.size());
      for (auto q = run; q != stop; ++q) {
        Face& face = faces_[q->face];
        face.edge[q->k] = id;
        face.reversed[q->k] = weld_[face.corner[q->k]] != e.w0;
        edge_faces_.push_back(q->face);
      }
      e.faces_end = static_cast<uint32_t>(edge_faces_.size());
      const Face& first = faces_[run->face];
      const uint32_t c0 = first.corner[run->k], c1 = first.corner[(run->k + 1) % 3];
      e.v0 = first.reversed[run->k] ? c1 : c0;
      e.v1 = first.reversed[run->k] ? c0 : c1;
      run = stop;
    }
  }
}

void Subdivider::FindEdgePoints() {
  ParallelChunks(static_cast<int>(edges_.size()), threads_, [&](int, int begin, int end) {
    std::vector<GridCrossing> crossings;
    std::vector<int> scratch;
    for (int e = begin; e < end; ++e) {
      Edge& edge = edges_[e];
      const int c0 = vertex_cell_[edge.v0], c1 = vertex_cell_[edge.v1];
      const Vec2 a = placed_[edge.v0].head<2>(), b = placed_[edge.v1].head<2>();
      CellEstimate terms;
      const bool in_block = Terms(c0, c1, c1, &terms);
      if (in_block) {
        // Within a 2 x 2 block of cells: as large as a cell, or not (the
        // same test as the screen's).
        edge.cell_side = terms.min_side;
        edge.long_edge = (b - a).norm() > edge.cell_side;
        if (c0 == c1) continue;  // inside one (convex) cell: no crossing
      }
      double min_side;
      GridCrossings(locator_, a, b, &crossings, &scratch, &min_side);
      if (!in_block) {
        edge.long_edge = (b - a).norm() > min_side;
        edge.cell_side = min_side;
      }
      edge.points.resize(crossings.size());
      for (size_t k = 0; k < crossings.size(); ++k) edge.points[k].crossing = crossings[k];
    }
  });
}

void Subdivider::ClassifyFaces() {
  for (Face& f : faces_) {
    if (f.degenerate) continue;
    double cell = kInf;
    for (int k = 0; k < 3; ++k) {
      const Edge& e = edges_[f.edge[k]];
      f.large = f.large || e.long_edge || uniform_;
      cell = std::min(cell, e.cell_side);
    }
    if (!f.large) continue;
    if (uniform_) {
      f.threshold = -kInf;
    } else {
      if (options_.epsilon > 0.0) f.threshold = options_.epsilon;
      // Without this grid point the pieces beside it double to about 2
      // cells: it is needed where k (2 c)^2 / 8 exceeds the tolerance, or
      // where the map's kink there, a jump j of its derivative, makes a piece
      // of 2 cells stray j (2 c) / 4 from it (the cell-wise bilinear map is
      // only continuous across grid lines).
      if (tolerance_ > 0.0 && std::isfinite(cell) && cell > 0.0) {
        f.threshold = std::min(f.threshold, 2.0 * kEdgeShare * tolerance_ / (cell * cell));
        f.kink_threshold = 2.0 * kEdgeShare * tolerance_ / cell;
      }
    }
    for (int k = 0; k < 3; ++k) {
      Edge& e = edges_[f.edge[k]];
      e.candidate = true;
      e.threshold = std::min(e.threshold, f.threshold);
      e.kink_threshold = std::min(e.kink_threshold, f.kink_threshold);
    }
  }
}

void Subdivider::FindFacePoints() {
  ParallelChunks(static_cast<int>(faces_.size()), threads_, [&](int, int begin, int end) {
    std::vector<GridNodeInside> nodes;
    std::vector<int> scratch;
    for (int fi = begin; fi < end; ++fi) {
      Face& f = faces_[fi];
      if (!f.large) continue;
      GridNodesInside(locator_, placed_[f.corner[0]].head<2>(), placed_[f.corner[1]].head<2>(),
                      placed_[f.corner[2]].head<2>(), &nodes, &scratch);
      f.points.resize(nodes.size());
      const double nu1 = locator_.nu() - 1, nv1 = locator_.nv() - 1;
      for (size_t k = 0; k < nodes.size(); ++k) {
        f.points[k].node = nodes[k];
        if (uniform_) continue;
        // A node's parameters are exact: (i / (nu - 1), j / (nv - 1)).
        const SurfacePoint s = map_.surface().Evaluate(nodes[k].i / nu1, nodes[k].j / nv1, 2);
        f.points[k].across_u_line = std::abs(NormalCurvature(s, Vec2(1, 0)));
        f.points[k].across_v_line = std::abs(NormalCurvature(s, Vec2(0, 1)));
      }
    }
  });
  if (uniform_) return;
  // Curvatures of the edge points of candidate edges, along the edge.
  ParallelChunks(static_cast<int>(edges_.size()), threads_, [&](int, int begin, int end) {
    int hint = -1;
    for (int e = begin; e < end; ++e) {
      Edge& edge = edges_[e];
      if (!edge.candidate || edge.points.empty()) continue;
      const Vec2 a = placed_[edge.v0].head<2>(), b = placed_[edge.v1].head<2>();
      const bool kinks = std::isfinite(edge.kink_threshold);
      const double step = 1e-4 * edge.cell_side;
      for (EdgePoint& p : edge.points) {
        const Vec2 at = a + p.crossing.t * (b - a);
        const SheetParameters sp = map_.Parameters(at, outside_, false, &hint);
        const SurfacePoint s = map_.surface().Evaluate(sp.uv.x(), sp.uv.y(), 2);
        // A u-line is needed where the surface bends along u (across it), a
        // v-line where it bends along v.
        if (p.crossing.u_line >= 0) {
          p.curvature = std::abs(NormalCurvature(s, Vec2(1, 0)));
        }
        if (p.crossing.v_line >= 0) {
          p.curvature = std::max(p.curvature, std::abs(NormalCurvature(s, Vec2(0, 1))));
        }
        if (!kinks) continue;
        // One-sided derivatives along the edge, a hair to either side.
        const Vec3 mid = EdgePlaced(edge, p.crossing.t);
        const Vec3 d3 = (placed_[edge.v1] - placed_[edge.v0]).normalized() * step;
        const Vec3 f0 = Deformed(mid, &hint);
        const Vec3 fp = Deformed(mid + d3, &hint), fm = Deformed(mid - d3, &hint);
        p.kink = ((fp - f0) - (f0 - fm)).norm() / step;
      }
    }
  });
}

std::vector<Chord> Subdivider::Chords(const Face& f) const {
  struct Entry {
    int line;
    ChordEntry e;
  };
  std::vector<Entry> entries;
  const int nu = locator_.nu();
  for (int k = 0; k < 3; ++k) {
    const Edge& e = edges_[f.edge[k]];
    for (size_t q = 0; q < e.points.size(); ++q) {
      const GridCrossing& c = e.points[q].crossing;
      if (c.u_line >= 0) entries.push_back({c.u_line, {c.u_along, k, static_cast<int>(q)}});
      if (c.v_line >= 0) entries.push_back({nu + c.v_line, {c.v_along, k, static_cast<int>(q)}});
    }
  }
  for (size_t q = 0; q < f.points.size(); ++q) {
    const GridNodeInside& n = f.points[q].node;
    entries.push_back({n.i, {static_cast<double>(n.j), -1, static_cast<int>(q)}});
    entries.push_back({nu + n.j, {static_cast<double>(n.i), -1, static_cast<int>(q)}});
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    if (a.line != b.line) return a.line < b.line;
    if (a.e.along != b.e.along) return a.e.along < b.e.along;
    return a.e.side < b.e.side;
  });
  // Along each line: an edge point opens a chord, the next one closes it.
  std::vector<Chord> chords;
  for (size_t k = 0; k < entries.size();) {
    size_t end = k;
    while (end < entries.size() && entries[end].line == entries[k].line) ++end;
    bool open = false;
    for (size_t q = k; q < end; ++q) {
      const ChordEntry& e = entries[q].e;
      if (!open) {
        chords.push_back({entries[k].line, {}});
        open = e.side >= 0;
        chords.back().entries.push_back(e);
        continue;  // a face point outside a chord stands alone
      }
      chords.back().entries.push_back(e);
      if (e.side >= 0) open = false;
    }
    k = end;
  }
  return chords;
}

// A chord is kept when one of its edge points is marked, or when one of its
// face points bends the surface across it beyond the face's threshold.
bool Subdivider::ChordKept(const Face& f, const Chord& chord) const {
  const bool u_line = chord.line < locator_.nu();
  for (const ChordEntry& e : chord.entries) {
    if (e.side >= 0) {
      if (edges_[f.edge[e.side]].points[e.ref].marked) return true;
    } else {
      const FacePoint& p = f.points[e.ref];
      if ((u_line ? p.across_u_line : p.across_v_line) > f.threshold) return true;
    }
  }
  return false;
}

// True when the grid line of `chord` turns at `node` on the flat sheet (its
// pieces before and after the node are not collinear, to 1e-4 of their
// length).
bool Subdivider::ChordTurns(const Chord& chord, const GridNodeInside& node) const {
  const bool u_line = chord.line < locator_.nu();
  const int i = node.i, j = node.j;
  const int last = u_line ? locator_.nv() - 1 : locator_.nu() - 1;
  const int at = u_line ? j : i;
  if (at == 0 || at == last) return false;
  const Vec2& a = u_line ? locator_.Node(i, j - 1) : locator_.Node(i - 1, j);
  const Vec2& b = u_line ? locator_.Node(i, j + 1) : locator_.Node(i + 1, j);
  const Vec2& p = locator_.Node(i, j);
  const Vec2 ab = b - a, ap = p - a;
  return std::abs(ab.x() * ap.y() - ab.y() * ap.x()) > 1e-4 * ab.squaredNorm();
}

void Subdivider::Mark() {
  // Seeds: edge points above their edge's threshold.
  for (Edge& e : edges_) {
    if (!e.candidate) continue;
    for (EdgePoint& p : e.points) {
      p.marked = uniform_ || p.curvature > e.threshold || p.kink > e.kink_threshold;
    }
  }
  // Chords, to a fixed point: a chord with a marked edge point or a face
  // point above the face's threshold is kept whole; its edge points are marked
  // for both faces of their edges.
  std::vector<uint32_t> queue;
  std::vector<char> queued(faces_.size(), 0);
  for (size_t f = 0; f < faces_.size(); ++f) {
    if (faces_[f].large) {
      queue.push_back(static_cast<uint32_t>(f));
      queued[f] = 1;
    }
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const uint32_t fi = queue[head];
    queued[fi] = 0;
    const Face& f = faces_[fi];
    for (const Chord& chord : Chords(f)) {
      if (!ChordKept(f, chord)) continue;
      for (const ChordEntry& e : chord.entries) {
        if (e.side < 0) continue;
        Edge& edge = edges_[f.edge[e.side]];
        if (edge.points[e.ref].marked) continue;
        edge.points[e.ref].marked = true;
        for (uint32_t q = edge.faces_begin; q < edge.faces_end; ++q) {
          const uint32_t g = edge_faces_[q];
          if (g != fi && faces_[g].large && !queued[g]) {
            queued[g] = 1;
            queue.push_back(g);
          }
        }
      }
    }
  }
  // Face points on kept chords are kept where the chord turns (a grid line
  // is straight on the sheet only between nodes), and where two kept chords
  // cross; on a straight run of a chord they are not needed.
  const int nu = locator_.nu();
  for (Face& f : faces_) {
    if (!f.large) continue;
    std::vector<char> on_u(f.points.size(), 0), on_v(f.points.size(), 0);
    for (const Chord& chord : Chords(f)) {
      if (!ChordKept(f, chord)) continue;
      for (const ChordEntry& e : chord.entries) {
        if (e.side >= 0) continue;
        (chord.line < nu ? on_u : on_v)[e.ref] = 1;
        if (ChordTurns(chord, f.points[e.ref].node)) f.points[e.ref].kept = true;
      }
    }
    for (size_t q = 0; q < f.points.size(); ++q) {
      if (on_u[q] && on_v[q]) f.points[q].kept = true;
    }
  }
}

void Subdivider::ComputeCellEstimates() {
  const int nu = locator_.nu(), nv = locator_.nv();
  const int cu = nu - 1, cv = nv - 1;
  cells_.assign(static_cast<size_t>(cu) * cv, {});
  std::vector<char> seen(cells_.size(), 0);
  double h_lo = kInf, h_hi = -kInf;  // the model's range of heights
  for (const Vec3& p : placed_) {
    h_lo = std::min(h_lo, p.z());
    h_hi = std::max(h_hi, p.z());
  }
  for (int c : vertex_cell_) {
    if (c < 0) continue;
    const int i = c % cu, j = c / cu;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        if (i + di >= 0 && i + di < cu && j + dj >= 0 && j + dj < cv)
          seen[i + di + cu * (j + dj)] = 1;
      }
  }
  std::vector<int> needed;
  for (size_t c = 0; c < seen.size(); ++c) {
    if (seen[c]) needed.push_back(static_cast<int>(c));
  }
  // The nodes and the interior sides of those cells, each once. Sides: the
  // ones along u (node (i, j) to (i + 1, j)) are numbered i + cu j, the ones
  // along v (node (i, j) to (i, j + 1)) cu nv + i + nu j. A side on the
  // sheet's border has no kink: nothing inside a 2 x 2 block crosses it.
  const int u_sides = cu * nv;
  std::vector<int> nodes, sides;
  std::vector<char> node_seen(static_cast<size_t>(nu) * nv, 0);
  std::vector<char> side_seen(static_cast<size_t>(u_sides) + nu * cv, 0);
  auto add = [](std::vector<char>& flags, std::vector<int>& list, int index) {
    if (!flags[index]) {
      flags[index] = 1;
      list.push_back(index);
    }
  };
  for (int c : needed) {
    const int i = c % cu, j = c / cu;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) add(node_seen, nodes, i + di + nu * (j + dj));
    if (j > 0) add(side_seen, sides, i + cu * j);
    if (j + 1 < cv) add(side_seen, sides, i + cu * (j + 1));
    if (i > 0) add(side_seen, sides, u_sides + i + nu * j);
    if (i + 1 < cu) add(side_seen, sides, u_sides + i + 1 + nu * j);
  }
  // The largest principal curvature at each node; the kink across each side:
  // the second difference of F = S + h N across the side's middle, divided by
  // the step, at the model's lowest and highest heights (|A + h B| is convex
  // in h, so its largest value over the model's range is at one of them).
  std::vector<double> node_curvature(node_seen.size(), 0.0);
  side_kink_.assign(side_seen.size(), 0.0);
  auto kink = [&](int side, int* hint) {
    const bool along_u = side < u_sides;
    const int i = along_u ? side % cu : (side - u_sides) % nu;
    const int j = along_u ? side / cu : (side - u_sides) / nu;
    const Vec2& a = locator_.Node(i, j);
    const Vec2& b = along_u ? locator_.Node(i + 1, j) : locator_.Node(i, j + 1);
    const double step = 1e-4 * (b - a).norm();
    const Vec2 across = Vec2(-(b - a).y(), (b - a).x()).normalized() * step;
    const Vec2 mid = 0.5 * (a + b);
    Vec3 sp[3], nn[3];
    const Vec2 at[3] = {mid, mid + across, mid - across};
    for (int w = 0; w < 3; ++w) map_.SurfaceAndNormal(at[w], outside_, hint, &sp[w], &nn[w]);
    const Vec3 d_surface = (sp[1] - sp[0]) - (sp[0] - sp[2]);
    const Vec3 d_normal = (nn[1] - nn[0]) - (nn[0] - nn[2]);
    return std::max((d_surface + h_lo * d_normal).norm(), (d_surface + h_hi * d_normal).norm()) /
           step;
  };
  const int node_count = static_cast<int>(nodes.size());
  const int count = node_count + static_cast<int>(sides.size());
  ParallelChunks(count, threads_, [&](int, int begin, int end) {
    int hint = -1;
    for (int q = begin; q < end; ++q) {
      if (q < node_count) {
        const int node = nodes[q];
        const SurfacePoint s = map_.surface().Evaluate(static_cast<double>(node % nu) / cu,
                                                       static_cast<double>(node / nu) / cv, 2);
        node_curvature[node] = MaxAbsCurvature(s);
      } else {
        const int side = sides[q - node_count];
        side_kink_[side] = kink(side, &hint);
      }
    }
  });
  for (int c : needed) {
    const int i = c % cu, j = c / cu;
    double kappa = 0.0;
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di)
        kappa = std::max(kappa, node_curvature[i + di + nu * (j + dj)]);
    const Vec2 &p00 = locator_.Node(i, j), &p10 = locator_.Node(i + 1, j);
    const Vec2 &p01 = locator_.Node(i, j + 1), &p11 = locator_.Node(i + 1, j + 1);
    const double side = locator_.CellMinSide(c);
    CellEstimate& e = cells_[c];
    e.curvature = kappa;
    e.min_side = side;
    e.twist = side > 0.0 ? (p00 - p10 + p11 - p01).norm() / (side * side) : kInf;
  }
}

bool Subdivider::Block(int a, int b, int c, std::array<int, 4>* cells) const {
  if (a < 0 || b < 0 || c < 0) return false;
  const int cu = locator_.nu() - 1;
  const int i0 = std::min({a % cu, b % cu, c % cu}), i1 = std::max({a % cu, b % cu, c % cu});
  const int j0 = std::min({a / cu, b / cu, c / cu}), j1 = std::max({a / cu, b / cu, c / cu});
  if (i1 - i0 > 1 || j1 - j0 > 1) return false;
  *cells = {i0 + cu * j0, i1 + cu * j0, i0 + cu * j1, i1 + cu * j1};
  return true;
}

// A model finer than the grid, on a surface that bends gently at its scale
// (the paper's dolphin): every face inside a 2 x 2 block of cells and none
// larger than a cell, all within the tolerance, by the cells' estimate or,
// where that is not small enough, measured as the full refinement would
// measure them. Then nothing is added.
bool Subdivider::Screen() {
  if (uniform_ || !refine_) return false;
  const int count = static_cast<int>(mesh_.triangles.size());
  std::atomic<bool> pass{true};
  std::vector<double> worst(threads_, 0.0), measured_worst(threads_, 0.0);
  std::vector<size_t> measured(threads_, 0);
  ParallelChunks(count, threads_, [&](int chunk, int begin, int end) {
    int hint = -1;
    std::vector<GridCrossing> crossings;
    std::vector<int> scratch;
    for (int fi = begin; fi < end && pass.load(std::memory_order_relaxed); ++fi) {
      const auto& tri = mesh_.triangles[fi];
      CellEstimate terms;
      if (!Terms(vertex_cell_[tri[0]], vertex_cell_[tri[1]], vertex_cell_[tri[2]], &terms)) {
        pass = false;
        break;
      }
      const Extent x = FaceExtent(tri);
      if (x.longest2 > terms.min_side * terms.min_side) {
        pass = false;
        break;
      }
      const double estimate = EstimateOf(terms, std::sqrt(x.longest2), x.dh, x.h);
      if (estimate <= kSkipShare * tolerance_) {
        worst[chunk] = std::max(worst[chunk], estimate);
        continue;
      }
      // Measure: each edge at its quarter points and grid crossings, the
      // face at its centroid, against the straight pieces.
      Vec3 f[3];
      for (int k = 0; k < 3; ++k) {
        f[k] = positions_reused_ ? deformed_[tri[k]] : Deformed(placed_[tri[k]], &hint);
      }
      double dev = 0.0;
      for (int k = 0; k < 3 && dev <= kEdgeShare * tolerance_; ++k) {
        const Vec3 &a = placed_[tri[k]], &b = placed_[tri[(k + 1) % 3]];
        double min_side;
        GridCrossings(locator_, a.head<2>(), b.head<2>(), &crossings, &scratch, &min_side);
        auto sample = [&](double t) {
          const Vec3 exact = Deformed(a + t * (b - a), &hint);
          dev = std::max(dev, (exact - ((1.0 - t) * f[k] + t * f[(k + 1) % 3])).norm());
          ++measured[chunk];
        };
        for (double t : {0.25, 0.5, 0.75}) sample(t);
        for (const GridCrossing& c : crossings) sample(c.t);
      }
      const Vec3 centroid =
          Deformed((placed_[tri[0]] + placed_[tri[1]] + placed_[tri[2]]) / 3.0, &hint);
      const double face_dev = (centroid - (f[0] + f[1] + f[2]) / 3.0).norm();
      ++measured[chunk];
      if (dev > kEdgeShare * tolerance_ || face_dev > kFaceShare * tolerance_) {
        pass = false;
        break;
      }
      measured_worst[chunk] = std::max({measured_worst[chunk], dev, face_dev});
    }
  });
  if (!pass) return false;
  for (int c = 0; c < threads_; ++c) {
    stats_.max_estimated_deviation = std::max(stats_.max_estimated_deviation, worst[c]);
    stats_.max_deviation = std::max(stats_.max_deviation, measured_worst[c]);
    stats_.measured_points += measured[c];
  }
  return true;
}

CellEstimate Subdivider::BlockTerms(const std::array<int, 4>& cells) const {
  CellEstimate t = cells_[cells[0]];
  for (int q = 1; q < 4; ++q) {
    const CellEstimate& e = cells_[cells[q]];
    t.curvature = std::max(t.curvature, e.curvature);
    t.twist = std::max(t.twist, e.twist);
    t.min_side = std::min(t.min_side, e.min_side);
  }
  // cells: (i0, j0), (i1, j0), (i0, j1), (i1, j1), with i1 - i0 and j1 - j0
  // at most 1. Inside the block: the v-sides at i1 (when i1 > i0) and the
  // u-sides at j1 (when j1 > j0).
  const int nu = locator_.nu(), cu = nu - 1, u_sides = cu * locator_.nv();
  const int i0 = cells[0] % cu, j0 = cells[0] / cu, i1 = cells[3] % cu, j1 = cells[3] / cu;
  if (i1 > i0) {
    t.kink =
        std::max({t.kink, side_kink_[u_sides + i1 + nu * j0], side_kink_[u_sides + i1 + nu * j1]});
  }
  if (j1 > j0) {
    t.kink = std::max({t.kink, side_kink_[i0 + cu * j1], side_kink_[i1 + cu * j1]});
  }
  return t;
}

bool Subdivider::Terms(int a, int b, int c, CellEstimate* terms) const {
  if (a == b && b == c && a >= 0) {  // inside one cell: most faces of a fine model
    *terms = cells_[a];
    return true;
  }
  std::array<int, 4> block;
  if (!Block(a, b, c, &block)) return false;
  *terms = BlockTerms(block);
  return true;
}

Subdivider::Extent Subdivider::FaceExtent(const std::array<uint32_t, 3>& corners) const {
  const Vec3 &p0 = placed_[corners[0]], &p1 = placed_[corners[1]], &p2 = placed_[corners[2]];
  const double h_lo = std::min({p0.z(), p1.z(), p2.z()});
  const double h_hi = std::max({p0.z(), p1.z(), p2.z()});
  return {std::max({(p1 - p0).head<2>().squaredNorm(), (p2 - p1).head<2>().squaredNorm(),
                    (p0 - p2).head<2>().squaredNorm()}),
          h_hi - h_lo, std::max(std::abs(h_lo), std::abs(h_hi))};
}

void Subdivider::RefineEdges() {
  ParallelChunks(static_cast<int>(edges_.size()), threads_, [&](int, int begin, int end) {
    int hint = -1;
    struct Span {
      double ta, tb;
      Vec3 fa, fb;
      int depth;
    };
    std::vector<Span> stack;
    for (int e = begin; e < end && !OutOfTime(); ++e) {
      Edge& edge = edges_[e];
      std::vector<double> ts;
      for (const EdgePoint& p : edge.points) {
        if (p.marked) ts.push_back(p.crossing.t);
      }
      std::vector<Vec3> fs(ts.size());
      for (size_t q = 0; q < ts.size(); ++q) fs[q] = Deformed(EdgePlaced(edge, ts[q]), &hint);
      CellEstimate terms;
      if (ts.empty() &&
          Terms(vertex_cell_[edge.v0], vertex_cell_[edge.v1], vertex_cell_[edge.v1], &terms)) {
        const Vec3 d = placed_[edge.v1] - placed_[edge.v0];
        const double h = std::max(std::abs(placed_[edge.v0].z()), std::abs(placed_[edge.v1].z()));
        const double estimate = EstimateOf(terms, d.head<2>().norm(), d.z(), h);
        if (!refine_ || estimate <= kSkipShare * tolerance_) {
          edge.tally.max_estimate = estimate;
          edge.kept_t = std::move(ts);
          continue;
        }
      }
      // Measure each piece at its middle and at the grid crossings inside it
      // that were not kept (where the map has kinks); with a tolerance, split
      // the ones that stray too far at their worst sample. This depends on the
      // edge alone.
      std::vector<double> out_t;
      std::vector<Vec3> out_f;
      Vec3 prev_f = deformed_[edge.v0];
      double prev_t = 0.0;
      for (size_t q = 0; q <= ts.size(); ++q) {
        const double next_t = q < ts.size() ? ts[q] : 1.0;
        const Vec3 next_f = q < ts.size() ? fs[q] : deformed_[edge.v1];
        stack.clear();
        stack.push_back({prev_t, next_t, prev_f, next_f, 0});
        // Depth first, left half last pushed: points come out in order.
        while (!stack.empty()) {
          const Span s = stack.back();
          stack.pop_back();
          double worst = -1.0, worst_t = 0.5 * (s.ta + s.tb);
          Vec3 worst_f = Vec3::Zero();
          auto sample = [&](double t) {
            const Vec3 fm = Deformed(EdgePlaced(edge, t), &hint);
            const double w = (t - s.ta) / (s.tb - s.ta);
            const double dev = (fm - ((1.0 - w) * s.fa + w * s.fb)).norm();
            ++edge.tally.measured;
            if (dev > worst) {
              worst = dev;
              worst_t = t;
              worst_f = fm;
            }
          };
          // Quarter points too: an S-shaped deviation (an inflection) is
          // near zero at the middle.
          for (double w : {0.25, 0.5, 0.75}) sample(s.ta + w * (s.tb - s.ta));
          const auto first =
              std::upper_bound(edge.points.begin(), edge.points.end(), s.ta,
                               [](double t, const EdgePoint& p) { return t < p.crossing.t; });
          for (auto it = first; it != edge.points.end() && it->crossing.t < s.tb; ++it) {
            if (!it->marked) sample(it->crossing.t);
          }
          const bool split = refine_ && worst > kEdgeShare * tolerance_ &&
                             s.depth < kMaxBisections &&
                             (s.tb - s.ta) * (placed_[edge.v1] - placed_[edge.v0]).norm() >
                                 1e-9 * locator_.bounds().diagonal().norm() &&
                             !over_limit_.load();
          if (!split) {
            edge.tally.max_dev = std::max(edge.tally.max_dev, worst);
            if (s.tb < next_t) {  // a split point closes this span
              out_t.push_back(s.tb);
              out_f.push_back(s.fb);
            }
            continue;
          }
          ++edge.tally.refinement;
          if (added_.fetch_add(1) + 1 > options_.max_vertices) over_limit_ = true;
          stack.push_back({worst_t, s.tb, worst_f, s.fb, s.depth + 1});
          stack.push_back({s.ta, worst_t, s.fa, worst_f, s.depth + 1});
        }
        if (q < ts.size()) {
          out_t.push_back(next_t);
          out_f.push_back(next_f);
        }
        prev_t = next_t;
        prev_f = next_f;
      }
      edge.kept_t = std::move(out_t);
      edge.kept_f = std::move(out_f);
    }
  });
}

void Subdivider::RefineFace(size_t fi, FaceOutput* out, int* hint) {
  const Face& f = faces_[fi];
  if (f.degenerate) return;
  bool on_sides = false;
  double edge_dev = 0.0, edge_estimate = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Edge& e = edges_[f.edge[k]];
    on_sides = on_sides || !e.kept_t.empty();
    edge_dev = std::max(edge_dev, e.tally.max_dev);
    edge_estimate = std::max(edge_estimate, e.tally.max_estimate);
  }
  for (const FacePoint& p : f.points) out->face_points_kept += p.kept ? 1 : 0;
  const Vec3 f0 = deformed_[f.corner[0]], f1 = deformed_[f.corner[1]], f2 = deformed_[f.corner[2]];
  if (!on_sides && out->face_points_kept == 0) {
    // The face as it is, when it is close enough to the exact deformation.
    CellEstimate terms;
    if (Terms(vertex_cell_[f.corner[0]], vertex_cell_[f.corner[1]], vertex_cell_[f.corner[2]],
              &terms)) {
      const Extent x = FaceExtent(f.corner);
      const double estimate = EstimateOf(terms, std::sqrt(x.longest2), x.dh, x.h);
      if (!refine_ || estimate <= kSkipShare * tolerance_) {
        out->tally.max_estimate = std::max(estimate, edge_estimate);
        out->tally.max_dev = edge_dev;
        return;
      }
    }
    const Vec3 fc = Deformed(Placed(f, 1.0 / 3, 1.0 / 3), hint);
    const double dev = (fc - (f0 + f1 + f2) / 3.0).norm();
    out->tally.measured = 1;
    out->tally.max_dev = std::max(dev, edge_dev);
    out->tally.max_estimate = edge_estimate;
    if (!refine_ || dev <= kFaceShare * tolerance_) return;
  }

  // The face's own frame: corner 0 at the origin, corner 1 on +x, corner 2
  // above (counter-clockwise, so triangles keep the face's orientation). A
  // face of (nearly) zero area gets its barycentric frame instead.
  const Vec3 e1 = placed_[f.corner[1]] - placed_[f.corner[0]];
  const Vec3 e2 = placed_[f.corner[2]] - placed_[f.corner[0]];
  const Vec3 nrm = e1.cross(e2);
  Vec2 q1(1, 0), q2(0, 1);
  if (nrm.norm() > 1e-12 * e1.norm() * e2.norm() && e1.norm() > 0.0) {
    const Vec3 x = e1.normalized();
    const Vec3 y = nrm.normalized().cross(x);
    q1 = Vec2(e1.norm(), 0.0);
    q2 = Vec2(e2.dot(x), e2.dot(y));
  }
  Eigen::Matrix2d frame;
  frame.col(0) = q1;
  frame.col(1) = q2;
  const Eigen::Matrix2d to_bary = frame.inverse();
  FaceTriangulation tri(Vec2::Zero(), q1, q2);
  std::vector<Vec3> fval = {f0, f1, f2};
  std::vector<LocalPoint>& local = out->points;
  const Vec2 corner_bary[3] = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  auto add_new = [&](const LocalPoint& lp, const Vec3& fv) {
    local.push_back(lp);
    fval.push_back(fv);
  };

  // Sides: the kept points of each edge, in the face's direction.
  std::vector<int> side_ids[3];
  for (int k = 0; k < 3; ++k) {
    const Edge& e = edges_[f.edge[k]];
    const size_t m = e.kept_t.size();
    side_ids[k].assign(m, -1);
    int prev = k;
    const int next = (k + 1) % 3;
    for (size_t q = 0; q < m; ++q) {
      const size_t idx = f.reversed[k] ? m - 1 - q : q;
      const double t = f.reversed[k] ? 1.0 - e.kept_t[idx] : e.kept_t[idx];
      const Vec2 l = corner_bary[k] + t * (corner_bary[next] - corner_bary[k]);
      const int id = tri.SplitBoundary(prev, next, frame * l);
      if (id != static_cast<int>(fval.size())) {
        failed_ = true;  // cannot happen: sides are only split here, in order
        return;
      }
      add_new({k, static_cast<int>(idx), l.x(), l.y()}, e.kept_f[idx]);
      side_ids[k][idx] = id;
      prev = id;
    }
  }
  // Kept face points, then the kept chords through them as constraints.
  std::vector<int> point_ids(f.points.size(), -1);
  for (size_t q = 0; q < f.points.size(); ++q) {
    if (!f.points[q].kept) continue;
    const GridNodeInside& node = f.points[q].node;
    const int id = tri.Insert(frame * Vec2(node.l1, node.l2));
    if (id < 0) continue;
    if (id == static_cast<int>(fval.size())) {
      add_new({-1, -1, node.l1, node.l2}, Deformed(Placed(f, node.l1, node.l2), hint));
    }
    point_ids[q] = id;
  }
  if (f.large) {
    for (const Chord& chord : Chords(f)) {
      if (!ChordKept(f, chord)) continue;
      int prev = -1;
      for (const ChordEntry& e : chord.entries) {
        int id = -1;
        if (e.side < 0) {
          id = point_ids[e.ref];
        } else {
          const Edge& edge = edges_[f.edge[e.side]];
          const double t = edge.points[e.ref].crossing.t;
          const auto it = std::lower_bound(edge.kept_t.begin(), edge.kept_t.end(), t);
          if (it != edge.kept_t.end() && *it == t) id = side_ids[e.side][it - edge.kept_t.begin()];
        }
        if (id < 0) continue;
        if (prev >= 0) tri.Constrain(prev, id);
        prev = id;
      }
    }
    tri.RestoreDelaunay();
  }

  // Deviation of each triangle: at its edge midpoints, its centroid and the
  // three points halfway from it to the corners, the exact deformation
  // against the triangle's linear interpolation.
  struct Cached {
    uint32_t stamp = 0;
    double dev = -1.0;
  };
  std::vector<Cached> cache;
  auto deviation = [&](int t) {
    const FaceTriangulation::Triangle& tr = tri.triangles()[t];
    if (static_cast<size_t>(t) >= cache.size()) cache.resize(tri.triangles().size());
    if (cache[t].dev >= 0.0 && cache[t].stamp == tr.stamp) return cache[t].dev;
    const std::vector<Vec2>& pts = tri.points();
    double dev = 0.0;
    constexpr double a = 2.0 / 3, b = 1.0 / 6, c = 1.0 / 3;
    const double w[7][3] = {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {c, c, c},
                            {a, b, b},     {b, a, b},     {b, b, a}};
    for (const auto& ww : w) {
      // A midpoint on the face's outline is its edge's to measure and refine.
      const int zero = ww[0] == 0.0 ? 0 : ww[1] == 0.0 ? 1 : ww[2] == 0.0 ? 2 : -1;
      if (zero >= 0 && tri.OnOutline(t, zero)) continue;
      const Vec2 p = ww[0] * pts[tr.v[0]] + ww[1] * pts[tr.v[1]] + ww[2] * pts[tr.v[2]];
      const Vec2 l = to_bary * p;
      const Vec3 exact = Deformed(Placed(f, l.x(), l.y()), hint);
      const Vec3 linear = ww[0] * fval[tr.v[0]] + ww[1] * fval[tr.v[1]] + ww[2] * fval[tr.v[2]];
      dev = std::max(dev, (exact - linear).norm());
    }
    out->tally.measured += 7;
    cache[t] = {tr.stamp, dev};
    return dev;
  };

  if (refine_) {
    const double target = kFaceShare * tolerance_;
    using Item = std::tuple<double, int, uint32_t>;
    std::priority_queue<Item> queue;
    for (size_t t = 0; t < tri.triangles().size(); ++t) {
      const double d = deviation(static_cast<int>(t));
      if (d > target) queue.push({d, static_cast<int>(t), tri.triangles()[t].stamp});
    }
    tri.TakeTouched();
    while (!queue.empty() && !over_limit_.load() && !OutOfTime()) {
      const auto [priority, t, stamp] = queue.top();
      queue.pop();
      if (tri.triangles()[t].stamp != stamp) continue;
      // Split the edge that strays most at its middle among those not on the
      // face's outline (sides only get points from their edge), or the
      // longest of them when none strays (the deviation is inside): the
      // refinement follows the bending, across a cylinder but not along it.
      // A triangle that is the whole face gets its centroid.
      const FaceTriangulation::Triangle tr = tri.triangles()[t];
      const std::vector<Vec2>& pts = tri.points();
      int best = -1;
      double best_len = 0.0, best_dev = 0.0, longest = 0.0;
      int longest_k = -1;
      for (int k = 0; k < 3; ++k) {
        if (tri.OnOutline(t, k)) continue;
        const int a = tr.v[(k + 1) % 3], b = tr.v[(k + 2) % 3];
        const double len = (pts[a] - pts[b]).norm();
        if (len > longest) {
          longest = len;
          longest_k = k;
        }
        const Vec2 l = to_bary * (0.5 * (pts[a] + pts[b]));
        const double dev =
            (Deformed(Placed(f, l.x(), l.y()), hint) - 0.5 * (fval[a] + fval[b])).norm();
        if (dev > best_dev) {
          best_dev = dev;
          best = k;
          best_len = len;
        }
      }
      if (best_dev <= 0.25 * target) {
        best = longest_k;
        best_len = longest;
      }
      const size_t before = fval.size();
      if (best >= 0) {
        if (best_len < 1e-6 * tri.size()) continue;  // as fine as it gets
        // Beside a side of the face whose own deviation is too large, thinner
        // and thinner triangles cannot help: stop at 1/1000 of the side.
        bool sliver = false;
        for (int k = 0; k < 3 && !sliver; ++k) {
          if (!tri.OnOutline(t, k)) continue;
          const Vec2 a = pts[tr.v[(k + 1) % 3]], b = pts[tr.v[(k + 2) % 3]];
          const Vec2 ab = b - a, ac = pts[tr.v[k]] - a;
          const double len2 = ab.squaredNorm();
          sliver = std::abs(ab.x() * ac.y() - ab.y() * ac.x()) < 1e-3 * len2;
        }
        if (sliver) continue;
        tri.SplitInteriorEdge(t, best);
      } else {
        tri.Insert((pts[tr.v[0]] + pts[tr.v[1]] + pts[tr.v[2]]) / 3.0);
      }
      for (size_t id = before; id < tri.points().size(); ++id) {
        const Vec2 l = to_bary * tri.points()[id];
        add_new({-1, -1, l.x(), l.y()}, Deformed(Placed(f, l.x(), l.y()), hint));
        ++out->tally.refinement;
        if (added_.fetch_add(1) + 1 > options_.max_vertices) over_limit_ = true;
      }
      for (int u : tri.TakeTouched()) {
        const double du = deviation(u);
        if (du > target) queue.push({du, u, tri.triangles()[u].stamp});
      }
    }
  }
  out->tally.max_dev = edge_dev;
  out->tally.max_estimate = edge_estimate;
  out->triangles.reserve(tri.triangles().size());
  for (size_t t = 0; t < tri.triangles().size(); ++t) {
    out->tally.max_dev = std::max(out->tally.max_dev, deviation(static_cast<int>(t)));
    const auto& v = tri.triangles()[t].v;
    out->triangles.push_back({v[0], v[1], v[2]});
  }
}

Status Subdivider::TimeUp() const {
  const double spent =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  return Status::LimitExceeded(
      "the subdivision did not finish within its time budget of " +
          std::to_string(static_cast<long long>(options_.time_budget_ms)) +
          " ms; raise subdivision.tolerance or epsilon, use mode \"off\", or a coarser grid",
      "subdivision", options_.time_budget_ms, spent);
}

Result<SubdivisionResult> Subdivider::Assemble() {
  SubdivisionResult r;
  Mesh& out = r.mesh;
  const Mesh& in = mesh_;
  out = in;  // the input's vertices first, in order; triangles rebuilt below
  r.placed = placed_;
  out.triangles.clear();
  auto append = [&](const uint32_t* v, const double* w, int count) {
    Vec3 pos = Vec3::Zero(), pl = Vec3::Zero();
    for (int q = 0; q < count; ++q) {
      pos += w[q] * in.positions[v[q]];
      pl += w[q] * placed_[v[q]];
    }
    out.positions.push_back(pos);
    r.placed.push_back(pl);
    if (!in.normals.empty()) {
      Vec3 nn = Vec3::Zero();
      for (int q = 0; q < count; ++q) nn += w[q] * in.normals[v[q]];
      out.normals.push_back(nn.norm() > 1e-12 ? nn.normalized() : in.normals[v[0]]);
    }
    if (!in.tangents.empty()) {
      Vec3 tt = Vec3::Zero();
      double sign = 0.0;
      for (int q = 0; q < count; ++q) {
        tt += w[q] * in.tangents[v[q]].head<3>();
        sign += w[q] * in.tangents[v[q]].w();
      }
      if (!(tt.norm() > 1e-12)) tt = in.tangents[v[0]].head<3>();
      tt.normalize();
      out.tangents.emplace_back(tt.x(), tt.y(), tt.z(), sign < 0.0 ? -1.0 : 1.0);
    }
    auto lerp2 = [&](const std::vector<Vec2>& a, std::vector<Vec2>* o) {
      if (a.empty()) return;
      Vec2 x = Vec2::Zero();
      for (int q = 0; q < count; ++q) x += w[q] * a[v[q]];
      o->push_back(x);
    };
    lerp2(in.uv0, &out.uv0);
    lerp2(in.uv1, &out.uv1);
    if (!in.colors.empty()) {
      Vec4 c = Vec4::Zero();
      for (int q = 0; q < count; ++q) c += w[q] * in.colors[v[q]];
      out.colors.push_back(c);
    }
  };

  std::unordered_map<uint64_t, uint32_t> side_base;  // (vertex pair) -> first of its points
  std::vector<uint32_t> per_face(faces_.size(), 1);
  std::vector<uint32_t> ids;
  SubdivisionStats& st = r.stats;
  st = stats_;
  Tally total;
  for (size_t fi = 0; fi < faces_.size(); ++fi) {
    const Face& f = faces_[fi];
    const FaceOutput& o = outputs_[fi];
    st.face_points_kept += o.face_points_kept;
    total.Add(o.tally);
    if (f.large) st.face_points_considered += f.points.size();
    if (o.triangles.empty()) {
      out.triangles.push_back(in.triangles[fi]);
      continue;
    }
    ids.assign(3 + o.points.size(), 0);
    for (int k = 0; k < 3; ++k) ids[k] = f.corner[k];
    for (size_t q = 0; q < o.points.size(); ++q) {
      const LocalPoint& lp = o.points[q];
      if (lp.side >= 0) {
        const Edge& e = edges_[f.edge[lp.side]];
        const uint32_t a = f.corner[lp.side], b = f.corner[(lp.side + 1) % 3];
        const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
        auto [it, fresh] = side_base.try_emplace(key, static_cast<uint32_t>(out.positions.size()));
        if (fresh) {
          // The edge's points for this pair of vertices (a texture seam has
          // two pairs at the same positions: same points, own attributes).
          const uint32_t from = weld_[a] == e.w0 ? a : b, to = from == a ? b : a;
          for (double t : e.kept_t) {
            const uint32_t v[2] = {from, to};
            const double w[2] = {1.0 - t, t};
            append(v, w, 2);
          }
        }
        ids[3 + q] = it->second + lp.index;
      } else {
        ids[3 + q] = static_cast<uint32_t>(out.positions.size());
        const uint32_t v[3] = {f.corner[0], f.corner[1], f.corner[2]};
        const double w[3] = {1.0 - lp.l1 - lp.l2, lp.l1, lp.l2};
        append(v, w, 3);
      }
    }
    per_face[fi] = static_cast<uint32_t>(o.triangles.size());
    for (const auto& t : o.triangles) out.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
  }
  for (const Edge& e : edges_) {
    total.Add(e.tally);
    if (!e.candidate) continue;
    st.edge_points_considered += e.points.size();
    for (const EdgePoint& p : e.points) st.edge_points_kept += p.marked ? 1 : 0;
  }
  st.refinement_points += total.refinement;
  st.max_deviation = std::max(st.max_deviation, total.max_dev);
  st.max_estimated_deviation = std::max(st.max_estimated_deviation, total.max_estimate);
  st.measured_points += total.measured;
  // Groups cover the refined triangles of their faces.
  uint32_t first = 0;
  size_t face = 0;
  for (MeshGroup& g : out.groups) {
    uint32_t count = 0;
    for (uint32_t q = 0; q < g.triangle_count; ++q) count += per_face[face++];
    g.first_triangle = first;
    g.triangle_count = count;
    first += count;
  }
  st.vertices_after = out.positions.size();
  st.triangles_after = out.triangles.size();
  if (st.vertices_after > options_.max_vertices) {
    return OverLimit("vertices", options_.max_vertices, st.vertices_after);
  }
  if (st.triangles_after > options_.max_triangles) {
    return OverLimit("triangles", options_.max_triangles, st.triangles_after);
  }
  return r;
}

// Each input vertex's cell (-1 off the sheet) and either its deformed
// position (those on the sheet as the deformation computes them, so that it
// can reuse them: when the mesh has no normals or tangents to carry) or its
// surface parameters (for DeformVertices, when the refinement needs the
// positions: the deformation, which needs the map's Jacobian as well, starts
// over); with outside = error, the count of those off the sheet and the worst
// distance, as the deformation would report them (before any work is spent
// refining a model that fails).
Status Subdivider::LocateVertices() {
  const size_t n = mesh_.positions.size();
  vertex_cell_.resize(n);
  on_sheet_.resize(n);
  if (positions_reused_) {
    deformed_.resize(n);
  } else {
    vertex_uv_.resize(n);
  }
  std::vector<size_t> outside(threads_, 0);
  std::vector<double> worst(threads_, 0.0);
  const bool exact = map_.sheet().method == "exact";
  ParallelChunks(static_cast<int>(n), threads_, [&](int chunk, int begin, int end) {
    int hint = -1;
    for (int k = begin; k < end; ++k) {
      const Vec3& abh = placed_[k];
      const SheetParameters p = map_.Parameters(abh.head<2>(), OutsideMode::kError, false, &hint);
      on_sheet_[k] = !p.outside;
      if (p.outside) {
        ++outside[chunk];
        worst[chunk] = std::max(worst[chunk], p.outside_distance);
      }
      if (!positions_reused_) {
        vertex_uv_[k] = p.uv;
      } else if (p.outside) {
        deformed_[k] = Deformed(abh, &hint);
      } else {
        deformed_[k] = OffsetAlongNormal(map_.surface().Evaluate(p.uv.x(), p.uv.y(), 1), abh.z());
      }
      int cell = p.cell;
      if (exact) {  // the closed-form inverse located nothing: find the cell
        SheetLocation l;
        cell = locator_.Locate(abh.head<2>(), &l, &hint) ? locator_.CellIndex(l) : -1;
      }
      vertex_cell_[k] = cell;
    }
  });
  size_t count = 0;
  double far = 0.0;
  for (int c = 0; c < threads_; ++c) {
    count += outside[c];
    far = std::max(far, worst[c]);
  }
  if (refuse_outside_ && count > 0) return OutsideSheetError(count, n, far);
  return Status::Ok();
}

// The deformed input vertices, for the refinement, unless LocateVertices
// computed them.
void Subdivider::DeformVertices() {
  if (positions_reused_) return;
  const size_t n = mesh_.positions.size();
  deformed_.resize(n);
  ParallelChunks(static_cast<int>(n), threads_, [&](int, int begin, int end) {
    int hint = -1;
    for (int k = begin; k < end; ++k) {
      const Vec3& abh = placed_[k];
      deformed_[k] =
          on_sheet_[k]
              ? OffsetAlongNormal(map_.surface().Evaluate(vertex_uv_[k].x(), vertex_uv_[k].y(), 1),
                                  abh.z())
              : Deformed(abh, &hint);
    }
  });
}

// What the deformation reuses: the positions of the input vertices on the
// sheet, NaN for the others; none when it will not reuse them.
std::vector<Vec3> Subdivider::InputPositions() {
  if (!positions_reused_) return {};
  std::vector<Vec3> out = std::move(deformed_);
  for (size_t k = 0; k < out.size(); ++k) {
    if (!on_sheet_[k]) out[k] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

Result<SubdivisionResult> Subdivider::Run() {
  const auto t0 = std::chrono::steady_clock::now();
  const size_t n = mesh_.positions.size();
  stats_.mode = options_.mode;
  stats_.vertices_before = n;
  stats_.triangles_before = mesh_.triangles.size();
  stats_.epsilon = uniform_ ? 0.0 : options_.epsilon;
  stats_.tolerance = refine_ ? tolerance_ : 0.0;

  SURFDEFORM_RETURN_IF_ERROR(LocateVertices());
  ComputeCellEstimates();
  if (Screen()) {
    SubdivisionResult r;
    r.unchanged = true;
    r.stats = stats_;
    r.stats.vertices_after = r.stats.vertices_before;
    r.stats.triangles_after = r.stats.triangles_before;
    r.input_positions = InputPositions();
    r.stats.time_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  // Each phase is bounded by the input's size; the refinement, by the output
  // limits and the time budget.
  for (void (Subdivider::*phase)() :
       {&Subdivider::Weld, &Subdivider::DeformVertices, &Subdivider::BuildEdges,
        &Subdivider::FindEdgePoints, &Subdivider::ClassifyFaces, &Subdivider::FindFacePoints,
        &Subdivider::Mark, &Subdivider::RefineEdges}) {
    if (OutOfTime()) return TimeUp();
    (this->*phase)();
  }
  if (over_limit_) {
    return OverLimit("new vertices", options_.max_vertices, added_.load());
  }
  if (OutOfTime()) return TimeUp();
  outputs_.resize(faces_.size());
  ParallelChunks(static_cast<int>(faces_.size()), threads_, [&](int, int begin, int end) {
    int hint = -1;
    for (int f = begin; f < end && !OutOfTime(); ++f) RefineFace(f, &outputs_[f], &hint);
  });
  if (over_limit_) {
    return OverLimit("new vertices", options_.max_vertices, added_.load());
  }
  if (OutOfTime()) return TimeUp();
  if (failed_) {
    return Status(ErrorCode::kInternal, "the subdivision could not re-triangulate a face");
  }
  auto result = Assemble();
  if (!result.ok()) return result;
  result->input_positions = InputPositions();
  result->stats.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace

const char* SubdivisionModeName(SubdivisionMode mode) {
  switch (mode) {
    case SubdivisionMode::kOff:
      return "off";
    case SubdivisionMode::kAdaptive:
      return "adaptive";
    case SubdivisionMode::kUniform:
      return "uniform";
  }
  return "off";
}

Status ValidateSubdivision(const SubdivisionOptions& o) {
  if (!(std::isfinite(o.epsilon) && o.epsilon >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (1 / surface units; 0 = none)",
                           "subdivision.epsilon");
  }
  if (!(std::isfinite(o.tolerance) && o.tolerance >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (surface units; 0 = automatic)",
                           "subdivision.tolerance");
  }
  if (o.max_vertices == 0 || o.max_triangles == 0) {
    return InvalidArgument("the output size limits must be positive", "subdivision");
  }
  if (o.threads < 0 || o.threads > 256) {
    return InvalidArgument("must be from 0 to 256", "subdivision.threads");
  }
  if (!(std::isfinite(o.time_budget_ms) && o.time_budget_ms >= 0.0)) {
    return InvalidArgument("must be a finite number >= 0 (milliseconds; 0 = none)",
                           "subdivision.time_budget_ms");
  }
  return Status::Ok();
}

Result<SubdivisionResult> Subdivide(const Mesh& mesh, const std::vector<Vec3>& placed,
                                    const SheetMap& map, OutsideMode outside,
                                    const SubdivisionOptions& options) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateSubdivision(options));
  if (placed.size() != mesh.positions.size()) {
    return InvalidArgument("one placed position per vertex is needed", "mesh");
  }
  if (options.mode == SubdivisionMode::kOff) {
    SubdivisionResult r;
    r.unchanged = true;
    r.stats.vertices_before = r.stats.vertices_after = mesh.positions.size();
    r.stats.triangles_before = r.stats.triangles_after = mesh.triangles.size();
    return r;
  }
  Subdivider s(mesh, placed, map, outside, options);
  return s.Run();
}

}  // namespace surfdeform
