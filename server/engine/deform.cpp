#include "engine/deform.hpp"

#include <chrono>
#include <cmath>

#include "engine/parallel.hpp"
#include "engine/sheet_map.hpp"

namespace surfdeform {
namespace {

using Mat3 = Eigen::Matrix3d;

// The deformation of `mesh` into `*result_out`. result_out->mesh is either
// empty (then everything but the attributes that are recomputed is copied
// from `mesh`) or `mesh` itself (in place: each vertex reads only its own
// input before writing its output).
Status Deform(const Surface& surface, const FlatSheet& sheet, const Mesh& mesh,
              const PlacementOptions& o, const SubdivisionOptions* subdivision,
              DeformResult* result_out) {
  const auto t0 = std::chrono::steady_clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidatePlacement(o));
  if (subdivision != nullptr) SURFDEFORM_RETURN_IF_ERROR(ValidateSubdivision(*subdivision));
  if (const std::string problem = CheckMesh(mesh); !problem.empty()) {
    return InvalidArgument("malformed mesh: " + problem, "mesh");
  }
  if (sheet.nu < 2 || sheet.nv < 2 ||
      sheet.flat.size() != static_cast<size_t>(sheet.nu) * sheet.nv) {
    return InvalidArgument("the flat sheet is empty or inconsistent", "surface");
  }
  const size_t n_input = mesh.positions.size();
  for (size_t k = 0; k < n_input; ++k) {
    if (!mesh.positions[k].allFinite()) {
      return InvalidArgument("vertex position is not finite",
                             "mesh.positions[" + std::to_string(k) + "]");
    }
  }
  const SheetMap map(surface, sheet);
  auto placement = ComputePlacement(map.locator(), sheet, mesh.positions, o);
  if (!placement.ok()) return placement.status();
  const Placement& pl = *placement;
  const Mat3 linear = pl.Linear();
  const Mat3 normal_linear = linear.inverse().transpose();

  DeformResult& result = *result_out;
  DeformStats& st = result.stats;
  const Mesh* source = &mesh;
  std::vector<Vec3> placed;  // empty: placed on the fly
  // The deformed input vertices on the sheet, if the subdivision computed them.
  std::vector<Vec3> known;
  if (subdivision != nullptr && subdivision->mode != SubdivisionMode::kOff &&
      !mesh.triangles.empty()) {
    const auto ts = std::chrono::steady_clock::now();
    // Placed coordinates; footprints off the sheet are reported by the loop
    // below (subdivision continues the map past the border meanwhile).
    placed.resize(n_input);
    const int threads = n_input >= 4096 ? ResolveThreads(o.threads) : 1;
    ParallelChunks(static_cast<int>(n_input), threads, [&](int, int begin, int end) {
      for (int k = begin; k < end; ++k) placed[k] = pl.Apply(mesh.positions[k]);
    });
    SubdivisionOptions so = *subdivision;
    if (so.threads == 0) so.threads = o.threads;
    auto refined = Subdivide(mesh, placed, map, o.outside, so);
    if (!refined.ok()) return refined.status();
    st.subdivision = refined->stats;
    known = std::move(refined->input_positions);
    if (refined->unchanged) {
      if (&result.mesh != &mesh) result.mesh = Mesh{};  // as without subdivision
    } else {
      result.mesh = std::move(refined->mesh);
      placed = std::move(refined->placed);
      source = &result.mesh;
    }
    st.subdivide_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - ts).count();
  }

