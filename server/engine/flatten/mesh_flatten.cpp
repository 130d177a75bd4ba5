#include "engine/flatten/mesh_flatten.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>

#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"
#include "engine/common/sparse_cholesky.hpp"
#include "engine/distance/mesh_chart.hpp"
#include "engine/flatten/flatten_solvers.hpp"
#include "engine/flatten/sheet_motion.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

// The Laplacian of the pairs' graph (unit weights) without the row and
// column of the last vertex, which the solves hold at the origin, factored.
class GroundedLaplacian {
 public:
  GroundedLaplacian(int n, const std::vector<GridEdge>& pairs) : n_(n) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(pairs.size() * 2 + n);
    std::vector<double> degree(n, 0.0);
    const int g = n - 1;
    for (const GridEdge& e : pairs) {
      degree[e.i] += 1.0;
      degree[e.j] += 1.0;
      if (e.i != g && e.j != g) {
        entries.emplace_back(std::max(e.i, e.j), std::min(e.i, e.j), -1.0);  // lower triangle
      }
    }
    for (int v = 0; v < g; ++v) entries.emplace_back(v, v, degree[v]);
    Eigen::SparseMatrix<double> l(g, g);
    l.setFromTriplets(entries.begin(), entries.end());
    factor_ = std::make_unique<SparseCholesky>(l);
  }
  bool ok() const { return factor_->ok(); }
  // b (x block then y block of n) -> L^+ b with the last vertex at the origin.
  void Solve(Eigen::VectorXd* b) const {
    Eigen::Map<Eigen::MatrixXd> m(b->data(), n_, 2);
    const Eigen::MatrixXd top = m.topRows(n_ - 1);
    m.topRows(n_ - 1) = factor_->Solve(top);
    m.row(n_ - 1).setZero();
  }

 private:
  int n_;
  std::unique_ptr<SparseCholesky> factor_;
};

