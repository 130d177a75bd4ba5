#include "engine/sheet/flat_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/common/clamped_floor.hpp"

namespace surfdeform {

FlatLocator::FlatLocator(const FlatSheet& sheet) : nu_(sheet.nu), nv_(sheet.nv), flat_(sheet.flat) {
  for (const Vec2& p : flat_) bounds_.extend(p);
  auto add_segment = [this](const Vec2& a, const Vec2& b) {
    const double len2 = (b - a).squaredNorm();
    boundary_.push_back({a, b - a, len2 > 0.0 ? 1.0 / len2 : 0.0});
  };
  for (int i = 0; i + 1 < nu_; ++i) {
    add_segment(Corner(i, 0), Corner(i + 1, 0));
    add_segment(Corner(i, nv_ - 1), Corner(i + 1, nv_ - 1));
  }
  for (int j = 0; j + 1 < nv_; ++j) {
    add_segment(Corner(0, j), Corner(0, j + 1));
    add_segment(Corner(nu_ - 1, j), Corner(nu_ - 1, j + 1));
  }
  const int cells = (nu_ - 1) * (nv_ - 1);
  const Vec2 size = bounds_.sizes().cwiseMax(1e-300);
  std::vector<Eigen::AlignedBox2d> cell_boxes(cells);
  cells_.resize(cells);
  for (int j = 0; j + 1 < nv_; ++j) {
    for (int i = 0; i + 1 < nu_; ++i) {
      Eigen::AlignedBox2d& box = cell_boxes[i + (nu_ - 1) * j];
      const Vec2 &a = Corner(i, j), &b = Corner(i + 1, j);
      const Vec2 &c = Corner(i + 1, j + 1), &d = Corner(i, j + 1);
      box.extend(a).extend(b).extend(c).extend(d);
      const Vec2 pad = Vec2::Constant(1e-9 * box.diagonal().norm());
      Cell& cell = cells_[i + (nu_ - 1) * j];
      cell.bounds = Eigen::AlignedBox2d(box.min() - pad, box.max() + pad);
      cell.a = a;
      cell.e = b - a;
      cell.f = d - a;
      cell.g = a - b + c - d;
      cell.k2 = Cross2(cell.g, cell.f);
      cell.k1 = Cross2(cell.e, cell.f);
      const double scale = std::abs(cell.k1) + std::abs(Cross2(c - b, c - d));
      cell.parallelogram = std::abs(cell.k2) <= 1e-12 * scale;
      cell.i = i;
      cell.j = j;
    }
  }
  // About four buckets per cell, buckets roughly square: few candidates each.
  const double per_side = 2.0 * std::sqrt(static_cast<double>(cells) * size.x() / size.y());
  bx_ = ClampedCeil(per_side, 1, 4096);
  by_ = ClampedCeil(4.0 * cells / static_cast<double>(bx_), 1, 4096);
  bucket_size_ = Vec2(size.x() / bx_, size.y() / by_);
  Bucket(cell_boxes, &bucket_start_, &bucket_cells_);
  // The boundary's segments by bucket (each in the buckets its box meets).
  std::vector<Eigen::AlignedBox2d> segment_boxes(boundary_.size());
  for (size_t k = 0; k < boundary_.size(); ++k) {
    segment_boxes[k].extend(boundary_[k].a).extend(boundary_[k].a + boundary_[k].ab);
  }
  Bucket(segment_boxes, &boundary_start_, &boundary_segments_);
}

FlatLocator::BucketSpan FlatLocator::BucketsOf(const Eigen::AlignedBox2d& box) const {
  const Vec2 lo = (box.min() - bounds_.min()).cwiseQuotient(bucket_size_);
  const Vec2 hi = (box.max() - bounds_.min()).cwiseQuotient(bucket_size_);
  auto column = [this](double r) { return ClampedFloor(r, 0, bx_ - 1); };
  auto row = [this](double r) { return ClampedFloor(r, 0, by_ - 1); };
  return {column(lo.x()), column(hi.x()), row(lo.y()), row(hi.y())};
}

void FlatLocator::Bucket(const std::vector<Eigen::AlignedBox2d>& boxes, std::vector<int>* start,
                         std::vector<int>* items) const {
  std::vector<int> count(static_cast<size_t>(bx_) * by_ + 1, 0);
  for (const Eigen::AlignedBox2d& box : boxes) {
    const auto [x0, x1, y0, y1] = BucketsOf(box);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) ++count[x + bx_ * y + 1];
  }
  for (size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
  *start = count;
  items->resize(count.back());
  for (size_t k = 0; k < boxes.size(); ++k) {
    const auto [x0, x1, y0, y1] = BucketsOf(boxes[k]);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) (*items)[count[x + bx_ * y]++] = static_cast<int>(k);
  }
}

