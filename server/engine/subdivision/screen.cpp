#include "engine/subdivision/screen.hpp"

#include <cmath>

#include "engine/common/parallel.hpp"
#include "engine/subdivision/grid_points.hpp"

namespace surfdeform::subdivision {
namespace {

// The largest deviation of a face's edges (at their quarter points and grid
// crossings, against the straight pieces), stopping once past kEdgeShare of
// the tolerance, and of its centroid against the flat triangle.
struct FaceDeviation {
  double edges = 0.0;
  double centroid = 0.0;
  size_t measured = 0;
};
FaceDeviation MeasureFace(const Context& ctx, const std::array<VertexId, 3>& tri,
                          const Vec3 (&f)[3], std::vector<GridCrossing>* crossings,
                          std::vector<int>* scratch, int* hint) {
  FaceDeviation d;
  for (int k = 0; k < 3 && d.edges <= kEdgeShare * ctx.tolerance; ++k) {
    const Vec3 &a = ctx.Placed(tri[k]), &b = ctx.Placed(tri[(k + 1) % 3]);
    double min_side;
    GridCrossings(ctx.locator, a.head<2>(), b.head<2>(), crossings, scratch, &min_side);
    auto sample = [&](double t) {
      const Vec3 exact = ctx.Deformed(a + t * (b - a), hint);
      d.edges = std::max(d.edges, (exact - ((1.0 - t) * f[k] + t * f[(k + 1) % 3])).norm());
      ++d.measured;
    };
    for (double t : {0.25, 0.5, 0.75}) sample(t);
    for (const GridCrossing& c : *crossings) sample(c.t);
  }
  const Vec3 centroid =
      ctx.Deformed((ctx.Placed(tri[0]) + ctx.Placed(tri[1]) + ctx.Placed(tri[2])) / 3.0, hint);
  d.centroid = (centroid - (f[0] + f[1] + f[2]) / 3.0).norm();
  ++d.measured;
  return d;
}

}  // namespace

ScreenResult Screen(const Context& ctx, const LocatedVertices& located,
                    const CellEstimates& estimates) {
  ScreenResult result;
  if (ctx.uniform || !ctx.refine) return result;
  const int count = static_cast<int>(ctx.mesh.triangles.size());
  std::atomic<bool> pass{true};
  const bool have_extents = ctx.extents.size() == static_cast<size_t>(count);
  std::vector<double> worst(ctx.threads, 0.0), measured_worst(ctx.threads, 0.0);
  std::vector<size_t> measured(ctx.threads, 0);
  // Blocks of faces dealt round-robin: the faces that need measuring
  // cluster where the surface bends, which contiguous halves split unevenly.
  constexpr int kBlock = 2048;
  const int blocks = (count + kBlock - 1) / kBlock;
  const int threads = std::max(1, std::min(ctx.threads, blocks));
  ParallelChunks(threads, threads, [&](int chunk, int, int) {
    int hint = -1;
    std::vector<GridCrossing> crossings;
    std::vector<int> scratch;
    // Kept in locals, written once: the per-chunk slots share a cache line.
    double chunk_worst = 0.0, chunk_measured_worst = 0.0;
    size_t chunk_measured = 0;
    for (int b = chunk; b < blocks && pass.load(std::memory_order_relaxed); b += threads) {
      for (int fi = b * kBlock;
           fi < std::min(count, (b + 1) * kBlock) && pass.load(std::memory_order_relaxed); ++fi) {
        const auto& t = ctx.mesh.triangles[fi];
        const std::array<VertexId, 3> tri = {VertexId(t[0]), VertexId(t[1]), VertexId(t[2])};
        CellTerms terms;
        if (!estimates.Terms(located.cell[tri[0]], located.cell[tri[1]], located.cell[tri[2]],
                             &terms)) {
          pass = false;
          break;
        }
        const FaceExtent x = have_extents ? ctx.extents[fi] : ExtentOf(ctx, tri);
        if (x.longest2 > terms.min_side * terms.min_side) {
          pass = false;
          break;
        }
        const double estimate = EstimateOf(terms, std::sqrt(x.longest2), x.dh, x.h);
        if (ctx.Skippable(estimate)) {
          chunk_worst = std::max(chunk_worst, estimate);
          continue;
        }
        Vec3 f[3];
        for (int k = 0; k < 3; ++k) {
          f[k] = located.deformed.empty() ? ctx.Deformed(ctx.Placed(tri[k]), &hint)
                                          : located.deformed[tri[k]];
        }
        const FaceDeviation d = MeasureFace(ctx, tri, f, &crossings, &scratch, &hint);
        chunk_measured += d.measured;
        if (d.edges > kEdgeShare * ctx.tolerance || d.centroid > kFaceShare * ctx.tolerance) {
          pass = false;
          break;
        }
        chunk_measured_worst = std::max({chunk_measured_worst, d.edges, d.centroid});
      }
    }
    worst[chunk] = chunk_worst;
    measured_worst[chunk] = chunk_measured_worst;
    measured[chunk] = chunk_measured;
  });
  if (!pass) return result;
  result.pass = true;
  for (int c = 0; c < threads; ++c) {
    result.max_estimate = std::max(result.max_estimate, worst[c]);
    result.max_deviation = std::max(result.max_deviation, measured_worst[c]);
    result.measured_points += measured[c];
  }
  return result;
}

}  // namespace surfdeform::subdivision
