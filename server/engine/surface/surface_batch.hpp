// Points of a surface evaluated a block at a time: the per-vertex passes
// locate vertices one by one on the sheet, queue their parameters here, and
// get the surface back from Surface::EvaluateMany (four points to a vector on
// the bicubic Bezier patch, where one at a time waited on each point's
// latency). Without a frame to carry the map needs only the positions moved
// along the normal: DrainOffsets (Surface::OffsetMany).
#pragma once

#include <span>

#include "engine/surface/surface.hpp"

namespace surfdeform {

class SurfaceBatch {
 public:
  static constexpr int kSize = 64;

  // Keeps a reference: `surface` must outlive the batch.
  SurfaceBatch(const Surface& surface, int order) : surface_(surface), order_(order) {}
  SurfaceBatch(const SurfaceBatch&) = delete;
  SurfaceBatch& operator=(const SurfaceBatch&) = delete;

  // Queues the point of vertex `index` at parameters `uv` and height `h`;
  // returns its slot (0 .. kSize - 1). Call Drain when full().
  int Add(int index, const Vec2& uv, double h) {
    index_[count_] = index;
    uv_[count_] = uv;
    height_[count_] = h;
    return count_++;
  }
  bool full() const { return count_ == kSize; }

  // Evaluates the queued points, calls each(slot, index, point, h) in the
  // order they were added, and empties the batch.
  template <typename Each>
  void Drain(Each&& each) {
    if (count_ == 0) return;
    surface_.EvaluateMany(std::span<const Vec2>(uv_, count_), order_,
                          std::span<SurfacePoint>(point_, count_));
    for (int b = 0; b < count_; ++b) each(b, index_[b], point_[b], height_[b]);
    count_ = 0;
  }

  // The queued points moved by their heights along the unit normal (NaN
  // where it vanishes): calls each(index, position) in the order they were
  // added, and empties the batch. The order given at construction is unused.
  template <typename Each>
  void DrainOffsets(Each&& each) {
    if (count_ == 0) return;
    surface_.OffsetMany(std::span<const Vec2>(uv_, count_),
                        std::span<const double>(height_, count_), std::span<Vec3>(moved_, count_));
    for (int b = 0; b < count_; ++b) each(index_[b], moved_[b]);
    count_ = 0;
  }

 private:
  const Surface& surface_;
  const int order_;
  int count_ = 0;
  int index_[kSize];
  double height_[kSize];
  Vec2 uv_[kSize];
  SurfacePoint point_[kSize];
  Vec3 moved_[kSize];
};

}  // namespace surfdeform