// Solves p = a + s e + t f + s t g for (s, t), the inverse of the bilinear map
// of the quad a (0,0), b (1,0), c (1,1), d (0,1): eliminating s leaves
// k2 t^2 + k1 t + k0 = 0. Returns false when no root lies in the cell (with a
// relative tolerance).
bool FlatLocator::Cell::Inverse(const Vec2& p, double* s_out, double* t_out) const {
  const Vec2 h = p - a;
  const double k1_p = k1 + Cross2(h, g);
  const double k0 = Cross2(h, e);
  constexpr double kTol = 1e-9;
  auto s_of = [&](double t) {
    const Vec2 den = e + g * t;
    const Vec2 num = h - f * t;
    return std::abs(den.x()) >= std::abs(den.y()) ? num.x() / den.x() : num.y() / den.y();
  };
  auto accept = [&](double t) {
    if (!(t >= -kTol && t <= 1.0 + kTol)) return false;
    const double s = s_of(t);
    if (!(s >= -kTol && s <= 1.0 + kTol)) return false;
    *s_out = std::clamp(s, 0.0, 1.0);
    *t_out = std::clamp(t, 0.0, 1.0);
    return true;
  };
  if (parallelogram) {  // linear
    if (k1_p == 0.0) return false;
    return accept(-k0 / k1_p);
  }
  const double disc = k1_p * k1_p - 4.0 * k0 * k2;
  if (disc < 0.0) return false;
  // The numerically stable pair of roots.
  const double q = -0.5 * (k1_p + std::copysign(std::sqrt(disc), k1_p));
  const double t1 = q / k2;
  if (accept(t1)) return true;
  return accept(q != 0.0 ? k0 / q : t1);
}

bool FlatLocator::TryCell(int cell, const Vec2& p, SheetLocation* out) const {
  const Cell& c = cells_[cell];
  if (!c.bounds.contains(p)) return false;
  double s, t;
  if (!c.Inverse(p, &s, &t)) return false;
  *out = {c.i, c.j, s, t};
  return true;
}

bool FlatLocator::Locate(const Vec2& p, SheetLocation* out, int* hint) const {
  if (hint != nullptr && *hint >= 0 && TryCell(*hint, p, out)) return true;
  const Vec2 rel = (p - bounds_.min()).cwiseQuotient(bucket_size_);
  if (!(rel.x() >= -1e-9 * bx_ && rel.y() >= -1e-9 * by_ && rel.x() <= bx_ * (1 + 1e-9) &&
        rel.y() <= by_ * (1 + 1e-9))) {
    return false;
  }
  const BucketSpan at = BucketsOf(Eigen::AlignedBox2d(p, p));
  const int b = at.x0 + bx_ * at.y0;
  for (int k = bucket_start_[b]; k < bucket_start_[b + 1]; ++k) {
    if (TryCell(bucket_cells_[k], p, out)) {
      if (hint != nullptr) *hint = bucket_cells_[k];
      return true;
    }
  }
  return false;
}