double SignedArea(const std::vector<Vec2>& x, const std::array<int, 3>& t) {
  return 0.5 * Cross2(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
}

// Turns back triangles the stress let fold: it barely sees a thin one flip.
// Each interior vertex of a folded triangle moves to the mean-value
// combination of its neighbours (Floater 2003; weights from the angles of
// its one-ring in space), which reproduces a planar one-ring exactly and
// lies within the convex hull of the ring. Up to `passes` passes over the
// folded triangles; returns how many stay folded.
int Untangle(const DiskMesh& mesh, const internal::MeshAdjacency& adjacency, int passes,
             std::vector<Vec2>* x) {
  std::vector<char> on_boundary(mesh.positions.size(), 0);
  for (int v : mesh.boundary) on_boundary[v] = 1;
  const std::vector<Vec3>& p = mesh.positions;
  std::vector<int> moving;
  for (int pass = 0;; ++pass) {
    moving.clear();
    for (const auto& t : mesh.triangles) {
      if (SignedArea(*x, t) > 0.0) continue;
      for (int v : t) {
        if (!on_boundary[v]) moving.push_back(v);
      }
    }
    if (moving.empty() || pass == passes) {
      int folded = 0;
      for (const auto& t : mesh.triangles) folded += SignedArea(*x, t) > 0.0 ? 0 : 1;
      return folded;
    }
    std::sort(moving.begin(), moving.end());
    moving.erase(std::unique(moving.begin(), moving.end()), moving.end());
    for (int v : moving) {
      Vec2 sum = Vec2::Zero();
      double weights = 0.0;
      for (int k = adjacency.triangle_start[v]; k < adjacency.triangle_start[v + 1]; ++k) {
        const auto& t = mesh.triangles[adjacency.triangles[k]];
        const int c = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        const int a = t[(c + 1) % 3], b = t[(c + 2) % 3];
        const Vec3 ea = p[a] - p[v], eb = p[b] - p[v];
        const double half = 0.5 * std::atan2(ea.cross(eb).norm(), ea.dot(eb));
        const double wa = std::tan(half) / ea.norm(), wb = std::tan(half) / eb.norm();
        sum += wa * (*x)[a] + wb * (*x)[b];
        weights += wa + wb;
      }
      if (weights > 0.0) (*x)[v] = sum / weights;
    }
  }
}

// Moves `x` to the canonical frame: counter-clockwise triangles, the area
// centroid at the origin, the axis of least spread along Y.
void Canonicalize(const DiskMesh& mesh, std::vector<Vec2>* x) {
  double total = 0.0;
  for (const auto& t : mesh.triangles) total += SignedArea(*x, t);
  if (total < 0.0) {
    for (Vec2& p : *x) p.x() = -p.x();
    total = -total;
  }
  Vec2 centroid = Vec2::Zero();
  for (const auto& t : mesh.triangles) {
    centroid += SignedArea(*x, t) * ((*x)[t[0]] + (*x)[t[1]] + (*x)[t[2]]) / 3.0;
  }
  centroid /= total;
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const auto& t : mesh.triangles) {
    const Vec2 c = ((*x)[t[0]] + (*x)[t[1]] + (*x)[t[2]]) / 3.0 - centroid;
    spread += SignedArea(*x, t) * c * c.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(spread);
  Vec2 axis = eig.eigenvectors().col(1);  // the largest spread
  if (axis.x() < 0.0 || (axis.x() == 0.0 && axis.y() < 0.0)) axis = -axis;
  Eigen::Matrix2d rotation;
  rotation << axis.x(), axis.y(), -axis.y(), axis.x();
  for (Vec2& p : *x) p = rotation * (p - centroid);
}

// Moves `x` onto `start` (the same vertices) by a rigid motion: the
// centroids matched, turned by the rotation of the best affine map from `x`
// to `start` (its polar decomposition's; shape matching, Mueller et al.
// 2005). A sheet that stretches from one frame to the next (a cloth pulled
// one way) then does not turn as a least-squares rigid fit of a jittered
// mesh would, a little with every frame; where the affine map mirrors
// (never for two layouts of one unfolded mesh), the least-squares rigid fit.
void MoveOnto(const std::vector<Vec2>& start, std::vector<Vec2>* x) {
  const double n = static_cast<double>(x->size());
  Vec2 cx = Vec2::Zero(), cs = Vec2::Zero();
  for (size_t v = 0; v < x->size(); ++v) {
    cx += (*x)[v] / n;
    cs += start[v] / n;
  }
  Eigen::Matrix2d xx = Eigen::Matrix2d::Zero(), sx = Eigen::Matrix2d::Zero();
  for (size_t v = 0; v < x->size(); ++v) {
    const Vec2 a = (*x)[v] - cx;
    xx += a * a.transpose();
    sx += (start[v] - cs) * a.transpose();
  }
  double angle = 0.0;
  const Eigen::Matrix2d affine = sx * xx.inverse();
  if (affine.allFinite() && affine.determinant() > 0.0) {
    angle = std::atan2(affine(1, 0) - affine(0, 1), affine(0, 0) + affine(1, 1));
  } else if (auto m = BestSheetMotion(*x, start); m.ok()) {
    angle = m->angle;
  }
  const Eigen::Rotation2Dd turn(angle);
  for (Vec2& p : *x) p = cs + turn * (p - cx);
}

void MeasureMeshQuality(const DiskMesh& mesh, const std::vector<GridEdge>& pairs,
                        const std::vector<Vec2>& x, FlattenQuality* q) {
  double c = 0.0, total = 0.0;
  q->max_edge_error = 0.0;
  for (const GridEdge& e : pairs) {
    const double len = (x[e.i] - x[e.j]).norm();
    c += (e.d - len) * (e.d - len);
    total += e.d * e.d;
    if (e.ring == 1) q->max_edge_error = std::max(q->max_edge_error, std::abs(len - e.d) / e.d);
  }
  q->stress = total > 0.0 ? std::sqrt(c / total) : 0.0;
  q->area_ratio_min = std::numeric_limits<double>::infinity();
  q->area_ratio_max = 0.0;
  q->folded_cells = 0;
  for (const auto& t : mesh.triangles) {
    const double flat = SignedArea(x, t);
    const Vec3& a = mesh.positions[t[0]];
    const double area = 0.5 * (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a).norm();
    if (!(flat > 0.0)) ++q->folded_cells;
    q->area_ratio_min = std::min(q->area_ratio_min, flat / area);
    q->area_ratio_max = std::max(q->area_ratio_max, flat / area);
  }
}

std::vector<Vec3> VertexNormals(const DiskMesh& mesh) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    const Vec3 n = (mesh.positions[t[1]] - mesh.positions[t[0]])
                       .cross(mesh.positions[t[2]] - mesh.positions[t[0]])
                       .normalized();
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = (mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]).normalized();
      const Vec3 b = (mesh.positions[t[(k + 2) % 3]] - mesh.positions[t[k]]).normalized();
      normals[t[k]] += std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * n;
    }
  }
  for (Vec3& n : normals) n.normalize();
  return normals;
}

}  // namespace

