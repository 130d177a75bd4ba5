#include "cgal_peer.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/Surface_mesh_shortest_path.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

namespace surfdeform::bench {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = Mesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

template <typename Parameterizer>
PeerResult Run(const std::vector<Vec3>& positions, const std::vector<std::array<int, 3>>& tris) {
  Mesh mesh;
  std::vector<VertexIndex> vertices;
  for (const Vec3& p : positions) {
    vertices.push_back(mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  }
  for (const auto& t : tris) mesh.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]);
  auto border = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  auto uv = mesh.add_property_map<VertexIndex, Kernel::Point_2>("v:uv").first;
  PeerResult r;
  const SMP::Error_code err = SMP::parameterize(mesh, Parameterizer(), border, uv);
  if (err != SMP::OK) {
    r.error = SMP::get_error_message(err);
    return r;
  }
  r.ok = true;
  for (VertexIndex v : vertices) r.flat.emplace_back(uv[v].x(), uv[v].y());
  return r;
}

}  // namespace

std::vector<std::array<int, 3>> DelaunayTriangles(const std::vector<Vec2>& points) {
  using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
  using Tds = CGAL::Triangulation_data_structure_2<VertexBase>;
  using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;
  std::vector<std::pair<Kernel::Point_2, int>> input;
  for (size_t k = 0; k < points.size(); ++k) {
    input.emplace_back(Kernel::Point_2(points[k].x(), points[k].y()), static_cast<int>(k));
  }
  Delaunay dt(input.begin(), input.end());
  std::vector<std::array<int, 3>> triangles;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
    triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return triangles;
}

std::vector<double> ExactGeodesics(const std::vector<Vec3>& positions,
                                   const std::vector<std::array<int, 3>>& triangles, int source) {
  using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, Mesh>;
  using ShortestPath = CGAL::Surface_mesh_shortest_path<Traits>;
  Mesh mesh;
  std::vector<VertexIndex> vertices;
  for (const Vec3& p : positions) {
    vertices.push_back(mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  }
  for (const auto& t : triangles) mesh.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]);
  ShortestPath paths(mesh);
  paths.add_source_point(vertices[source]);
  paths.build_sequence_tree();
  std::vector<double> d;
  for (VertexIndex v : vertices) d.push_back(paths.shortest_distance_to_source_points(v).first);
  return d;
}

PeerResult CgalParameterizeMesh(const std::vector<Vec3>& positions,
                                const std::vector<std::array<int, 3>>& triangles,
                                const std::string& method) {
  if (method == "arap") return Run<SMP::ARAP_parameterizer_3<Mesh>>(positions, triangles);
  return Run<SMP::LSCM_parameterizer_3<Mesh>>(positions, triangles);
}

PeerResult CgalParameterize(const Surface& surface, int nu, int nv, const std::string& method) {
  std::vector<Vec3> positions;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      positions.push_back(
          surface.Position(static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1)));
    }
  }
  std::vector<std::array<int, 3>> triangles;
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      const int a = i + nu * j, b = a + 1, c = a + 1 + nu, d = a + nu;
      triangles.push_back({a, b, c});
      triangles.push_back({a, c, d});
    }
  }
  return CgalParameterizeMesh(positions, triangles, method);
}

}  // namespace surfdeform::bench