SheetLocation FlatLocator::NearestOnBoundary(const Vec2& p, double* distance) const {
  double best = std::numeric_limits<double>::infinity();
  SheetLocation loc;
  // One boundary side of one cell: the segment from corner a to corner b,
  // local coordinates running from la to lb.
  auto consider = [&](int i, int j, const Vec2& a, const Vec2& b, const Vec2& la, const Vec2& lb) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double w = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d = (p - (a + w * ab)).norm();
    if (d < best) {
      best = d;
      const Vec2 st = la + w * (lb - la);
      loc = {i, j, st.x(), st.y()};
    }
  };
  for (int i = 0; i + 1 < nu_; ++i) {
    consider(i, 0, Corner(i, 0), Corner(i + 1, 0), Vec2(0, 0), Vec2(1, 0));
    consider(i, nv_ - 2, Corner(i, nv_ - 1), Corner(i + 1, nv_ - 1), Vec2(0, 1), Vec2(1, 1));
  }
  for (int j = 0; j + 1 < nv_; ++j) {
    consider(0, j, Corner(0, j), Corner(0, j + 1), Vec2(0, 0), Vec2(0, 1));
    consider(nu_ - 2, j, Corner(nu_ - 1, j), Corner(nu_ - 1, j + 1), Vec2(1, 0), Vec2(1, 1));
  }
  *distance = best;
  return loc;
}

bool FlatLocator::BoundaryWithin(const Vec2& p, double distance) const {
  const double limit = distance * distance;
  auto near = [&](const Segment& s) {
    const Vec2 ap = p - s.a;
    const double w = std::clamp(ap.dot(s.ab) * s.inv_len2, 0.0, 1.0);
    return (ap - w * s.ab).squaredNorm() < limit;
  };
  // Only the segments listed in the buckets that meet the square around p
  // (every segment lies inside the bounds, so the range is clamped to them);
  // all of them when that square covers more buckets than there are segments.
  const Vec2 lo = (p - bounds_.min()).array() - distance;
  const Vec2 hi = (p - bounds_.min()).array() + distance;
  const double x0 = std::floor(lo.x() / bucket_size_.x()),
               x1 = std::floor(hi.x() / bucket_size_.x());
  const double y0 = std::floor(lo.y() / bucket_size_.y()),
               y1 = std::floor(hi.y() / bucket_size_.y());
  if (!(x1 >= 0.0 && y1 >= 0.0 && x0 < bx_ && y0 < by_)) return false;  // no segment that near
  const double span = (std::min(x1, bx_ - 1.0) - std::max(x0, 0.0) + 1.0) *
                      (std::min(y1, by_ - 1.0) - std::max(y0, 0.0) + 1.0);
  if (!(span <= static_cast<double>(boundary_.size()))) {
    for (const Segment& s : boundary_) {
      if (near(s)) return true;
    }
    return false;
  }
  const int bx0 = std::max(static_cast<int>(x0), 0), bx1 = std::min(static_cast<int>(x1), bx_ - 1);
  const int by0 = std::max(static_cast<int>(y0), 0), by1 = std::min(static_cast<int>(y1), by_ - 1);
  for (int y = by0; y <= by1; ++y) {
    for (int x = bx0; x <= bx1; ++x) {
      const int b = x + bx_ * y;
      for (int k = boundary_start_[b]; k < boundary_start_[b + 1]; ++k) {
        if (near(boundary_[boundary_segments_[k]])) return true;
      }
    }
  }
  return false;
}

Vec2 FlatLocator::FlatPoint(const SheetLocation& l) const {
  const Vec2 &a = Corner(l.i, l.j), &b = Corner(l.i + 1, l.j);
  const Vec2 &c = Corner(l.i + 1, l.j + 1), &d = Corner(l.i, l.j + 1);
  return (1 - l.s) * (1 - l.t) * a + l.s * (1 - l.t) * b + l.s * l.t * c + (1 - l.s) * l.t * d;
}