Result<FlatMesh> AssembleFlatMesh(DiskMesh mesh, std::vector<Vec2> flat,
                                  const FlattenQuality& quality) {
  if (flat.size() != mesh.positions.size()) {
    return InvalidArgument("the flat positions are " + std::to_string(flat.size()) +
                           " for a mesh of " + std::to_string(mesh.positions.size()) + " vertices");
  }
  for (const Vec2& p : flat) {
    if (!p.allFinite()) return InvalidArgument("a flat position is not finite");
  }
  for (const auto& t : mesh.triangles) {
    if (!(SignedArea(flat, t) > 0.0)) return InvalidArgument("a flat triangle is folded");
  }
  FlatMesh out;
  out.normals = VertexNormals(mesh);
  out.mesh = std::move(mesh);
  out.flat = std::move(flat);
  out.quality = quality;
  return out;
}

std::vector<GridEdge> MeshPairDistances(const FlatMesh& reference, int rings, int threads) {
  const internal::MeshAdjacency adjacency = internal::Adjacency(reference.mesh);
  std::vector<GridEdge> pairs = *internal::RingPairs(adjacency, rings, threads);
  internal::MeasureAlongChart(reference.mesh, adjacency, reference.flat, threads, &pairs);
  std::erase_if(pairs, [](const GridEdge& e) { return !(e.d > 0.0); });
  return pairs;
}

FlattenQuality MeasureMeshLayout(const FlatMesh& reference, std::vector<Vec2> layout, int threads) {
  const DiskMesh& mesh = reference.mesh;
  const std::vector<GridEdge> pairs = MeshPairDistances(reference, 3, threads);
  double total = 0.0;
  for (const auto& t : mesh.triangles) total += SignedArea(layout, t);
  if (total < 0.0) {
    for (Vec2& p : layout) p.x() = -p.x();
  }
  FlattenQuality q;
  MeasureMeshQuality(mesh, pairs, layout, &q);
  return q;
}

// What consecutive flattenings of one topology share: the adjacency, the
// pairs listed (their distances those of the last flattening), which of them
// the stress sums, and the factored Laplacian of their graph.
struct MeshFlattener::Topology {
  std::vector<std::array<int, 3>> triangles;
  int range = 0;
  internal::MeshAdjacency adjacency;
  std::vector<GridEdge> all;
  std::vector<GridEdge> solved;
  std::vector<size_t> solved_at;  // each solved pair's place in `all`
  std::unique_ptr<GroundedLaplacian> laplacian;
};

MeshFlattener::MeshFlattener(FlattenOptions options) : options_(std::move(options)) {}
MeshFlattener::~MeshFlattener() = default;
MeshFlattener::MeshFlattener(MeshFlattener&&) noexcept = default;
MeshFlattener& MeshFlattener::operator=(MeshFlattener&&) noexcept = default;

