// A flattened triangle mesh as a Surface, so that placement, the
// map, subdivision, rigid parts and the distortion treat it as every other
// kind.
//
// Its parameters are the flat sheet itself: (u, v) in [0, 1]^2 spans a box
// round the flat mesh (FlatMesh::flat), centred on the mesh's area centroid
// (or the triangle centre nearest it, when the centroid falls outside a
// concave mesh), so that (1/2, 1/2), where placement centres a model, is on
// the mesh. The unrolling is therefore exact (ExactUnrolling is the flat
// point), and the map from the sheet to the surface is:
//  - position: barycentric on the 3D triangle whose flat image holds the
//    point (piecewise linear, as the mesh is);
//  - normal: the vertex normals interpolated barycentrically and normalised,
//    so that heights along it do not crack at the mesh's edges;
//  - first derivatives: the triangle's, projected onto the plane normal to
//    that normal (Su x Sv is then along it, and a model's normals and
//    tangents turn with the interpolated normal); second derivatives zero.
// Points of the box off the mesh continue the nearest boundary triangle's
// map (DomainGap says how far off they are).
#pragma once

#include <memory>

#include "engine/common/flat_sheet.hpp"
#include "engine/surface/flat_triangles.hpp"
#include "engine/surface/surface.hpp"

namespace surfdeform {

class MeshSurface final : public Surface {
 public:
  explicit MeshSurface(std::shared_ptr<const FlatMesh> mesh);

  SurfacePoint Evaluate(double u, double v, int order) const override;
  const char* Kind() const override { return "mesh"; }
  std::optional<Vec2> ExactUnrolling(double u, double v) const override {
    return box_min_ + Vec2(u * box_size_.x(), v * box_size_.y());
  }
  std::optional<Vec2> InverseUnrolling(const Vec2& flat) const override {
    return (flat - box_min_).cwiseQuotient(box_size_);
  }
  std::optional<double> DomainGap(const Vec2& uv, Vec2* nearest) const override;
  std::optional<double> DomainDepth(const Vec2& uv) const override;
  const FlatMesh* flat_mesh() const override { return mesh_.get(); }

  const FlatTriangles& index() const { return index_; }

 private:
  std::shared_ptr<const FlatMesh> mesh_;
  FlatTriangles index_;
  Vec2 box_min_ = Vec2::Zero();
  Vec2 box_size_ = Vec2::Ones();
};

// The index of a flattened mesh: its triangles and boundary.
FlatTriangles IndexFlatMesh(const FlatMesh& mesh);

}  // namespace surfdeform
