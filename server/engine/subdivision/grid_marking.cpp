#include "engine/subdivision/grid_marking.hpp"

#include <algorithm>
#include <cmath>

#include "engine/common/parallel.hpp"
#include "engine/subdivision/target_edges.hpp"

namespace surfdeform::subdivision {
namespace {

// The grid crossings of each edge, and whether it is larger than its cells.
void FindEdgePoints(const Context& ctx, const EdgeGraph& graph,
                    const IdVector<VertexId, int>& vertex_cell, const CellEstimates& estimates,
                    Budget* budget, GridMarking* m) {
  ParallelChunks(static_cast<int>(graph.edges.size()), ctx.threads, [&](int, int begin, int end) {
    std::vector<GridCrossing> crossings;
    std::vector<int> scratch;
    for (int e = begin; e < end && !budget->TooManyCrossings(); ++e) {
      const GraphEdge& edge = graph.edges[EdgeId(e)];
      EdgeMarks& marks = m->edges[EdgeId(e)];
      const int c0 = vertex_cell[edge.v0], c1 = vertex_cell[edge.v1];
      const Vec2 a = ctx.Placed(edge.v0).head<2>(), b = ctx.Placed(edge.v1).head<2>();
      if (ctx.target != nullptr) {
        // A mesh surface bends only across its edges: an edge that crosses
        // none lies on one flat triangle.
        ctx.target->Crossings(a, b, &crossings, &marks.cell_side, &scratch);
        // Without the point where it crosses a kink j, the edge strays at
        // most j l / 4: crossings that cannot pass the threshold are left
        // out (every one counts in uniform mode).
        const double length = (b - a).norm();
        const double h =
            std::max(std::abs(ctx.Placed(edge.v0).z()), std::abs(ctx.Placed(edge.v1).z()));
        // With epsilon, a crossing is needed where the kink over the crossed
        // edge's length (a curvature) passes it.
        const double epsilon = ctx.options.epsilon;
        if (!ctx.uniform) {
          marks.kink_threshold = ctx.tolerance > 0.0 && length > 0.0
                                     ? 4.0 * kEdgeShare * ctx.tolerance / length
                                     : kInf;
          if (epsilon > 0.0) marks.threshold = epsilon;
          std::erase_if(crossings, [&](const GridCrossing& c) {
            const TargetEdges::Edge& crossed = ctx.target->edges()[c.u_line];
            const double kink = crossed.KinkAt(h);
            return !(kink > marks.kink_threshold ||
                     (epsilon > 0.0 && kink > epsilon * crossed.length));
          });
        }
        marks.long_edge = !crossings.empty();
        if (!budget->AddCrossings(crossings.size())) break;
        marks.points.resize(crossings.size());
        for (size_t k = 0; k < crossings.size(); ++k) marks.points[k].crossing = crossings[k];
        continue;
      }
      CellTerms terms;
      const bool in_block = estimates.Terms(c0, c1, c1, &terms);
      if (in_block) {
        // Within a 2 x 2 block of cells: as large as a cell, or not (the
        // same test as the screen's).
        marks.cell_side = terms.min_side;
        marks.long_edge = (b - a).norm() > marks.cell_side;
        if (c0 == c1) continue;  // inside one (convex) cell: no crossing
      }
      double min_side;
      GridCrossings(ctx.locator, a, b, &crossings, &scratch, &min_side);
      if (!in_block) {
        marks.long_edge = (b - a).norm() > min_side;
        marks.cell_side = min_side;
      }
      if (!budget->AddCrossings(crossings.size())) break;
      marks.points.resize(crossings.size());
      for (size_t k = 0; k < crossings.size(); ++k) marks.points[k].crossing = crossings[k];
    }
  });
}

// Large faces and their thresholds; their edges become candidates.
void ClassifyFaces(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  for (size_t fi = 0; fi < graph.faces.size(); ++fi) {
    const GraphFace& face = graph.faces[FaceId(fi)];
    FaceMarks& f = m->faces[FaceId(fi)];
    if (face.degenerate) continue;
    double cell = kInf;
    for (int k = 0; k < 3; ++k) {
      const EdgeMarks& e = m->edges[face.edge[k]];
      f.large = f.large || e.long_edge || ctx.uniform;
      cell = std::min(cell, e.cell_side);
    }
    if (!f.large) continue;
    if (ctx.uniform) {
      f.threshold = -kInf;
    } else if (ctx.target != nullptr) {
      // A mesh surface: a vertex inside the face whose edges kink by j makes
      // the face stray about j l / 4 without it (l: the face's size).
      if (ctx.tolerance > 0.0) {
        double longest = 0.0;
        for (int k = 0; k < 3; ++k) {
          longest = std::max(longest, (ctx.Placed(face.corner[(k + 1) % 3]).head<2>() -
                                       ctx.Placed(face.corner[k]).head<2>())
                                          .norm());
        }
        if (longest > 0.0) f.threshold = 4.0 * kFaceShare * ctx.tolerance / longest;
      }
      // With epsilon: a kink j over the face's cells' size c, j / c, past it.
      if (ctx.options.epsilon > 0.0 && std::isfinite(cell)) {
        f.threshold = std::min(f.threshold, ctx.options.epsilon * cell);
      }
    } else {
      if (ctx.options.epsilon > 0.0) f.threshold = ctx.options.epsilon;
      // Without this grid point the pieces beside it double to about 2
      // cells: it is needed where k (2 c)^2 / 8 exceeds the tolerance, or
      // where the map's kink there, a jump j of its derivative, makes a piece
      // of 2 cells stray j (2 c) / 4 from it (the cell-wise bilinear map is
      // only continuous across grid lines).
      if (ctx.tolerance > 0.0 && std::isfinite(cell) && cell > 0.0) {
        f.threshold = std::min(f.threshold, 2.0 * kEdgeShare * ctx.tolerance / (cell * cell));
        f.kink_threshold = 2.0 * kEdgeShare * ctx.tolerance / cell;
      }
    }
    for (int k = 0; k < 3; ++k) {
      EdgeMarks& e = m->edges[face.edge[k]];
      e.candidate = true;
      // (A mesh surface's edge points have their own curvature threshold,
      // epsilon; its faces' is on kinks.)
      if (ctx.target == nullptr) e.threshold = std::min(e.threshold, f.threshold);
      e.kink_threshold = std::min(e.kink_threshold, f.kink_threshold);
    }
  }
}

// A mesh surface's vertices inside each large face. (How much the surface
// bends at one is its edges' kinks, which ChordKept reads per chord.)
void FindTargetVertices(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  ParallelChunks(static_cast<int>(graph.faces.size()), ctx.threads, [&](int, int begin, int end) {
    std::vector<GridNodeInside> nodes;
    for (int fi = begin; fi < end; ++fi) {
      FaceMarks& f = m->faces[FaceId(fi)];
      if (!f.large) continue;
      const auto& c = graph.faces[FaceId(fi)].corner;
      ctx.target->VerticesInside(ctx.Placed(c[0]).head<2>(), ctx.Placed(c[1]).head<2>(),
                                 ctx.Placed(c[2]).head<2>(), &nodes);
      f.points.resize(nodes.size());
      for (size_t k = 0; k < nodes.size(); ++k) f.points[k].node = nodes[k];
    }
  });
}

// The grid nodes inside each large face, with their curvatures.
void FindFacePoints(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  if (ctx.target != nullptr) {
    FindTargetVertices(ctx, graph, m);
    return;
  }
  ParallelChunks(static_cast<int>(graph.faces.size()), ctx.threads, [&](int, int begin, int end) {
    std::vector<GridNodeInside> nodes;
    std::vector<int> scratch;
    const double nu1 = ctx.locator.nu() - 1, nv1 = ctx.locator.nv() - 1;
    for (int fi = begin; fi < end; ++fi) {
      FaceMarks& f = m->faces[FaceId(fi)];
      if (!f.large) continue;
      const auto& c = graph.faces[FaceId(fi)].corner;
      GridNodesInside(ctx.locator, ctx.Placed(c[0]).head<2>(), ctx.Placed(c[1]).head<2>(),
                      ctx.Placed(c[2]).head<2>(), &nodes, &scratch);
      f.points.resize(nodes.size());
      for (size_t k = 0; k < nodes.size(); ++k) {
        f.points[k].node = nodes[k];
        if (ctx.uniform) continue;
        // A node's parameters are exact: (i / (nu - 1), j / (nv - 1)).
        const SurfacePoint s = ctx.map.surface().Evaluate(nodes[k].i / nu1, nodes[k].j / nv1, 2);
        f.points[k].across_u_line = std::abs(NormalCurvature(s, Vec2(1, 0)));
        f.points[k].across_v_line = std::abs(NormalCurvature(s, Vec2(0, 1)));
      }
    }
  });
}

// The curvature of each edge point of the candidate edges along its line(s),
// and the map's kink there along the edge (where a kink threshold applies).
void MeasureEdgePoints(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  ParallelChunks(static_cast<int>(graph.edges.size()), ctx.threads, [&](int, int begin, int end) {
    int hint = -1;
    for (int e = begin; e < end; ++e) {
      const GraphEdge& edge = graph.edges[EdgeId(e)];
      EdgeMarks& marks = m->edges[EdgeId(e)];
      if (!marks.candidate || marks.points.empty()) continue;
      const Vec2 a = ctx.Placed(edge.v0).head<2>(), b = ctx.Placed(edge.v1).head<2>();
      const bool kinks = std::isfinite(marks.kink_threshold) ||
                         (ctx.target != nullptr && std::isfinite(marks.threshold));
      const double step = 1e-4 * marks.cell_side;
      for (EdgePoint& p : marks.points) {
        const Vec2 at = a + p.crossing.t * (b - a);
        const SheetParameters sp = ctx.map.Parameters(at, ctx.outside, false, &hint);
        const SurfacePoint s = ctx.map.surface().Evaluate(sp.uv.x(), sp.uv.y(), 2);
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
        const Vec3 mid = ctx.Between(edge.v0, edge.v1, p.crossing.t);
        const Vec3 d3 = (ctx.Placed(edge.v1) - ctx.Placed(edge.v0)).normalized() * step;
        const Vec3 f0 = ctx.Deformed(mid, &hint);
        const Vec3 fp = ctx.Deformed(mid + d3, &hint), fm = ctx.Deformed(mid - d3, &hint);
        p.kink = ((fp - f0) - (f0 - fm)).norm() / step;
        if (ctx.target != nullptr) {
          // A mesh surface bends at its edges: its curvature there is the
          // kink over the crossed edge's length.
          const double crossed = ctx.target->edges()[p.crossing.u_line].length;
          if (crossed > 0.0) p.curvature = p.kink / crossed;
          // An edge's crossings are apart: one at t strays the straight edge
          // by j t (1 - t) l, which the threshold's j l / 4 counts at t = 1/2.
          p.kink *= 4.0 * p.crossing.t * (1.0 - p.crossing.t);
        }
      }
    }
  });
}

// True when the grid line of `chord` turns at `node` on the flat sheet (its
// pieces before and after the node are not collinear, to 1e-4 of their
// length).
bool ChordTurns(const FlatLocator& locator, const Chord& chord, const GridNodeInside& node) {
  const bool u_line = chord.line < locator.nu();
  const int i = node.i, j = node.j;
  const int last = u_line ? locator.nv() - 1 : locator.nu() - 1;
  const int at = u_line ? j : i;
  if (at == 0 || at == last) return false;
  const Vec2& a = u_line ? locator.Node(i, j - 1) : locator.Node(i - 1, j);
  const Vec2& b = u_line ? locator.Node(i, j + 1) : locator.Node(i + 1, j);
  const Vec2& p = locator.Node(i, j);
  return std::abs(Cross2(b - a, p - a)) > 1e-4 * (b - a).squaredNorm();
}

// A mesh surface's chords are its edges' pieces, which kink only where
// their edge does: a chord is kept for what its own points need, and its
// other end marked so that the face can follow it, without carrying the
// mark on along the edge (a grid line is kept whole: its curvature runs
// along it). One pass; the marks it adds do not keep chords.
void MarkTargetChords(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  std::vector<std::pair<EdgeId, int>> marks;
  for (size_t f = 0; f < graph.faces.size(); ++f) {
    const FaceId fi(static_cast<int>(f));
    if (!m->faces[fi].large) continue;
    for (const Chord& chord : Chords(ctx, graph, *m, fi)) {
      if (!ChordKept(ctx, graph, *m, fi, chord)) continue;
      for (const ChordEntry& e : chord.entries) {
        if (e.IsEdgePoint()) marks.push_back({graph.faces[fi].edge[e.side], e.ref});
      }
    }
  }
  for (const auto& [edge, ref] : marks) m->edges[edge].points[ref].marked = true;
}

// Marks the edge points of the chords kept, to a fixed point over the faces.
void PropagateChords(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  if (ctx.target != nullptr) {
    MarkTargetChords(ctx, graph, m);
    return;
  }
  std::vector<FaceId> queue;
  std::vector<char> queued(graph.faces.size(), 0);
  for (size_t f = 0; f < graph.faces.size(); ++f) {
    if (m->faces[FaceId(f)].large) {
      queue.push_back(FaceId(f));
      queued[f] = 1;
    }
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const FaceId fi = queue[head];
    queued[fi.value()] = 0;
    const GraphFace& face = graph.faces[fi];
    for (const Chord& chord : Chords(ctx, graph, *m, fi)) {
      if (!ChordKept(ctx, graph, *m, fi, chord)) continue;
      for (const ChordEntry& e : chord.entries) {
        if (!e.IsEdgePoint()) continue;
        const EdgeId id = face.edge[e.side];
        EdgePoint& p = m->edges[id].points[e.ref];
        if (p.marked) continue;
        p.marked = true;
        for (const FaceId* g = graph.FacesBegin(id); g != graph.FacesEnd(id); ++g) {
          if (*g != fi && m->faces[*g].large && !queued[g->value()]) {
            queued[g->value()] = 1;
            queue.push_back(*g);
          }
        }
      }
    }
  }
}

// Keeps the face points on kept chords where the chord turns, and where two
// kept chords cross; on a straight run of a chord they are not needed. On a
// mesh surface every one on a kept chord ends it (a chord is one of its
// edges).
void KeepFacePoints(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  const int nu = ctx.locator.nu();
  for (size_t fi = 0; fi < graph.faces.size(); ++fi) {
    FaceMarks& f = m->faces[FaceId(fi)];
    if (!f.large) continue;
    if (ctx.target != nullptr) {
      for (const Chord& chord : Chords(ctx, graph, *m, FaceId(fi))) {
        if (!ChordKept(ctx, graph, *m, FaceId(fi), chord)) continue;
        for (const ChordEntry& e : chord.entries) {
          if (!e.IsEdgePoint()) f.points[e.ref].kept = true;
        }
      }
      continue;
    }
    std::vector<char> on_u(f.points.size(), 0), on_v(f.points.size(), 0);
    for (const Chord& chord : Chords(ctx, graph, *m, FaceId(fi))) {
      if (!ChordKept(ctx, graph, *m, FaceId(fi), chord)) continue;
      for (const ChordEntry& e : chord.entries) {
        if (e.IsEdgePoint()) continue;
        (chord.line < nu ? on_u : on_v)[e.ref] = 1;
        if (ChordTurns(ctx.locator, chord, f.points[e.ref].node)) f.points[e.ref].kept = true;
      }
    }
    for (size_t q = 0; q < f.points.size(); ++q) {
      if (on_u[q] && on_v[q]) f.points[q].kept = true;
    }
  }
}

}  // namespace

GridMarking FindGridPoints(const Context& ctx, const EdgeGraph& graph,
                           const IdVector<VertexId, int>& vertex_cell,
                           const CellEstimates& estimates, Budget* budget) {
  GridMarking m;
  m.edges.resize(graph.edges.size());
  m.faces.resize(graph.faces.size());
  FindEdgePoints(ctx, graph, vertex_cell, estimates, budget, &m);
  if (budget->TooManyCrossings()) return m;
  ClassifyFaces(ctx, graph, &m);
  FindFacePoints(ctx, graph, &m);
  if (!ctx.uniform) MeasureEdgePoints(ctx, graph, &m);
  return m;
}

void SeedEdgePoints(const Context& ctx, GridMarking* m) {
  for (EdgeMarks& e : m->edges) {
    if (!e.candidate) continue;
    for (EdgePoint& p : e.points) {
      p.marked = ctx.uniform || p.curvature > e.threshold || p.kink > e.kink_threshold;
    }
  }
}

void MarkGridPoints(const Context& ctx, const EdgeGraph& graph, GridMarking* m) {
  SeedEdgePoints(ctx, m);
  PropagateChords(ctx, graph, m);
  KeepFacePoints(ctx, graph, m);
}

namespace {

// A mesh surface's chords in face `fi`: the pieces of its edges inside the
// face, each from an edge point or a vertex inside to the next (a straight
// edge meets a triangle in one piece).
std::vector<Chord> TargetChords(const Context& ctx, const EdgeGraph& graph,
                                const GridMarking& marking, FaceId fi) {
  using Kind = ChordEntry::Kind;
  std::vector<std::pair<int, ChordEntry>> entries;
  const GraphFace& face = graph.faces[fi];
  for (int k = 0; k < 3; ++k) {
    const EdgeMarks& e = marking.edges[face.edge[k]];
    for (size_t q = 0; q < e.points.size(); ++q) {
      const GridCrossing& c = e.points[q].crossing;
      entries.push_back({c.u_line, {c.u_along, Kind::kEdgePoint, k, static_cast<int>(q)}});
    }
  }
  const FaceMarks& f = marking.faces[fi];
  for (size_t q = 0; q < f.points.size(); ++q) {
    const int v = f.points[q].node.i;
    for (int edge : ctx.target->EdgesAt(v)) {
      const double along = ctx.target->edges()[edge].v[0] == v ? 0.0 : 1.0;
      entries.push_back({edge, {along, Kind::kFacePoint, 0, static_cast<int>(q)}});
    }
  }
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second.along < b.second.along;
  });
  std::vector<Chord> chords;
  for (size_t k = 0; k < entries.size(); ++k) {
    if (k == 0 || entries[k].first != entries[k - 1].first)
      chords.push_back({entries[k].first, {}});
    chords.back().entries.push_back(entries[k].second);
  }
  return chords;
}

}  // namespace

