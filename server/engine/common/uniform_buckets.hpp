// A uniform grid of buckets over a box on the plane, for the flat meshes'
// spatial indices (FlatTriangles, subdivision::TargetEdges): about one
// bucket per item, square cells, at most 4096 a side. Items are filed, by
// their boxes, in compressed rows (each bucket's ids between start[b] and
// start[b + 1]).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/common/clamped_floor.hpp"
#include "engine/common/geometry_types.hpp"

namespace surfdeform {

class UniformBuckets {
 public:
  UniformBuckets() = default;
  // About `items` buckets over `bounds` (at least one).
  UniformBuckets(const Eigen::AlignedBox2d& bounds, double items) : bounds_(bounds) {
    const Vec2 size = bounds_.sizes().cwiseMax(1e-300);
    const double cell = std::sqrt(size.x() * size.y() / std::max(items, 1.0));
    columns_ = ClampedCeil(size.x() / cell, 1, 4096);
    rows_ = ClampedCeil(size.y() / cell, 1, 4096);
    cell_ = Vec2(size.x() / columns_, size.y() / rows_);
  }

  // The cell that holds p (clamped to the grid).
  Eigen::Vector2i CellOf(const Vec2& p) const {
    const Vec2 g = (p - bounds_.min()).cwiseQuotient(cell_);
    return Eigen::Vector2i(ClampedFloor(g.x(), 0, columns_ - 1), ClampedFloor(g.y(), 0, rows_ - 1));
  }
  int Bucket(const Eigen::Vector2i& c) const { return c.x() + columns_ * c.y(); }
  int bucket_count() const { return columns_ * rows_; }

  // Calls visit(bucket) for every bucket `box` covers; none for a box off
  // the grid.
  template <typename Visit>
  void ForBox(const Eigen::AlignedBox2d& box, Visit&& visit) const {
    if (box.isEmpty() || !bounds_.intersects(box)) return;
    const Eigen::Vector2i lo = CellOf(box.min()), hi = CellOf(box.max());
    for (int y = lo.y(); y <= hi.y(); ++y) {
      for (int x = lo.x(); x <= hi.x(); ++x) visit(Bucket(Eigen::Vector2i(x, y)));
    }
  }

  // Files items 0 .. items - 1 in every bucket their box (box_of(k))
  // covers: bucket b's items are ids[start[b]] .. ids[start[b + 1] - 1].
  template <typename BoxOf>
  void Fill(int items, const BoxOf& box_of, std::vector<int>* start, std::vector<int>* ids) const {
    start->assign(static_cast<size_t>(bucket_count()) + 1, 0);
    for (int k = 0; k < items; ++k) ForBox(box_of(k), [&](int b) { ++(*start)[b + 1]; });
    for (size_t b = 1; b < start->size(); ++b) (*start)[b] += (*start)[b - 1];
    ids->resize(start->back());
    std::vector<int> next(start->begin(), start->end() - 1);
    for (int k = 0; k < items; ++k) ForBox(box_of(k), [&](int b) { (*ids)[next[b]++] = k; });
  }

  const Eigen::AlignedBox2d& bounds() const { return bounds_; }
  const Vec2& cell() const { return cell_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }

 private:
  Eigen::AlignedBox2d bounds_;
  Vec2 cell_ = Vec2::Ones();
  int columns_ = 1, rows_ = 1;
};

}  // namespace surfdeform
