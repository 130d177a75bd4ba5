#include "engine/subdivision/edge_graph.hpp"

#include <algorithm>
#include <numeric>

namespace surfdeform::subdivision {

IdVector<VertexId, WeldedId> WeldByPosition(const std::vector<Vec3>& p) {
  const size_t n = p.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&p](uint32_t a, uint32_t b) {
    if (p[a].x() != p[b].x()) return p[a].x() < p[b].x();
    if (p[a].y() != p[b].y()) return p[a].y() < p[b].y();
    if (p[a].z() != p[b].z()) return p[a].z() < p[b].z();
    return a < b;
  });
  IdVector<VertexId, WeldedId> weld(n);
  for (size_t k = 0; k < n;) {
    size_t e = k + 1;
    while (e < n && p[order[e]] == p[order[k]]) ++e;
    for (size_t q = k; q < e; ++q) weld[VertexId(order[q])] = WeldedId(order[k]);
    k = e;
  }
  return weld;
}

EdgeGraph BuildEdgeGraph(const Mesh& mesh) {
  EdgeGraph g;
  g.weld = WeldByPosition(mesh.positions);
  const size_t nf = mesh.triangles.size();
  g.faces.resize(nf);
  // Edges grouped by their smaller welded end (CSR), then matched by the other.
  const size_t n = mesh.positions.size();
  std::vector<uint32_t> count(n + 1, 0);
  for (size_t f = 0; f < nf; ++f) {
    GraphFace& face = g.faces[FaceId(f)];
    for (int k = 0; k < 3; ++k) face.corner[k] = VertexId(mesh.triangles[f][k]);
    const uint32_t w[3] = {g.weld[face.corner[0]].value(), g.weld[face.corner[1]].value(),
                           g.weld[face.corner[2]].value()};
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
    const GraphFace& face = g.faces[FaceId(f)];
    if (face.degenerate) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = g.weld[face.corner[k]].value(),
                     b = g.weld[face.corner[(k + 1) % 3]].value();
      slots[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<uint32_t>(f), k};
    }
  }
  // Each vertex's slots, by the other end (then face, for determinism): a run
  // of equal ends is one edge, and its faces are the run's.
  g.edges.reserve(nf * 3 / 2 + 16);
  g.edge_faces.reserve(slots.size());
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
      const EdgeId id(g.edges.size());
      GraphEdge& e = g.edges.emplace_back();
      e.w0 = WeldedId(v);
      e.w1 = WeldedId(run->other);
      e.faces_begin = static_cast<uint32_t>(g.edge_faces.size());
      for (auto q = run; q != stop; ++q) {
        GraphFace& face = g.faces[FaceId(q->face)];
        face.edge[q->k] = id;
        face.reversed[q->k] = g.weld[face.corner[q->k]] != e.w0;
        g.edge_faces.push_back(FaceId(q->face));
      }
      e.faces_end = static_cast<uint32_t>(g.edge_faces.size());
      const GraphFace& first = g.faces[FaceId(run->face)];
      const VertexId c0 = first.corner[run->k], c1 = first.corner[(run->k + 1) % 3];
      e.v0 = first.reversed[run->k] ? c1 : c0;
      e.v1 = first.reversed[run->k] ? c0 : c1;
      run = stop;
    }
  }
  return g;
}

}  // namespace surfdeform::subdivision
