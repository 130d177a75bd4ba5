#include "engine/sheet/sheet_marks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/format.hpp"

namespace surfdeform {
namespace {

SheetMark MarkOfParameters(const SheetMap& map, const Vec2& uv) {
  SheetMark m;
  const SurfacePoint s = map.surface().Evaluate(uv.x(), uv.y(), 1);
  m.point = s.p;
  m.normal = UnitNormal(s);
  m.uv = map.GivenParameters(uv);  // modulo the period on a closed surface
  return m;
}

// The distance of the image of the sheet piece a-b from the chord between
// the images of its ends, at a quarter, half and three quarters.
double ChordDeviation(const SheetMap& map, const Vec2& a, const Vec2& b, const Vec3& pa,
                      const Vec3& pb) {
  double worst = 0.0;
  for (double t : {0.25, 0.5, 0.75}) {
    const Vec3 on = map.Position(Vec3(a.x() + t * (b.x() - a.x()), a.y() + t * (b.y() - a.y()), 0),
                                 OutsideMode::kClamp, nullptr);
    worst = std::max(worst, (on - (pa + t * (pb - pa))).norm());
  }
  return worst;
}

}  // namespace

SheetMark MarkAt(const SheetMap& map, const Vec2& ab) {
  const SheetParameters p = map.Parameters(ab, OutsideMode::kClamp, false, nullptr);
  SheetMark m = MarkOfParameters(map, p.uv);
  m.sheet = ab;
  m.on_sheet = !p.outside;
  return m;
}

Result<std::vector<std::vector<SheetMark>>> ResamplePolylines(
    const SheetMap& map, const std::vector<std::vector<Vec2>>& polylines,
    const PolylineOptions& o) {
  const double diagonal = map.given_locator().bounds().diagonal().norm();
  const double tolerance = o.tolerance > 0.0 ? o.tolerance : 1e-3 * diagonal;
  const double finest = kFinestMarkShare * diagonal;
  for (const auto& [value, field] :
       {std::pair{o.tolerance, "tolerance"}, std::pair{o.max_segment, "max_segment"}}) {
    if (value > 0.0 && value < finest) {
      return InvalidArgument(Format("must be at least %g (1e-7 of the sheet's diagonal, finer "
                                    "than the flattening keeps distances), got %g",
                                    finest, value),
                             field);
    }
  }
  for (size_t k = 0; k < polylines.size(); ++k) {
    const std::string field = "polylines[" + std::to_string(k) + "]";
    if (polylines[k].size() < 2)
      return InvalidArgument("a polyline needs two points or more", field);
    for (const Vec2& p : polylines[k]) {
      if (!p.allFinite()) return InvalidArgument("a point is not finite", field);
    }
  }
  std::vector<std::vector<SheetMark>> out(polylines.size());
  size_t total = 0;
  auto add = [&](std::vector<SheetMark>* line, const SheetMark& m) -> Status {
    if (++total > o.max_points) {
      return Status::LimitExceeded(
          "the resampled polylines would have more than " + std::to_string(o.max_points) +
              " points; raise max_segment or tolerance, or send fewer polylines",
          "polylines", static_cast<double>(o.max_points), static_cast<double>(total));
    }
    line->push_back(m);
    return Status::Ok();
  };
  for (size_t k = 0; k < polylines.size(); ++k) {
    const std::vector<Vec2>& in = polylines[k];
    std::vector<SheetMark>& line = out[k];
    SURFDEFORM_RETURN_IF_ERROR(add(&line, MarkAt(map, in[0])));
    for (size_t e = 0; e + 1 < in.size(); ++e) {
      // Depth-first bisection of the piece in[e] - in[e + 1]: a stack of the
      // pieces' far ends, nearest on top, so points come out in order.
      std::vector<std::pair<SheetMark, int>> ends = {{MarkAt(map, in[e + 1]), 0}};
      while (!ends.empty()) {
        const SheetMark& from = line.back();
        const auto [to, depth] = ends.back();
        const bool long_piece =
            o.max_segment > 0.0 && (to.sheet - from.sheet).norm() > o.max_segment;
        // 40 halvings: pieces 1e-12 of the segment; a kink ends there.
        if (depth < 40 && (long_piece || ChordDeviation(map, from.sheet, to.sheet, from.point,
                                                        to.point) > tolerance)) {
          ends.emplace_back(MarkAt(map, 0.5 * (from.sheet + to.sheet)), depth + 1);
          continue;
        }
        ends.pop_back();
        SURFDEFORM_RETURN_IF_ERROR(add(&line, to));
      }
    }
  }
  return out;
}

SheetMark MarkNearest(const SheetMap& map, const Vec3& x) {
  const FlatSheet& sheet = map.sheet();
  // The nearest sample.
  size_t best = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < sheet.points.size(); ++k) {
    const double d2 = (sheet.points[k] - x).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = k;
    }
  }
  Vec2 uv(static_cast<double>(best % sheet.nu) / (sheet.nu - 1),
          static_cast<double>(best / sheet.nu) / (sheet.nv - 1));
  // Newton on f = |S - x|^2 / 2, with the Gauss-Newton Hessian where the full
  // one is not positive definite, a halving line search, and the step kept
  // inside [0, 1]^2.
  const Surface& surface = map.surface();
  auto f = [&](const Vec2& p) {
    return 0.5 * (surface.Evaluate(p.x(), p.y(), 0).p - x).squaredNorm();
  };
  double fx = f(uv);
  for (int it = 0; it < 100; ++it) {
    const SurfacePoint s = surface.Evaluate(uv.x(), uv.y(), 2);
    const Vec3 r = s.p - x;
    const Vec2 g(s.su.dot(r), s.sv.dot(r));
    Eigen::Matrix2d h;
    h << s.su.dot(s.su), s.su.dot(s.sv), s.su.dot(s.sv), s.sv.dot(s.sv);
    Eigen::Matrix2d full = h;
    full(0, 0) += s.suu.dot(r);
    full(0, 1) += s.suv.dot(r);
    full(1, 0) += s.suv.dot(r);
    full(1, 1) += s.svv.dot(r);
    const bool definite = full(0, 0) > 0.0 && full.determinant() > 0.0;
    Vec2 step = -(definite ? full : h).ldlt().solve(g);
    if (!step.allFinite()) break;
    // Not out of the domain: stop at its border (the projected step).
    const Vec2 target = (uv + step).cwiseMax(0.0).cwiseMin(1.0);
    step = target - uv;
    double t = 1.0, ft = f(uv + step);
    while (ft > fx && t > 1e-12) {
      t *= 0.5;
      ft = f(uv + t * step);
    }
    if (ft > fx) break;
    const Vec2 moved = t * step;
    uv += moved;
    fx = ft;
    if (moved.norm() < 1e-15) break;
  }
  // On a closed surface, the copy of the point on the given sheet.
  uv = map.MapParameters(map.GivenParameters(uv));
  SheetMark m = MarkOfParameters(map, uv);
  m.sheet = map.SheetPoint(uv);
  m.on_sheet = true;
  m.distance = (m.point - x).norm();
  return m;
}

}  // namespace surfdeform
