// Stage 2 of the subdivision: the terms of the deviation estimate, per cell.
//
// How far a straight edge or a flat triangle strays from the exact
// deformation depends, inside one cell or a 2 x 2 block of cells, on: the
// largest curvature at the cells' nodes, how much faster the normal turns
// across them (its second derivative: a model above the surface follows
// that), their twist (how far from a parallelogram a flat quad is, which
// bends the inverse bilinear map), and the largest kink across the sides
// inside the block (the jump of the deformation's derivative there: the
// cell-wise map is only continuous across grid lines). Computed only for the
// cells near the model's vertices.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/subdivision/context.hpp"

namespace surfdeform::subdivision {

struct CellTerms {
  double curvature = -1.0;  // < 0: not computed
  // The unit normal's second derivative along the sheet (per length^2), at
  // most: its rate of turning changes across the cell.
  double bend = 0.0;
  double twist = 0.0;
  // 0 for a single cell of a parametric surface; on a mesh surface, the
  // largest kink of its edges in the cell (TargetEdges::Edge::kink).
  double kink = 0.0;
  double min_side = 0.0;  // the shortest cell side on the sheet
};

// An estimate, with a safety factor of two, of how far a straight segment or
// a triangle in these cells strays from the exact deformation: the second
// derivatives of F(a, b, h) = S + h N there are about the surface's
// curvature, plus h times the normal's second derivative (at least the
// curvature squared; more where the curvature changes, as along a short
// wave), plus the bending of the cells' inverse bilinear maps, and
// d2F/(da dh) = dN/da about the curvature;
// a straight piece of size l then strays (F'' l^2) / 8, plus j l / 4 for a
// kink j of the map where it crosses from one cell to the next. `length` is
// the piece's size on the sheet, `dh` the spread of its heights, `h` their
// largest magnitude. Inline, as the two below: the screen calls them for
// every face of the model.
inline double EstimateOf(const CellTerms& t, double length, double dh, double h) {
  const double k = t.curvature;
  const double second = k + std::abs(h) * std::max(k * k, t.bend) + 2.0 * t.twist;
  return 2.0 * ((second * length * length + 2.0 * k * length * std::abs(dh)) / 8.0 +
                t.kink * length / 4.0);
}

// A face's extent for its estimate (FaceExtent in subdivide.hpp), from its
// corners' placed coordinates.
inline FaceExtent ExtentOfCorners(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const double h_lo = std::min({p0.z(), p1.z(), p2.z()});
  const double h_hi = std::max({p0.z(), p1.z(), p2.z()});
  return {std::max({(p1 - p0).head<2>().squaredNorm(), (p2 - p1).head<2>().squaredNorm(),
                    (p0 - p2).head<2>().squaredNorm()}),
          h_hi - h_lo, std::max(std::abs(h_lo), std::abs(h_hi))};
}
inline FaceExtent ExtentOf(const Context& ctx, const std::array<VertexId, 3>& corners) {
  return ExtentOfCorners(ctx.Placed(corners[0]), ctx.Placed(corners[1]), ctx.Placed(corners[2]));
}

class CellEstimates {
 public:
  // The terms of every cell within one cell of a vertex's (vertex_cell: per
  // input vertex, -1 off the sheet), at the model's range of heights.
  CellEstimates(const Context& ctx, const IdVector<VertexId, int>& vertex_cell);

  // The terms of the cell or 2 x 2 block a piece with corners in cells a, b,
  // c lies in; false when they are not within one block (or off the sheet).
  // Inline for its common case, all three in one cell (most faces of a fine
  // model): the screen asks for every face.
  bool Terms(int a, int b, int c, CellTerms* terms) const {
    if (a == b && b == c && a >= 0) {
      *terms = cells_[a];
      return true;
    }
    return BlockTermsOf(a, b, c, terms);
  }

  const CellTerms& cell(int c) const { return cells_[c]; }
  // The kink across side `side` (CellGrid's numbering); 0 where not computed
  // and on the sheet's border (nothing inside a block crosses it).
  double side_kink(int side) const { return side_kink_[side]; }

 private:
  CellTerms BlockTerms(int i0, int j0, int i1, int j1) const;
  // Terms when a, b and c are not all one cell.
  bool BlockTermsOf(int a, int b, int c, CellTerms* terms) const;

  CellGrid grid_;
  std::vector<CellTerms> cells_;
  std::vector<double> side_kink_;
};

}  // namespace surfdeform::subdivision