std::vector<Chord> Chords(const Context& ctx, const EdgeGraph& graph, const GridMarking& marking,
                          FaceId fi) {
  if (ctx.target != nullptr) return TargetChords(ctx, graph, marking, fi);
  struct Entry {
    int line;
    ChordEntry e;
  };
  using Kind = ChordEntry::Kind;
  std::vector<Entry> entries;
  const int nu = ctx.locator.nu();
  const GraphFace& face = graph.faces[fi];
  const FaceMarks& f = marking.faces[fi];
  for (int k = 0; k < 3; ++k) {
    const EdgeMarks& e = marking.edges[face.edge[k]];
    for (size_t q = 0; q < e.points.size(); ++q) {
      const GridCrossing& c = e.points[q].crossing;
      const int ref = static_cast<int>(q);
      if (c.u_line >= 0) entries.push_back({c.u_line, {c.u_along, Kind::kEdgePoint, k, ref}});
      if (c.v_line >= 0) entries.push_back({nu + c.v_line, {c.v_along, Kind::kEdgePoint, k, ref}});
    }
  }
  for (size_t q = 0; q < f.points.size(); ++q) {
    const GridNodeInside& n = f.points[q].node;
    const int ref = static_cast<int>(q);
    entries.push_back({n.i, {static_cast<double>(n.j), Kind::kFacePoint, 0, ref}});
    entries.push_back({nu + n.j, {static_cast<double>(n.i), Kind::kFacePoint, 0, ref}});
  }
  // By line, then along it; at one place a face point before the edge
  // points, and those by side.
  auto order = [](const ChordEntry& e) { return e.IsEdgePoint() ? e.side : -1; };
  std::sort(entries.begin(), entries.end(), [&](const Entry& a, const Entry& b) {
    if (a.line != b.line) return a.line < b.line;
    if (a.e.along != b.e.along) return a.e.along < b.e.along;
    return order(a.e) < order(b.e);
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
        open = e.IsEdgePoint();
        chords.back().entries.push_back(e);
        continue;  // a face point outside a chord stands alone
      }
      chords.back().entries.push_back(e);
      if (e.IsEdgePoint()) open = false;
    }
    k = end;
  }
  return chords;
}

bool ChordKept(const Context& ctx, const EdgeGraph& graph, const GridMarking& marking, FaceId fi,
               const Chord& chord) {
  const bool u_line = chord.line < ctx.locator.nu();
  const FaceMarks& f = marking.faces[fi];
  for (const ChordEntry& e : chord.entries) {
    if (e.IsEdgePoint()) {
      if (marking.edges[graph.faces[fi].edge[e.side]].points[e.ref].marked) return true;
    } else if (ctx.target != nullptr) {
      // A mesh surface's vertex needs the chords along its edges that kink.
      if (ctx.target->edges()[chord.line].kink > f.threshold) return true;
    } else {
      const FacePoint& p = f.points[e.ref];
      if ((u_line ? p.across_u_line : p.across_v_line) > f.threshold) return true;
    }
  }
  return false;
}

}  // namespace surfdeform::subdivision
