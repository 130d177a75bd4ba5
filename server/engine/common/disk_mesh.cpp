#include "engine/common/disk_mesh.hpp"

#include "base/format.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>
#include <unordered_map>

namespace surfdeform {
namespace {

Status Refuse(const std::string& message) {
  return Status(ErrorCode::kDegenerate, message, "model_id");
}

// Welds vertices closer than `tolerance` (a spatial hash of cells that
// size, each vertex compared with the representatives of the 27 cells
// round its own). Returns the representative of every input vertex.
std::vector<int> Weld(const std::vector<Vec3>& p, double tolerance) {
  std::vector<int> rep(p.size());
  if (!(tolerance > 0.0)) {
    std::iota(rep.begin(), rep.end(), 0);
    return rep;
  }
  auto cell = [&](const Vec3& x) {
    return Eigen::Vector3<long long>(static_cast<long long>(std::floor(x.x() / tolerance)),
                                     static_cast<long long>(std::floor(x.y() / tolerance)),
                                     static_cast<long long>(std::floor(x.z() / tolerance)));
  };
  auto key = [](const Eigen::Vector3<long long>& c) {
    const auto h = [](long long v) { return static_cast<unsigned long long>(v); };
    return h(c.x()) * 0x9E3779B97F4A7C15ull ^ h(c.y()) * 0xC2B2AE3D27D4EB4Full ^
           h(c.z()) * 0x165667B19E3779F9ull;
  };
  std::unordered_multimap<unsigned long long, int> reps;
  reps.reserve(p.size());
  for (size_t v = 0; v < p.size(); ++v) {
    const auto c = cell(p[v]);
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto range = reps.equal_range(key(c + Eigen::Vector3<long long>(dx, dy, dz)));
          for (auto it = range.first; it != range.second; ++it) {
            if ((p[it->second] - p[v]).norm() <= tolerance) {
              found = it->second;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(v);
      reps.emplace(key(c), found);
    }
    rep[v] = found;
  }
  return rep;
}

struct HalfEdges {
  // opposite[3 f + k]: the triangle across edge k of triangle f (from
  // corner k to corner k + 1), -1 on the boundary.
  std::vector<int> opposite;
};

// Pairs the triangles' edges; the first edge in more than two triangles, or
// two triangles that run along an edge in the same direction, is refused.
Result<HalfEdges> PairEdges(const std::vector<std::array<int, 3>>& tris) {
  struct Entry {
    unsigned long long key;
    int half;  // 3 f + k
    bool forward;
  };
  std::vector<Entry> entries;
  entries.reserve(tris.size() * 3);
  for (size_t f = 0; f < tris.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const unsigned a = static_cast<unsigned>(tris[f][k]);
      const unsigned b = static_cast<unsigned>(tris[f][(k + 1) % 3]);
      const unsigned long long key =
          (static_cast<unsigned long long>(std::min(a, b)) << 32) | std::max(a, b);
      entries.push_back({key, static_cast<int>(3 * f + k), a < b});
    }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return x.key != y.key ? x.key < y.key : x.half < y.half;
  });
  HalfEdges h;
  h.opposite.assign(tris.size() * 3, -1);
  for (size_t s = 0; s < entries.size();) {
    size_t e = s;
    while (e < entries.size() && entries[e].key == entries[s].key) ++e;
    const unsigned a = static_cast<unsigned>(entries[s].key >> 32);
    const unsigned b = static_cast<unsigned>(entries[s].key & 0xffffffffu);
    if (e - s > 2) {
      return Refuse("edge (" + std::to_string(a) + ", " + std::to_string(b) + ") is shared by " +
                    std::to_string(e - s) + " triangles (" + std::to_string(entries[s].half / 3) +
                    ", " + std::to_string(entries[s + 1].half / 3) + ", " +
                    std::to_string(entries[s + 2].half / 3) +
                    "...): the mesh is not manifold there; remove the extra triangles or split "
                    "the surface along that edge");
    }
    if (e - s == 2) {
      if (entries[s].forward == entries[s + 1].forward) {
        return Refuse("triangles " + std::to_string(entries[s].half / 3) + " and " +
                      std::to_string(entries[s + 1].half / 3) + " run along edge (" +
                      std::to_string(a) + ", " + std::to_string(b) +
                      ") in the same direction: triangle " +
                      std::to_string(entries[s + 1].half / 3) +
                      " is flipped (or the surface is not orientable); orient the faces "
                      "consistently (\"recalculate normals\" in a mesh editor)");
      }
      h.opposite[entries[s].half] = entries[s + 1].half / 3;
      h.opposite[entries[s + 1].half] = entries[s].half / 3;
    }
    s = e;
  }
  return h;
}

int CornerOf(const std::array<int, 3>& t, int v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

// The first vertex whose triangles form more than one fan (they meet there
// and nowhere else round it), or -1.
int NonManifoldVertex(const std::vector<std::array<int, 3>>& tris, const HalfEdges& h,
                      size_t vertices) {
  std::vector<int> start(vertices + 1, 0);
  for (const auto& t : tris) {
    for (int v : t) ++start[v + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> incident(start.back());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < tris.size(); ++f) {
    for (int v : tris[f]) incident[fill[v]++] = static_cast<int>(f);
  }
  std::vector<int> seen(tris.size(), -1);
  for (size_t v = 0; v < vertices; ++v) {
    const int iv = static_cast<int>(v);
    const int first = start[v], last = start[v + 1];
    if (first == last) continue;
    // Walk the fan of the first triangle both ways round v.
    const int f0 = incident[first];
    seen[f0] = iv;
    for (int dir = 0; dir < 2; ++dir) {
      int f = f0;
      for (;;) {
        const int c = CornerOf(tris[f], iv);
        // dir 0: across the edge from v to the next corner; 1: from the previous one to v.
        const int g = h.opposite[3 * f + (dir == 0 ? c : (c + 2) % 3)];
        if (g < 0 || seen[g] == iv) break;
        seen[g] = iv;
        f = g;
      }
    }
    for (int k = first; k < last; ++k) {
      if (seen[incident[k]] != iv) return iv;
    }
  }
  return -1;
}

int Find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

int CollapsedTriangle(const DiskMesh& mesh, double min_area) {
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3& a = mesh.positions[t[0]];
    const double area = 0.5 * (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a).norm();
    if (!(area > min_area)) return static_cast<int>(f);
  }
  return -1;
}

Result<DiskMesh> MakeDiskMesh(const std::vector<Vec3>& positions,
                              const std::vector<std::array<uint32_t, 3>>& triangles,
                              const DiskMeshOptions& options) {
  if (triangles.empty()) return Refuse("the mesh has no triangles");
  Eigen::AlignedBox3d box;
  for (size_t v = 0; v < positions.size(); ++v) {
    if (!positions[v].allFinite()) {
      return InvalidArgument("vertex " + std::to_string(v) + " is not finite", "model_id");
    }
    box.extend(positions[v]);
  }
  for (size_t f = 0; f < triangles.size(); ++f) {
    for (uint32_t v : triangles[f]) {
      if (v >= positions.size()) {
        return InvalidArgument("triangle " + std::to_string(f) + " names vertex " +
                                   std::to_string(v) + " of " + std::to_string(positions.size()),
                               "model_id");
      }
    }
  }
  const double diagonal = box.diagonal().norm();
  if (!(diagonal > 0.0)) return Refuse("every vertex of the mesh is at one point");

  // Weld, then renumber the vertices the triangles use, in the input's
  // order (a mesh with nothing to weld or drop keeps its numbers).
  const std::vector<int> rep = Weld(positions, options.weld_tolerance * diagonal);
  DiskMesh out;
  std::vector<int> index(positions.size(), -1);
  for (const auto& t : triangles) {
    for (uint32_t v : t) index[rep[v]] = 0;
  }
  for (size_t v = 0; v < positions.size(); ++v) {
    if (rep[v] != static_cast<int>(v)) {
      ++out.welded;
    } else if (index[v] < 0) {
      ++out.dropped;
    } else {
      index[v] = static_cast<int>(out.positions.size());
      out.positions.push_back(positions[v]);
    }
  }
  out.triangles.resize(triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) out.triangles[f][k] = index[rep[triangles[f][k]]];
  }
  const size_t n = out.positions.size();
  if (options.max_vertices > 0 && n > options.max_vertices) {
    return Status::LimitExceeded(
        "the surface mesh has " + std::to_string(n) + " vertices, more than " +
            std::to_string(options.max_vertices) + "; decimate it",
        "model_id", static_cast<double>(options.max_vertices), static_cast<double>(n));
  }

  if (const int f = CollapsedTriangle(out, options.min_area * diagonal * diagonal); f >= 0) {
    const auto& t = out.triangles[f];
    const Vec3& a = out.positions[t[0]];
    const double area = 0.5 * (out.positions[t[1]] - a).cross(out.positions[t[2]] - a).norm();
    return Refuse("triangle " + std::to_string(f) + " has zero area (" + Num(area) +
                  "; its corners are vertices " + std::to_string(t[0]) + ", " +
                  std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                  " after welding): remove degenerate faces (\"merge by distance\" and "
                  "\"delete loose\" / \"degenerate dissolve\" in a mesh editor)");
  }

  SURFDEFORM_ASSIGN_OR_RETURN(const HalfEdges h, PairEdges(out.triangles));
  if (const int v = NonManifoldVertex(out.triangles, h, n); v >= 0) {
    return Refuse("vertex " + std::to_string(v) +
                  " joins triangles that meet nowhere else round it (a non-manifold vertex, "
                  "as where two sheets touch at a point): split the vertex or remove one of "
                  "the sheets");
  }

  // Components, over shared edges.
  const int nf = static_cast<int>(out.triangles.size());
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int g = h.opposite[3 * f + k];
      if (g >= 0) parent[Find(parent, f)] = Find(parent, g);
    }
  }
  std::unordered_map<int, int> sizes;
  for (int f = 0; f < nf; ++f) ++sizes[Find(parent, f)];
  if (sizes.size() > 1) {
    std::vector<int> counts;
    for (const auto& [root, count] : sizes) counts.push_back(count);
    std::sort(counts.rbegin(), counts.rend());
    std::string list;
    for (size_t c = 0; c < counts.size() && c < 5; ++c) {
      list += (c > 0 ? ", " : "") + std::to_string(counts[c]);
    }
    if (counts.size() > 5) list += ", ...";
    return Refuse("the mesh has " + std::to_string(counts.size()) + " separate components (of " +
                  list +
                  " triangles): keep the one to bend along (\"separate by loose parts\" in "
                  "a mesh editor)");
  }

  // Boundary loops: each boundary vertex of a manifold mesh starts exactly one
  // boundary edge.
  std::vector<int> next(n, -1);
  size_t boundary_edges = 0;
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (h.opposite[3 * f + k] >= 0) continue;
      next[out.triangles[f][k]] = out.triangles[f][(k + 1) % 3];
      ++boundary_edges;
    }
  }
  if (boundary_edges == 0) {
    return Refuse(
        "the mesh is closed (it has no boundary): cut it open along a seam, or cut a "
        "disk out of it, in a mesh editor; a closed surface cannot lie flat in one "
        "piece");
  }
  struct Loop {
    std::vector<int> vertices;
    double length = 0.0;
  };
  std::vector<Loop> loops;
  std::vector<char> done(n, 0);
  for (size_t v = 0; v < n; ++v) {
    if (next[v] < 0 || done[v]) continue;
    Loop loop;
    for (int w = static_cast<int>(v); !done[w]; w = next[w]) {
      done[w] = 1;
      loop.vertices.push_back(w);
      loop.length += (out.positions[next[w]] - out.positions[w]).norm();
    }
    loops.push_back(std::move(loop));
  }
  std::sort(loops.begin(), loops.end(),
            [](const Loop& a, const Loop& b) { return a.length > b.length; });
  if (loops.size() > 1) {
    return Refuse("the mesh has " + std::to_string(loops.size() - 1) +
                  (loops.size() == 2 ? " hole" : " holes") +
                  " besides its outer boundary (the longest " + Num(loops[1].length) +
                  " units round, through vertex " + std::to_string(loops[1].vertices[0]) +
                  "): fill the holes (\"fill holes\" in a mesh editor), or cut from each hole to "
                  "the outer boundary so that one boundary remains");
  }
  const long long edges = (3LL * nf + static_cast<long long>(boundary_edges)) / 2;
  const long long euler = static_cast<long long>(n) - edges + nf;
  if (euler != 1) {
    return Refuse("the mesh has one boundary but " + std::to_string((1 - euler) / 2) +
                  " handle(s) (Euler characteristic " + std::to_string(euler) +
                  ", a disk's is 1): cut through each handle so that the surface is a disk");
  }
  out.boundary = std::move(loops[0].vertices);
  out.neighbours.resize(out.triangles.size());
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) out.neighbours[f][k] = h.opposite[3 * f + k];
  }
  return out;
}

}  // namespace surfdeform
