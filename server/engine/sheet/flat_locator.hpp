// Point location on a flat sheet: which cell of the flattened grid holds a
// point, and where inside it, by the exact inverse of the cell's bilinear map.
//
// Cells are the quads of samples (i, j), (i+1, j), (i+1, j+1), (i, j+1), mapped
// bilinearly from local (s, t) in [0, 1]^2; the sheet's parameters there are
// (u, v) = ((i + s) / (nu - 1), (j + t) / (nv - 1)). A bucket grid over the
// sheet's bounding box lists the cells whose bounds overlap each bucket, so a
// query tests O(1) cells on average. Requires a sheet without folded cells
// (the flattening guarantees it): then at most one cell holds an interior
// point, and the answer does not depend on the order of the tests.
#pragma once

#include <vector>

#include "engine/common/flat_sheet.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

struct SheetLocation {
  int i = 0;  // cell
  int j = 0;
  double s = 0.0;  // local coordinates; outside [0, 1] when extrapolated
  double t = 0.0;
};

class FlatLocator {
 public:
  explicit FlatLocator(const FlatSheet& sheet);

  // The cell holding p (boundaries included, to a relative 1e-9), or false.
  // `hint`, when not negative, is a cell to try first (the previous vertex's:
  // mesh vertices come in spatially coherent order); it is updated.
  bool Locate(const Vec2& p, SheetLocation* out, int* hint = nullptr) const;

  // The point of the sheet's boundary nearest to p: its cell and local
  // coordinates, and the distance from p.
  SheetLocation NearestOnBoundary(const Vec2& p, double* distance) const;

  // The flat position of a location and d(flat)/d(s, t) there (columns).
  Vec2 FlatPoint(const SheetLocation& l) const;
  Eigen::Matrix2d FlatJacobian(const SheetLocation& l) const;

  // Surface parameters of a location and d(u, v)/d(s, t) (diagonal).
  Vec2 Parameters(const SheetLocation& l) const {
    return Vec2((l.i + l.s) / (nu_ - 1), (l.j + l.t) / (nv_ - 1));
  }
  Vec2 ParameterScale() const { return Vec2(1.0 / (nu_ - 1), 1.0 / (nv_ - 1)); }

  // True when some point of the sheet's boundary is closer to p than
  // `distance` (strictly): the fit's margin test, without square roots and
  // with an early exit.
  bool BoundaryWithin(const Vec2& p, double distance) const;

  // Bounding box of the sheet.
  const Eigen::AlignedBox2d& bounds() const { return bounds_; }

  int nu() const { return nu_; }
  int nv() const { return nv_; }
  // Flat position of grid node (i, j).
  const Vec2& Node(int i, int j) const { return flat_[i + nu_ * j]; }
  // Cell index i + (nu - 1) j of a location.
  int CellIndex(const SheetLocation& l) const { return l.i + (nu_ - 1) * l.j; }
  // The shortest side of a cell (by index) on the sheet.
  double CellMinSide(int cell) const;

  // The cells (indices, sorted, each once) whose bounds meet the buckets that
  // the segment a-b passes through: every cell the segment crosses, and a few
  // near it.
  void CellsAlongSegment(const Vec2& a, const Vec2& b, std::vector<int>* cells) const;
  // The same for the buckets that meet a box.
  void CellsInBox(const Eigen::AlignedBox2d& box, std::vector<int>* cells) const;

 private:
  const Vec2& Corner(int i, int j) const { return flat_[i + nu_ * j]; }

  int nu_, nv_;
  std::vector<Vec2> flat_;
  Eigen::AlignedBox2d bounds_;
  bool TryCell(int cell, const Vec2& p, SheetLocation* out) const;

  struct Segment {
    Vec2 a, ab;
    double inv_len2;  // 1 / |ab|^2, 0 for a degenerate segment
  };
  std::vector<Segment> boundary_;  // the sheet's outline, for BoundaryWithin
  // Appends the cells of buckets x0..x1 of row y, then (last call) sorts and
  // removes repeats.
  void AppendBucketRow(int y, int x0, int x1, std::vector<int>* cells) const;
  static void SortUnique(std::vector<int>* cells);
  // The buckets a box meets, clamped to the grid of buckets (a point: its own).
  // BoundaryWithin computes its range apart: it must first see how many
  // buckets an unclamped range spans, to fall back to a full scan.
  struct BucketSpan {
    int x0, x1, y0, y1;
  };
  BucketSpan BucketsOf(const Eigen::AlignedBox2d& box) const;
  // CSR lists of the items (indices into `boxes`) in each bucket: each item in
  // every bucket its box meets (clamped to the grid of buckets).
  void Bucket(const std::vector<Eigen::AlignedBox2d>& boxes, std::vector<int>* start,
              std::vector<int>* items) const;

  // A cell a (0,0), b (1,0), c (1,1), d (0,1): its bounds (slightly
  // enlarged) and what inverting its bilinear map a + s e + t f + s t g needs.
  struct Cell {
    Eigen::AlignedBox2d bounds;
    Vec2 a, e, f, g;             // e = b - a, f = d - a, g = a - b + c - d
    double k2 = 0.0;             // k2 t^2 + k1 t + k0 = 0 in t: k2 = g x f,
    double k1 = 0.0;             // k1 = e x f + (p - a) x g (the first term here)
    bool parallelogram = false;  // k2 negligible: the equation is linear
    int i = 0, j = 0;            // its place in the grid
    bool Inverse(const Vec2& p, double* s, double* t) const;
  };
  std::vector<Cell> cells_;
  int bx_ = 1, by_ = 1;  // buckets along x and y
  Vec2 bucket_size_ = Vec2::Ones();
  std::vector<int> bucket_start_;  // CSR: cells of bucket b are
  std::vector<int> bucket_cells_;  // bucket_cells_[bucket_start_[b] .. bucket_start_[b+1])
  // CSR: the boundary segments (indices into boundary_) in each bucket.
  std::vector<int> boundary_start_;
  std::vector<int> boundary_segments_;
};

}  // namespace surfdeform
