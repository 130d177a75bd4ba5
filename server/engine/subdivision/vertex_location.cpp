#include "engine/subdivision/vertex_location.hpp"

#include "engine/common/parallel.hpp"
#include "engine/surface/surface_batch.hpp"

namespace surfdeform::subdivision {
namespace {

// SurfaceBatch::DrainOffsets' callback for both passes: the on-sheet vertex k
// at its height along the normal.
auto WriteDeformed(IdVector<VertexId, Vec3>& deformed) {
  return [&deformed](int k, const Vec3& moved) { deformed[VertexId(k)] = moved; };
}

}  // namespace

Result<LocatedVertices> LocateVertices(const Context& ctx, bool positions) {
  const size_t n = ctx.mesh.positions.size();
  LocatedVertices out;
  out.cell.resize(n);
  out.on_sheet.resize(n);
  if (positions) {
    out.deformed.resize(n);
  } else {
    out.uv.resize(n);
  }
  std::vector<size_t> outside(ctx.threads, 0);
  std::vector<double> worst(ctx.threads, 0.0);
  const bool exact = ctx.map.sheet().method == "exact";
  ParallelChunks(static_cast<int>(n), ctx.threads, [&](int chunk, int begin, int end) {
    SurfaceBatch batch(ctx.map.surface(), 1);  // the on-sheet vertices' positions
    const auto finish = WriteDeformed(out.deformed);
    int hint = -1;
    for (int k = begin; k < end; ++k) {
      const VertexId v(k);
      const Vec3& abh = ctx.Placed(v);
      const SheetParameters p = ctx.footprint.Parameters(
          ctx.map, static_cast<size_t>(k), abh.head<2>(), OutsideMode::kError, false, &hint);
      out.on_sheet[v] = !p.outside;
      if (p.outside) {
        ++outside[chunk];
        worst[chunk] = std::max(worst[chunk], p.outside_distance);
      }
      if (!positions) {
        out.uv[v] = p.uv;
      } else if (p.outside) {
        out.deformed[v] = ctx.Deformed(abh, &hint);
      } else {
        batch.Add(k, p.uv, abh.z());
        if (batch.full()) batch.DrainOffsets(finish);
      }
      int cell = p.cell;
      if (exact) {  // the closed-form inverse located nothing: find the cell
        SheetLocation l;
        cell = ctx.locator.Locate(abh.head<2>(), &l, &hint) ? ctx.locator.CellIndex(l) : -1;
      }
      out.cell[v] = cell;
    }
    batch.DrainOffsets(finish);
  });
  for (int c = 0; c < ctx.threads; ++c) {
    out.outside += outside[c];
    out.outside_worst = std::max(out.outside_worst, worst[c]);
  }
  if (ctx.refuse_outside && out.outside > 0) {
    return OutsideSheetError(out.outside, n, out.outside_worst);
  }
  return out;
}

void CompleteDeformed(const Context& ctx, LocatedVertices* located) {
  if (!located->deformed.empty()) return;
  const size_t n = ctx.mesh.positions.size();
  located->deformed.resize(n);
  ParallelChunks(static_cast<int>(n), ctx.threads, [&](int, int begin, int end) {
    SurfaceBatch batch(ctx.map.surface(), 1);  // the on-sheet vertices
    const auto finish = WriteDeformed(located->deformed);
    int hint = -1;
    for (int k = begin; k < end; ++k) {
      const VertexId v(k);
      const Vec3& abh = ctx.Placed(v);
      if (!located->on_sheet[v]) {
        located->deformed[v] = ctx.Deformed(abh, &hint);
        continue;
      }
      batch.Add(k, located->uv[v], abh.z());
      if (batch.full()) batch.DrainOffsets(finish);
    }
    batch.DrainOffsets(finish);
  });
}

}  // namespace surfdeform::subdivision