Result<FlatMesh> MeshFlattener::Flatten(DiskMesh mesh, const std::vector<Vec2>* start,
                                        const std::vector<Vec2>* guess) {
  const FlattenOptions& options = options_;
  const auto t0 = Clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidateFlattenOptions(options));
  if (start != nullptr) {
    if (start->size() != mesh.positions.size()) {
      return InvalidArgument("the start layout has " + std::to_string(start->size()) +
                             " points for a mesh of " + std::to_string(mesh.positions.size()) +
                             " vertices");
    }
    for (const Vec2& p : *start) {
      if (!p.allFinite()) return InvalidArgument("a point of the start layout is not finite");
    }
    if (guess != nullptr && guess->size() != start->size()) {
      return InvalidArgument("the guess has another size than the start layout");
    }
  }
  if (options.method != FlattenMethod::kMajorization) {
    return InvalidArgument("a mesh surface is flattened by \"majorization\" only",
                           "flatten.method");
  }
  const internal::Deadline deadline = DeadlineAfter(t0, options.time_budget_ms, options.cancel);
  auto out_of_time = [&](const char* stage) {
    return Status::DeadlineExceeded(
        std::string("the mesh flattening ran out of its time budget of ") +
            std::to_string(static_cast<long long>(options.time_budget_ms)) + " ms (" + stage +
            "); decimate the mesh, use a smaller range or a looser tolerance",
        "flatten", options.time_budget_ms, MsSince(t0));
  };
  const int n = static_cast<int>(mesh.positions.size());
  FlatMesh out;
  // From a start layout, a mesh of the last one's topology keeps its pairs
  // and factor (a pair whose segment now leaves the mesh is left free).
  const bool same = start != nullptr && topology_ != nullptr && topology_->range == options.range &&
                    topology_->triangles == mesh.triangles;
  if (!same) {
    topology_.reset();
    auto t = std::make_unique<Topology>();
    t->triangles = mesh.triangles;
    t->range = options.range;
    t->adjacency = internal::Adjacency(mesh);
    // Pairs within max(range, 3) rings (3 for the quality measures). Listed
    // before the chart is made, so that a mesh with more pairs than it may
    // have is refused before the chart's memory (some 3.8 KB a vertex) is
    // taken.
    const auto td = Clock::now();
    const int rings = std::max(options.range, 3);
    std::optional<std::vector<GridEdge>> listed =
        internal::RingPairs(t->adjacency, rings, options.threads, options.max_mesh_pairs);
    if (!listed) {
      return Status::LimitExceeded(
          "the mesh has more than " + std::to_string(options.max_mesh_pairs) +
              " vertex pairs within " + std::to_string(rings) +
              " rings (some vertex joins very many triangles, or the range is large): use a "
              "smaller flatten.range, or remesh the surface more evenly",
          "flatten.range", static_cast<double>(options.max_mesh_pairs),
          static_cast<double>(options.max_mesh_pairs) + 1);
    }
    t->all = std::move(*listed);
    out.quality.distance_ms += MsSince(td);
    topology_ = std::move(t);
  }
  Topology& topology = *topology_;
  const internal::MeshAdjacency& adjacency = topology.adjacency;
  std::vector<GridEdge>& all = topology.all;
  std::vector<Vec2> x;
  if (start != nullptr) {
    x = *start;
  } else {
    SURFDEFORM_ASSIGN_OR_RETURN(x, internal::ConformalChart(mesh));
  }
  if (deadline.Passed()) return out_of_time("the conformal start");
  const auto t_distances = Clock::now();
  // Another mesh's distances are no fallback: where a pair's segment leaves
  // this one, it is left out (as measured afresh).
  if (same) {
    for (GridEdge& e : all) e.d = 0.0;
  }
  if (!internal::MeasureAlongChart(mesh, adjacency, x, options.threads, &all, deadline)) {
    topology_.reset();  // half measured
    return out_of_time("the distances");
  }
  out.quality.distance_ms += MsSince(t_distances);
  if (deadline.Passed()) return out_of_time("the distances");

  const int max_it = options.max_iterations > 0 ? options.max_iterations : 3000;
  // The pairs the stress sums: within range, measured along the first chart
  // (the conformal one, or the first frame's start); and where each is in
  // `all`, to take later measurements' distances.
  std::vector<GridEdge>& solved = topology.solved;
  const std::vector<size_t>& solved_at = topology.solved_at;
  auto take_distances = [&] {
    // A pair whose segment now leaves the mesh keeps its earlier distance
    // when the mesh is the same (round 2); on another mesh (a later frame)
    // it is left free (a negative distance: the solver keeps its current
    // length, which leaves the stress's minimum where the other pairs put
    // it), so that the factor still serves.
    for (size_t k = 0; k < solved.size(); ++k)
      solved[k].d = all[solved_at[k]].d > 0.0 ? all[solved_at[k]].d : -1.0;
  };
  if (topology.laplacian == nullptr) {
    for (size_t k = 0; k < all.size(); ++k) {
      if (all[k].ring <= options.range && all[k].d > 0.0) {
        topology.solved.push_back(all[k]);
        topology.solved_at.push_back(k);
      }
    }
    const auto tf = Clock::now();
    auto laplacian = std::make_unique<GroundedLaplacian>(n, solved);
    out.quality.solve_ms += MsSince(tf);
    if (!laplacian->ok()) {
      topology_.reset();
      return Status(ErrorCode::kNotConverged,
                    "the stress Laplacian of the mesh could not be factored");
    }
    topology.laplacian = std::move(laplacian);
  } else {
    take_distances();
  }
  const GroundedLaplacian& laplacian = *topology.laplacian;
  if (start != nullptr && guess != nullptr) x = *guess;
  // Round 1 from the chart; from the conformal chart, round 2 measures again
  // along the first result (closer to an isometry) and continues from it.
  // The pairs kept are those measured in round 1, so the factor stays
  // valid. From a start layout (near-isometric already), round 1 alone.
  const int rounds = start != nullptr ? 1 : 2;
  for (int round = 0; round < rounds; ++round) {
    if (round == 1) {
      const auto tr = Clock::now();
      if (!internal::MeasureAlongChart(mesh, adjacency, x, options.threads, &all, deadline)) {
        topology_.reset();
        return out_of_time("the distances");
      }
      out.quality.distance_ms += MsSince(tr);
      take_distances();
    }
    const auto tm = Clock::now();
    // A stress of 1e-12 counts as none: a developable mesh would otherwise
    // crawl from its exact conformal start to the last bits.
    const internal::SolveStats stats =
        internal::MajorizeLayout([&](Eigen::VectorXd* b) { laplacian.Solve(b); }, solved,
                                 options.tolerance, max_it, options.threads, &x, deadline, 1e-24);
    out.quality.solve_ms += MsSince(tm);
    out.quality.iterations += stats.iterations;
    out.quality.converged = stats.converged;
    if (stats.out_of_time) return out_of_time("the stress solve");
  }
  for (const Vec2& p : x) {
    if (!p.allFinite()) {
      return Status(ErrorCode::kNotConverged, "the mesh flattening diverged");
    }
  }
  if (start != nullptr) {
    // The grounded solve holds the last vertex at the origin: back onto the start.
    MoveOnto(*start, &x);
  } else {
    Canonicalize(mesh, &x);
  }
  Untangle(mesh, adjacency, 100, &x);
  std::vector<GridEdge> measured;
  for (const GridEdge& e : all) {
    if (e.ring <= 3 && e.d > 0.0) measured.push_back(e);
  }
  out.pairs = solved.size();
  out.dropped_pairs = static_cast<size_t>(
      std::count_if(all.begin(), all.end(), [](const GridEdge& e) { return !(e.d > 0.0); }));
  MeasureMeshQuality(mesh, measured, x, &out.quality);
  if (out.quality.folded_cells > 0) {
    return Status(ErrorCode::kNotConverged,
                  std::to_string(out.quality.folded_cells) + " of " +
                      std::to_string(mesh.triangles.size()) +
                      " triangles fold over in the flat sheet, so it cannot be inverted; the "
                      "surface bends too much to lie flat in one piece: cut it into flatter "
                      "pieces, or use a larger range");
  }
  out.normals = VertexNormals(mesh);
  out.flat = std::move(x);
  out.mesh = std::move(mesh);
  out.quality.total_ms = MsSince(t0);
  return out;
}

Result<FlatMesh> FlattenMesh(DiskMesh mesh, const FlattenOptions& options,
                             const std::vector<Vec2>* start) {
  return MeshFlattener(options).Flatten(std::move(mesh), start);
}

}  // namespace surfdeform
