#include "engine/distance/mesh_chart.hpp"

#include <Eigen/SparseCore>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "engine/common/parallel.hpp"
#include "engine/common/sparse_cholesky.hpp"

namespace surfdeform::internal {

MeshAdjacency Adjacency(const DiskMesh& mesh) {
  const size_t n = mesh.positions.size();
  MeshAdjacency a;
  a.triangle_start.assign(n + 1, 0);
  for (const auto& t : mesh.triangles) {
    for (int v : t) ++a.triangle_start[v + 1];
  }
  std::partial_sum(a.triangle_start.begin(), a.triangle_start.end(), a.triangle_start.begin());
  a.triangles.resize(a.triangle_start.back());
  std::vector<int> fill(a.triangle_start.begin(), a.triangle_start.end() - 1);
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (int v : mesh.triangles[f]) a.triangles[fill[v]++] = static_cast<int>(f);
  }
  // Neighbours: the other corners of a vertex's triangles, each once.
  a.vertex_start.assign(n + 1, 0);
  std::vector<int> scratch;
  for (size_t v = 0; v < n; ++v) {
    scratch.clear();
    for (int k = a.triangle_start[v]; k < a.triangle_start[v + 1]; ++k) {
      for (int w : mesh.triangles[a.triangles[k]]) {
        if (w != static_cast<int>(v)) scratch.push_back(w);
      }
    }
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    a.vertices.insert(a.vertices.end(), scratch.begin(), scratch.end());
    a.vertex_start[v + 1] = static_cast<int>(a.vertices.size());
  }
  return a;
}

Result<std::vector<Vec2>> ConformalChart(const DiskMesh& mesh) {
  const int n = static_cast<int>(mesh.positions.size());
  const std::vector<Vec3>& X = mesh.positions;
  // The pins: the boundary vertex farthest from the loop's first, and the
  // one farthest from that.
  auto farthest = [&](int from) {
    int best = from;
    double d = -1.0;
    for (int v : mesh.boundary) {
      const double e = (X[v] - X[from]).squaredNorm();
      if (e > d) {
        d = e;
        best = v;
      }
    }
    return best;
  };
  const int pa = farthest(mesh.boundary.front());
  const int pb = farthest(pa);
  // Unknowns u_0..u_{n-1}, v_0..v_{n-1}; the pins' four are moved to the
  // right-hand side.
  std::vector<int> column(2 * n, -1);
  int free = 0;
  for (int c = 0; c < 2 * n; ++c) {
    const int v = c % n;
    if (v != pa && v != pb) column[c] = free++;
  }
  Eigen::VectorXd pinned = Eigen::VectorXd::Zero(2 * n);
  pinned(pb) = (X[pb] - X[pa]).norm();  // u_b; u_a = v_a = v_b = 0

  // Per triangle, in its own plane (q0 = 0, q1 on +x, q2 above), the
  // gradients g_k of the barycentric functions; the residual of the
  // Cauchy-Riemann equations grad v = perp(grad u) is
  // sum_k v_k g_k - u_k perp(g_k), two rows weighted by sqrt(area).
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(mesh.triangles.size() * 12);
  Eigen::VectorXd rhs_rows =
      Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(mesh.triangles.size()));
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3 e1 = X[t[1]] - X[t[0]], e2 = X[t[2]] - X[t[0]];
    const double l1 = e1.norm();
    const Vec3 ex = e1 / l1;
    const double x2 = e2.dot(ex);
    const double y2 = ex.cross(e2).norm();
    const Vec2 q[3] = {Vec2(0, 0), Vec2(l1, 0), Vec2(x2, y2)};
    const double area = 0.5 * l1 * y2;
    const double w = std::sqrt(area);
    for (int k = 0; k < 3; ++k) {
      const Vec2 e = q[(k + 2) % 3] - q[(k + 1) % 3];
      const Vec2 g = Vec2(-e.y(), e.x()) / (2 * area);
      // Row 2f: v_k g.x + u_k g.y; row 2f + 1: v_k g.y - u_k g.x.
      const double coef[2][2] = {{g.y(), g.x()}, {-g.x(), g.y()}};  // [row][u, v]
      for (int r = 0; r < 2; ++r) {
        for (int uv = 0; uv < 2; ++uv) {
          const int c = t[k] + uv * n;
          const double value = w * coef[r][uv];
          const Eigen::Index row = 2 * static_cast<Eigen::Index>(f) + r;
          if (column[c] >= 0) {
            entries.emplace_back(row, column[c], value);
          } else {
            rhs_rows(row) -= value * pinned(c);
          }
        }
      }
    }
  }
  Eigen::SparseMatrix<double> a(2 * static_cast<Eigen::Index>(mesh.triangles.size()), free);
  a.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> at = a.transpose();
  const Eigen::SparseMatrix<double> normal = at * a;
  const SparseCholesky factor(normal);
  if (!factor.ok()) {
    return Status(ErrorCode::kNotConverged,
                  "the conformal start of the mesh flattening could not be factored");
  }
  const Eigen::VectorXd solution = factor.Solve(Eigen::MatrixXd(at * rhs_rows));
  std::vector<Vec2> chart(n);
  for (int v = 0; v < n; ++v) {
    const double u = column[v] >= 0 ? solution(column[v]) : pinned(v);
    const double w = column[v + n] >= 0 ? solution(column[v + n]) : pinned(v + n);
    chart[v] = Vec2(u, w);
    if (!chart[v].allFinite()) {
      return Status(ErrorCode::kNotConverged,
                    "the conformal start of the mesh flattening is not finite");
    }
  }
  return chart;
}

