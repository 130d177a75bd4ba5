// What a part is, checked before it is sent: closed (every edge shared by
// exactly two triangles), consistently oriented (the two run an edge in
// opposite directions), bounding a positive volume, no degenerate
// triangles, no triangles crossing one another; and its measures.
#pragma once

#include <string>
#include <vector>

#include "base/status.hpp"
#include "engine/common/mesh.hpp"

namespace surfdeform {

struct SolidReport {
  size_t vertices = 0;
  size_t triangles = 0;
  size_t border_edges = 0;        // edges of one triangle only: the part is not closed
  std::vector<Vec3> border_at;    // the first few border edges' midpoints
  size_t non_manifold_edges = 0;  // edges of three triangles or more
  size_t misoriented_edges = 0;   // edges two triangles run the same way
  size_t degenerate_triangles = 0;
  bool self_intersection_checked = false;  // only on a closed, manifold mesh
  bool self_intersects = false;
  double volume = 0.0;  // signed: outward triangles bound a positive one
  double area = 0.0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the bounding box

  bool closed() const { return border_edges == 0 && non_manifold_edges == 0; }
  bool oriented() const { return misoriented_edges == 0; }
  bool sound() const {
    return closed() && oriented() && degenerate_triangles == 0 && self_intersection_checked &&
           !self_intersects && volume > 0;
  }
};

// The checks and measures of `mesh`. The self-intersection test (CGAL's
// exact predicates on an AABB tree) runs when the mesh is closed and
// manifold and `self_intersections` is set.
SolidReport CheckSolid(const Mesh& mesh, bool self_intersections = true);

// The first check `report` fails, as an error naming what and where
// (kDegenerate; OK when it is sound). `what` names the mesh ("the part",
// "the body").
Status SolidProblem(const SolidReport& report, const std::string& what, const std::string& field);

}  // namespace surfdeform
