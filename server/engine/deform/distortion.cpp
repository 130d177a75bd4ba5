#include "engine/deform/distortion.hpp"

#include <algorithm>
#include <cmath>

namespace surfdeform {

Vec2 SingularValues(const Eigen::Matrix<double, 3, 2>& j) {
  // The eigenvalues of the 2x2 Gram matrix J^T J, in the stable form.
  const double a = j.col(0).squaredNorm();
  const double b = j.col(0).dot(j.col(1));
  const double c = j.col(1).squaredNorm();
  const double mean = 0.5 * (a + c);
  const double radius = std::hypot(0.5 * (a - c), b);
  const double l1 = mean + radius;
  // l1 * l2 = det, which keeps the small one accurate when they differ a lot.
  const double det = a * c - b * b;
  const double l2 = l1 > 0.0 ? std::max(0.0, det / l1) : 0.0;
  return Vec2(std::sqrt(l1), std::sqrt(l2));
}

DistortionStats SummarizeDistortion(const Mesh& mesh) {
  DistortionStats st;
  const size_t n = mesh.distortion.size();
  if (n == 0 || n != mesh.positions.size()) return st;
  st.computed = true;
  std::vector<double> d(n);
  for (size_t k = 0; k < n; ++k) {
    d[k] = std::max(std::abs(mesh.distortion[k].x()), std::abs(mesh.distortion[k].y()));
  }
  std::vector<double> weight(n, 0.0);
  for (const auto& t : mesh.triangles) {
    const Vec3& p = mesh.positions[t[0]];
    const double third = (mesh.positions[t[1]] - p).cross(mesh.positions[t[2]] - p).norm() / 6.0;
    for (uint32_t v : t) weight[v] += third;
  }
  double total = 0.0, sum = 0.0;
  for (size_t k = 0; k < n; ++k) {
    total += weight[k];
    sum += weight[k] * d[k];
  }
  if (total > 0.0) {
    st.mean = sum / total;
  } else {
    for (double x : d) st.mean += x / static_cast<double>(n);
  }
  st.max = *std::max_element(d.begin(), d.end());
  // Nearest rank: the smallest value with at least 95% of the values at or below it.
  const size_t rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(n)));
  std::nth_element(d.begin(), d.begin() + (rank - 1), d.end());
  st.p95 = d[rank - 1];
  return st;
}

}  // namespace surfdeform
