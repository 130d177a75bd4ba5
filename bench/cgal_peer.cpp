#include "cgal_peer.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

namespace surfdeform::bench {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = Mesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

template <typename Parameterizer>
PeerResult Run(const Surface& surface, int nu, int nv) {
  Mesh mesh;
  std::vector<VertexIndex> vertices;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const Vec3 p =
          surface.Position(static_cast<double>(i) / (nu - 1), static_cast<double>(j) / (nv - 1));
      vertices.push_back(mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
    }
  }
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      const VertexIndex a = vertices[i + nu * j], b = vertices[i + 1 + nu * j];
      const VertexIndex c = vertices[i + 1 + nu * (j + 1)], d = vertices[i + nu * (j + 1)];
      mesh.add_face(a, b, c);
      mesh.add_face(a, c, d);
    }
  }
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

PeerResult CgalParameterize(const Surface& surface, int nu, int nv, const std::string& method) {
  if (method == "arap") return Run<SMP::ARAP_parameterizer_3<Mesh>>(surface, nu, nv);
  return Run<SMP::LSCM_parameterizer_3<Mesh>>(surface, nu, nv);
}

}  // namespace surfdeform::bench
