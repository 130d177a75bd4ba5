#include "engine/sheet/sheet_field.hpp"

#include <string>

#include "engine/common/parallel.hpp"

namespace surfdeform {

Result<SheetField> SampleSheetField(const SheetMap& map, int n, int threads) {
  if (n < kMinFieldSide) {
    return InvalidArgument("the field needs at least " + std::to_string(kMinFieldSide) +
                               " lattice points per side, got " + std::to_string(n),
                           "n");
  }
  const std::vector<Vec2>& flat = map.given_sheet().flat;
  if (flat.empty()) return InvalidArgument("the sheet has no samples", "id");
  SheetField f;
  f.n = n;
  f.lo = f.hi = flat[0];
  for (const Vec2& p : flat) {
    f.lo = f.lo.cwiseMin(p);
    f.hi = f.hi.cwiseMax(p);
  }
  const size_t count = static_cast<size_t>(n) * static_cast<size_t>(n);
  f.positions.resize(count);
  f.normals.resize(count);
  f.on_sheet.resize(count);
  f.params.resize(count);
  const Vec2 step = (f.hi - f.lo) / (n - 1);
  // One row of the lattice per task; each row walks its cells in order, so
  // the previous point's cell is the search's first guess.
  ParallelChunks(n, ResolveThreads(threads), [&](int, int row_begin, int row_end) {
    for (int j = row_begin; j < row_end; ++j) {
      int hint = -1;
      for (int i = 0; i < n; ++i) {
        const size_t k = static_cast<size_t>(i) + static_cast<size_t>(n) * j;
        // The last lattice point of a row or column is the box's corner
        // itself, not lo + (n - 1) step rounded.
        const Vec2 ab(i + 1 == n ? f.hi.x() : f.lo.x() + i * step.x(),
                      j + 1 == n ? f.hi.y() : f.lo.y() + j * step.y());
        const SheetParameters p = map.Parameters(ab, OutsideMode::kExtrapolate, false, &hint);
        const SurfacePoint s = map.surface().Evaluate(p.uv.x(), p.uv.y(), 1);
        f.positions[k] = s.p;
        f.normals[k] = UnitNormal(s);
        f.on_sheet[k] = p.outside ? 0 : 1;
        f.params[k] = p.uv;
      }
    }
  });
  // A continuation far past a curved border could leave the surface's
  // domain (a normal that vanishes, a point that overflows): an error, never
  // a value a client would draw.
  for (size_t k = 0; k < count; ++k) {
    if (f.positions[k].allFinite() && f.normals[k].allFinite() && f.params[k].allFinite()) continue;
    return Status(ErrorCode::kDegenerate,
                  "the map continued off the sheet is not finite at lattice point " +
                      std::to_string(k % n) + ", " + std::to_string(k / n),
                  "n");
  }
  return f;
}

}  // namespace surfdeform