std::optional<std::vector<GridEdge>> RingPairs(const MeshAdjacency& adjacency, int rings,
                                               int threads, size_t max_pairs) {
  const int n = static_cast<int>(adjacency.vertex_start.size()) - 1;
  threads = std::max(1, std::min(ResolveThreads(threads), n / 4096 + 1));
  std::vector<std::vector<GridEdge>> parts(threads);
  std::atomic<size_t> listed{0};
  std::atomic<bool> over{false};
  ParallelChunks(n, threads, [&](int chunk, int begin, int end) {
    std::vector<int> stamp(n, -1), frontier, next;
    std::vector<GridEdge>& out = parts[chunk];
    for (int i = begin; i < end; ++i) {
      if (over.load(std::memory_order_relaxed)) return;
      frontier.assign(1, i);
      stamp[i] = i;
      const size_t first = out.size();
      for (int ring = 1; ring <= rings && !frontier.empty(); ++ring) {
        next.clear();
        for (int v : frontier) {
          for (int k = adjacency.vertex_start[v]; k < adjacency.vertex_start[v + 1]; ++k) {
            const int w = adjacency.vertices[k];
            if (stamp[w] == i) continue;
            stamp[w] = i;
            next.push_back(w);
            if (w > i) {
              GridEdge e;
              e.i = i;
              e.j = w;
              e.ring = ring;
              out.push_back(e);
            }
          }
        }
        frontier.swap(next);
      }
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                [](const GridEdge& a, const GridEdge& b) { return a.j < b.j; });
      if (max_pairs > 0 &&
          listed.fetch_add(out.size() - first, std::memory_order_relaxed) + (out.size() - first) >
              max_pairs) {
        over.store(true, std::memory_order_relaxed);
        return;
      }
    }
  });
  if (over.load()) return std::nullopt;
  std::vector<GridEdge> pairs;
  for (auto& p : parts) pairs.insert(pairs.end(), p.begin(), p.end());
  return pairs;
}

namespace {

// The mesh length of the straight chart segment from vertex i to vertex j,
// or -1 where it leaves the mesh (or the walk does not end).
class SegmentTracer {
 public:
  SegmentTracer(const DiskMesh& mesh, const MeshAdjacency& adjacency, const std::vector<Vec2>& x)
      : mesh_(mesh), adj_(adjacency), x_(x) {}

