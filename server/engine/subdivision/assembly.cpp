#include "engine/subdivision/assembly.hpp"

#include <unordered_map>

namespace surfdeform::subdivision {
namespace {

// Appends vertices interpolated from input vertices to a refined mesh.
class VertexAppender {
 public:
  VertexAppender(const Mesh& in, const std::vector<Vec3>& placed, SubdivisionResult* r)
      : in_(in), placed_(placed), out_(r->mesh), out_placed_(r->placed) {}

  // A new vertex at weights w of input vertices v (count of them).
  void Append(const VertexId* v, const double* w, int count);

 private:
  template <typename T>
  T Blend(const std::vector<T>& a, const VertexId* v, const double* w, int count) const {
    T x = T::Zero();
    for (int q = 0; q < count; ++q) x += w[q] * a[v[q].value()];
    return x;
  }

  const Mesh& in_;
  const std::vector<Vec3>& placed_;
  Mesh& out_;
  std::vector<Vec3>& out_placed_;
};

void VertexAppender::Append(const VertexId* v, const double* w, int count) {
  out_.positions.push_back(Blend(in_.positions, v, w, count));
  out_placed_.push_back(Blend(placed_, v, w, count));
  const uint32_t first = v[0].value();
  if (!in_.normals.empty()) {
    const Vec3 nn = Blend(in_.normals, v, w, count);
    out_.normals.push_back(nn.norm() > 1e-12 ? nn.normalized() : in_.normals[first]);
  }
  if (!in_.tangents.empty()) {
    Vec3 tt = Vec3::Zero();
    double sign = 0.0;
    for (int q = 0; q < count; ++q) {
      tt += w[q] * in_.tangents[v[q].value()].head<3>();
      sign += w[q] * in_.tangents[v[q].value()].w();
    }
    if (!(tt.norm() > 1e-12)) tt = in_.tangents[first].head<3>();
    tt.normalize();
    out_.tangents.emplace_back(tt.x(), tt.y(), tt.z(), sign < 0.0 ? -1.0 : 1.0);
  }
  if (!in_.uv0.empty()) out_.uv0.push_back(Blend(in_.uv0, v, w, count));
  if (!in_.uv1.empty()) out_.uv1.push_back(Blend(in_.uv1, v, w, count));
  if (!in_.colors.empty()) out_.colors.push_back(Blend(in_.colors, v, w, count));
}

// Sums what the edges and faces counted into `st`.
void CountPoints(const EdgeGraph& graph, const GridMarking& marking,
                 const IdVector<EdgeId, RefinedEdge>& edges,
                 const IdVector<FaceId, FaceOutput>& faces, SubdivisionStats* st) {
  Tally total;
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    const FaceOutput& o = faces[FaceId(fi)];
    st->face_points_kept += o.face_points_kept;
    total.Add(o.tally);
    const FaceMarks& m = marking.faces[FaceId(fi)];
    if (m.large) st->face_points_considered += m.points.size();
  }
  for (size_t e = 0; e < graph.edges.size(); ++e) {
    total.Add(edges[EdgeId(e)].tally);
    const EdgeMarks& m = marking.edges[EdgeId(e)];
    if (!m.candidate) continue;
    st->edge_points_considered += m.points.size();
    for (const EdgePoint& p : m.points) st->edge_points_kept += p.marked ? 1 : 0;
  }
  st->refinement_points += total.refinement;
  st->max_deviation = std::max(st->max_deviation, total.max_dev);
  st->max_estimated_deviation = std::max(st->max_estimated_deviation, total.max_estimate);
  st->measured_points += total.measured;
}

}  // namespace

Result<SubdivisionResult> Assemble(const Context& ctx, const EdgeGraph& graph,
                                   const GridMarking& marking,
                                   const IdVector<EdgeId, RefinedEdge>& edges,
                                   const IdVector<FaceId, FaceOutput>& faces,
                                   const SubdivisionStats& stats) {
  SubdivisionResult r;
  Mesh& out = r.mesh;
  const Mesh& in = ctx.mesh;
  out = in;  // the input's vertices first, in order; triangles rebuilt below
  r.placed = ctx.placed;
  out.triangles.clear();
  VertexAppender appender(in, ctx.placed, &r);
  std::unordered_map<uint64_t, uint32_t> side_base;  // (vertex pair) -> first of its points
  std::vector<uint32_t> per_face(faces.size(), 1);
  std::vector<uint32_t> ids;
  for (size_t fi = 0; fi < faces.size(); ++fi) {
    const GraphFace& f = graph.faces[FaceId(fi)];
    const FaceOutput& o = faces[FaceId(fi)];
    if (o.triangles.empty()) {
      out.triangles.push_back(in.triangles[fi]);
      continue;
    }
    ids.assign(3 + o.points.size(), 0);
    for (int k = 0; k < 3; ++k) ids[k] = f.corner[k].value();
    for (size_t q = 0; q < o.points.size(); ++q) {
      const LocalPoint& lp = o.points[q];
      if (lp.kind == LocalPoint::Kind::kOnSide) {
        const EdgeId e = f.edge[lp.side];
        const VertexId a = f.corner[lp.side], b = f.corner[(lp.side + 1) % 3];
        const uint64_t key =
            (static_cast<uint64_t>(std::min(a, b).value()) << 32) | std::max(a, b).value();
        auto [it, fresh] = side_base.try_emplace(key, static_cast<uint32_t>(out.positions.size()));
        if (fresh) {
          // The edge's points for this pair of vertices, from its w0 end.
          const VertexId from = graph.weld[a] == graph.edges[e].w0 ? a : b;
          const VertexId v[2] = {from, from == a ? b : a};
          for (double t : edges[e].kept_t) {
            const double w[2] = {1.0 - t, t};
            appender.Append(v, w, 2);
          }
        }
        ids[3 + q] = it->second + lp.index;
      } else {
        ids[3 + q] = static_cast<uint32_t>(out.positions.size());
        const double w[3] = {1.0 - lp.l1 - lp.l2, lp.l1, lp.l2};
        appender.Append(f.corner.data(), w, 3);
      }
    }
    per_face[fi] = static_cast<uint32_t>(o.triangles.size());
    for (const auto& t : o.triangles) out.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
  }
  SubdivisionStats& st = r.stats;
  st = stats;
  CountPoints(graph, marking, edges, faces, &st);
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
  if (st.vertices_after > ctx.options.max_vertices) {
    return Budget::OverLimitError("vertices", ctx.options.max_vertices, st.vertices_after);
  }
  if (st.triangles_after > ctx.options.max_triangles) {
    return Budget::OverLimitError("triangles", ctx.options.max_triangles, st.triangles_after);
  }
  return r;
}

}  // namespace surfdeform::subdivision