Eigen::Matrix2d FlatLocator::FlatJacobian(const SheetLocation& l) const {
  const Vec2 &a = Corner(l.i, l.j), &b = Corner(l.i + 1, l.j);
  const Vec2 &c = Corner(l.i + 1, l.j + 1), &d = Corner(l.i, l.j + 1);
  Eigen::Matrix2d m;
  m.col(0) = (1 - l.t) * (b - a) + l.t * (c - d);
  m.col(1) = (1 - l.s) * (d - a) + l.s * (c - b);
  return m;
}

void FlatLocator::CellsAlongSegment(const Vec2& a, const Vec2& b, std::vector<int>* cells) const {
  cells->clear();
  // Row by row of buckets: the x-range the segment covers within the row's
  // y-range, widened by a hair so that a segment on a bucket border sees both.
  const Vec2 ra = (a - bounds_.min()).cwiseQuotient(bucket_size_);
  const Vec2 rb = (b - bounds_.min()).cwiseQuotient(bucket_size_);
  constexpr double kPad = 1e-7;
  const double y_lo = std::min(ra.y(), rb.y()) - kPad, y_hi = std::max(ra.y(), rb.y()) + kPad;
  // Rows past either end (by_, -1) leave the loop empty.
  const int row0 = ClampedFloor(y_lo, 0, by_);
  const int row1 = ClampedFloor(y_hi, -1, by_ - 1);
  for (int y = row0; y <= row1; ++y) {
    const double lo = std::max(y_lo, static_cast<double>(y));
    const double hi = std::min(y_hi, static_cast<double>(y + 1));
    double x_lo, x_hi;
    if (std::abs(rb.y() - ra.y()) < 1e-300) {
      x_lo = std::min(ra.x(), rb.x());
      x_hi = std::max(ra.x(), rb.x());
    } else {
      auto x_at = [&](double yy) {
        const double w = std::clamp((yy - ra.y()) / (rb.y() - ra.y()), 0.0, 1.0);
        return ra.x() + w * (rb.x() - ra.x());
      };
      x_lo = std::min(x_at(lo), x_at(hi));
      x_hi = std::max(x_at(lo), x_at(hi));
    }
    AppendBucketRow(y, ClampedFloor(x_lo - kPad, 0, bx_), ClampedFloor(x_hi + kPad, -1, bx_ - 1),
                    cells);
  }
  SortUnique(cells);
}

void FlatLocator::CellsInBox(const Eigen::AlignedBox2d& box, std::vector<int>* cells) const {
  cells->clear();
  const auto [x0, x1, y0, y1] = BucketsOf(box);
  for (int y = y0; y <= y1; ++y) AppendBucketRow(y, x0, x1, cells);
  SortUnique(cells);
}

void FlatLocator::AppendBucketRow(int y, int x0, int x1, std::vector<int>* cells) const {
  for (int x = x0; x <= x1; ++x) {
    const int bucket = x + bx_ * y;
    cells->insert(cells->end(), bucket_cells_.begin() + bucket_start_[bucket],
                  bucket_cells_.begin() + bucket_start_[bucket + 1]);
  }
}

void FlatLocator::SortUnique(std::vector<int>* cells) {
  std::sort(cells->begin(), cells->end());
  cells->erase(std::unique(cells->begin(), cells->end()), cells->end());
}

double FlatLocator::CellMinSide(int cell) const {
  const int i = cell % (nu_ - 1), j = cell / (nu_ - 1);
  const Vec2 &p00 = Corner(i, j), &p10 = Corner(i + 1, j);
  const Vec2 &p01 = Corner(i, j + 1), &p11 = Corner(i + 1, j + 1);
  return std::min({(p10 - p00).norm(), (p11 - p10).norm(), (p11 - p01).norm(), (p01 - p00).norm()});
}

}  // namespace surfdeform