  double Length(int i, int j) const {
    const Vec2 p = x_[i];
    const Vec2 d = x_[j] - p;
    const double dd = d.squaredNorm();
    if (!(dd > 0.0)) return -1.0;
    const double nd = std::sqrt(dd);
    const std::vector<Vec3>& space = mesh_.positions;
    // The length is summed in space, between the points where the segment
    // crosses the mesh's edges (placed along each edge by the chart): a
    // chart's slight misshape of a thin triangle moves a crossing a little
    // along its edge, never far off.
    double total = 0.0;
    Vec3 at = space[i];
    int v = i;
    for (int steps = 0; steps < kMaxSteps;) {
      // At vertex v: the triangle whose corner at v holds the direction d.
      int cur = -1, right = -1, left = -1, through = -1;
      for (int k = adj_.triangle_start[v]; k < adj_.triangle_start[v + 1]; ++k) {
        const int f = adj_.triangles[k];
        const auto& t = mesh_.triangles[f];
        const int c = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        const int b = t[(c + 1) % 3], e = t[(c + 2) % 3];
        const Vec2 xb = x_[b] - x_[v], xe = x_[e] - x_[v];
        const double sb = Cross2(xb, d), se = Cross2(d, xe);
        const double tb = kCollinear * xb.norm() * nd, te = kCollinear * xe.norm() * nd;
        if (sb < -tb || se < -te) continue;
        // Along an edge: the segment runs through that vertex.
        if (std::abs(sb) <= tb && xb.dot(d) > 0.0) {
          through = b;
        } else if (std::abs(se) <= te && xe.dot(d) > 0.0) {
          through = e;
        } else {
          cur = f;
          right = b;
          left = e;
        }
        break;
      }
      if (through >= 0) {
        if (through != j && (x_[through] - p).dot(d) >= dd) return -1.0;  // passes j
        total += (space[through] - at).norm();
        if (through == j) return total;
        at = space[through];
        v = through;
        ++steps;
        continue;
      }
      if (cur < 0) return -1.0;
      // Walk across triangles: the segment leaves cur through edge (right, left).
      for (;; ++steps) {
        if (steps >= kMaxSteps) return -1.0;
        const Vec3 exit = Crossing(p, d, right, left);
        total += (exit - at).norm();
        at = exit;
        const auto& t = mesh_.triangles[cur];
        const int cr = t[0] == right ? 0 : t[1] == right ? 1 : 2;
        const int next = mesh_.neighbours[cur][cr];
        if (next < 0) return -1.0;
        const auto& u = mesh_.triangles[next];
        const int w = u[0] != right && u[0] != left   ? u[0]
                      : u[1] != right && u[1] != left ? u[1]
                                                      : u[2];
        if (w == j) return total + (space[j] - at).norm();
        const Vec2 xw = x_[w] - p;
        const double side = Cross2(d, xw);
        if (std::abs(side) <= kCollinear * nd * xw.norm()) {
          if (xw.dot(d) >= dd) return -1.0;
          total += (space[w] - at).norm();
          at = space[w];
          v = w;
          ++steps;
          break;
        }
        if (side > 0.0) {
          left = w;
        } else {
          right = w;
        }
        cur = next;
      }
    }
    return -1.0;
  }

 private:
  static constexpr int kMaxSteps = 256;
  // A vertex within this fraction of the lengths involved of the segment is
  // on it (the chart is solved to about 1e-10).
  static constexpr double kCollinear = 1e-9;

  // Where p + tau d crosses edge (a, b), in space: the point that far along
  // the edge.
  Vec3 Crossing(const Vec2& p, const Vec2& d, int a, int b) const {
    const Vec2 e = x_[b] - x_[a];
    const double lambda = std::clamp(Cross2(p - x_[a], d) / Cross2(e, d), 0.0, 1.0);
    return mesh_.positions[a] + lambda * (mesh_.positions[b] - mesh_.positions[a]);
  }

  const DiskMesh& mesh_;
  const MeshAdjacency& adj_;
  const std::vector<Vec2>& x_;
};

}  // namespace

bool MeasureAlongChart(const DiskMesh& mesh, const MeshAdjacency& adjacency,
                       const std::vector<Vec2>& chart, int threads, std::vector<GridEdge>* pairs,
                       Deadline deadline) {
  const SegmentTracer tracer(mesh, adjacency, chart);
  std::vector<GridEdge>& e = *pairs;
  const int count = static_cast<int>(e.size());
  std::atomic<bool> late{false};
  ParallelChunks(count, std::min(ResolveThreads(threads), count / 20000 + 1),
                 [&](int, int begin, int end) {
                   for (int k = begin; k < end; ++k) {
                     if ((k - begin) % 4096 == 4095 &&
                         (late.load(std::memory_order_relaxed) || deadline.Passed())) {
                       late.store(true, std::memory_order_relaxed);
                       return;
                     }
                     if (e[k].ring == 1) {
                       e[k].d = (mesh.positions[e[k].i] - mesh.positions[e[k].j]).norm();
                       continue;
                     }
                     const double d = tracer.Length(e[k].i, e[k].j);
                     if (d > 0.0) {
                       e[k].d = d;
                     } else if (!(e[k].d > 0.0)) {
                       e[k].d = -1.0;
                     }
                   }
                 });
  return !late.load();
}

}  // namespace surfdeform::internal