  // Deformation, vertex by vertex.
  const Mesh& in = *source;
  Mesh& out = result.mesh;
  const size_t n = in.positions.size();
  if (&out != &in) {
    // Attributes, triangles and groups carry over; positions, normals and
    // tangents are all written below, so they are only sized, not copied.
    out.triangles = in.triangles;
    out.groups = in.groups;
    out.uv0 = in.uv0;
    out.uv1 = in.uv1;
    out.colors = in.colors;
    out.positions.resize(n);
    out.normals.resize(in.normals.size());
    out.tangents.resize(in.tangents.size());
  }
  const bool need_frame = !in.normals.empty() || !in.tangents.empty();
  const int threads = n >= 4096 ? ResolveThreads(o.threads) : 1;
  std::vector<size_t> outside(threads, 0);
  std::vector<double> worst(threads, 0.0);
  std::vector<long long> bad(threads, -1);  // first vertex with a non-finite result
  ParallelChunks(static_cast<int>(n), threads, [&](int chunk, int begin, int end) {
    int hint = -1;  // the previous vertex's cell
    for (int k = begin; k < end; ++k) {
      if (!need_frame && static_cast<size_t>(k) < known.size() && !std::isnan(known[k].x())) {
        out.positions[k] = known[k];  // on the sheet, deformed by the subdivision already
        if (!known[k].allFinite() && bad[chunk] < 0) bad[chunk] = k;
        continue;
      }
      const Vec3 abh = placed.empty() ? pl.Apply(in.positions[k]) : placed[k];
      const double h = abh.z();
      // Vertices added by the subdivision inside faces whose corners are on
      // the sheet continue its map past a concave border.
      const bool added = static_cast<size_t>(k) >= n_input;
      const OutsideMode mode =
          added && o.outside == OutsideMode::kError ? OutsideMode::kExtrapolate : o.outside;
      const SheetParameters p = map.Parameters(abh.head<2>(), mode, need_frame, &hint);
      if (p.outside && !added) {
        ++outside[chunk];
        worst[chunk] = std::max(worst[chunk], p.outside_distance);
      }
      if (p.outside && mode == OutsideMode::kError) continue;
      const SurfacePoint s = map.surface().Evaluate(p.uv.x(), p.uv.y(), need_frame ? 2 : 1);
      if (!need_frame) {
        out.positions[k] = OffsetAlongNormal(s, h);
      } else {
        Vec3 nrm;
        const Mat3 jac = DeformJacobian(s, p, h, &nrm);  // d(position)/d(a, b, h)
        out.positions[k] = s.p + h * nrm;
        const Mat3 total = jac * linear;
        if (!in.normals.empty()) {
          // J^-T n up to a positive factor (1 / det J), which the normalisation
          // removes: the cofactor matrix, i.e. cross products of J's columns.
          const Vec3 m = normal_linear * in.normals[k];
          const Vec3 nn = m.x() * jac.col(1).cross(jac.col(2)) +
                          m.y() * jac.col(2).cross(jac.col(0)) +
                          m.z() * jac.col(0).cross(jac.col(1));
          out.normals[k] = nn.normalized();
        }
        if (!in.tangents.empty()) {
          const Vec4& t = in.tangents[k];
          const Vec3 tt = (total * t.head<3>()).normalized();
          const double w = total.determinant() < 0.0 ? -t.w() : t.w();
          out.tangents[k] = Vec4(tt.x(), tt.y(), tt.z(), w);
        }
      }
      const bool finite = out.positions[k].allFinite() &&
                          (in.normals.empty() || out.normals[k].allFinite()) &&
                          (in.tangents.empty() || out.tangents[k].allFinite());
      if (!finite && bad[chunk] < 0) bad[chunk] = k;
    }
  });
  st.vertices = n;
  st.triangles = in.triangles.size();
  if (st.subdivision.mode == SubdivisionMode::kOff) {
    st.subdivision.vertices_before = st.subdivision.vertices_after = n;
    st.subdivision.triangles_before = st.subdivision.triangles_after = st.triangles;
  }
  st.scale = pl.scale;
  for (int c = 0; c < threads; ++c) {
    st.outside += outside[c];
    st.max_outside_distance = std::max(st.max_outside_distance, worst[c]);
  }
  if (st.outside > 0 && o.outside == OutsideMode::kError) {
    return OutsideSheetError(st.outside, n_input, st.max_outside_distance);
  }
  for (int c = 0; c < threads; ++c) {
    if (bad[c] >= 0) {
      return Degenerate("the deformation of vertex " + std::to_string(bad[c]) +
                            " is not finite (the surface normal vanishes there)",
                        "surface");
    }
  }
  st.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return Status::Ok();
}

}  // namespace

Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, const Mesh& mesh,
                                const PlacementOptions& options) {
  DeformResult result;
  SURFDEFORM_RETURN_IF_ERROR(Deform(surface, sheet, mesh, options, nullptr, &result));
  return result;
}

Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, Mesh&& mesh,
                                const PlacementOptions& options) {
  DeformResult result;
  result.mesh = std::move(mesh);
  SURFDEFORM_RETURN_IF_ERROR(Deform(surface, sheet, result.mesh, options, nullptr, &result));
  return result;
}

Result<DeformResult> DeformMesh(const Surface& surface, const FlatSheet& sheet, Mesh&& mesh,
                                const PlacementOptions& options,
                                const SubdivisionOptions& subdivision) {
  if (subdivision.mode == SubdivisionMode::kOff) {
    return DeformMesh(surface, sheet, std::move(mesh), options);
  }
  DeformResult result;
  result.mesh = std::move(mesh);
  SURFDEFORM_RETURN_IF_ERROR(Deform(surface, sheet, result.mesh, options, &subdivision, &result));
  return result;
}

}  // namespace surfdeform
