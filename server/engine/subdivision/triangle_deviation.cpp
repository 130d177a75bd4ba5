#include "engine/subdivision/triangle_deviation.hpp"

namespace surfdeform::subdivision {

double TriangleDeviation::operator()(int t, int* hint) {
  const FaceTriangulation& tri = work_.tri;
  const FaceTriangulation::Triangle& tr = tri.triangles()[t];
  if (static_cast<size_t>(t) >= cache_.size()) cache_.resize(tri.triangles().size());
  if (cache_[t].dev >= 0.0 && cache_[t].stamp == tr.stamp) return cache_[t].dev;
  const std::vector<Vec2>& pts = tri.points();
  const std::vector<Vec3>& fval = work_.fval;
  double dev = 0.0;
  constexpr double a = 2.0 / 3, b = 1.0 / 6, c = 1.0 / 3;
  const double w[7][3] = {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {c, c, c},
                          {a, b, b},     {b, a, b},     {b, b, a}};
  for (const auto& ww : w) {
    const int zero = ww[0] == 0.0 ? 0 : ww[1] == 0.0 ? 1 : ww[2] == 0.0 ? 2 : -1;
    if (zero >= 0 && tri.OnOutline(t, zero)) continue;
    const Vec2 p = ww[0] * pts[tr.v[0]] + ww[1] * pts[tr.v[1]] + ww[2] * pts[tr.v[2]];
    const Vec2 l = work_.Bary(p);
    const Vec3 exact = ctx_.Deformed(ctx_.InTriangle(corners_, l.x(), l.y()), hint);
    const Vec3 linear = ww[0] * fval[tr.v[0]] + ww[1] * fval[tr.v[1]] + ww[2] * fval[tr.v[2]];
    dev = std::max(dev, (exact - linear).norm());
  }
  tally_->measured += 7;
  cache_[t] = {tr.stamp, dev};
  return dev;
}

}  // namespace surfdeform::subdivision
