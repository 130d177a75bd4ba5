// A constrained Delaunay triangulation of one mesh face, in the face's own
// plane, for the subdivision: the face's three corners, the points kept on its
// sides, the points kept inside it, and the grid-line chords between them as
// constraints.
//
// The face's sides are fixed: a point is only ever added on a side by
// SplitBoundary, so a face's triangulation uses exactly the points its sides
// were given, and neighbouring faces, given the same side points, agree (no
// cracks, no T-junctions). Interior points are inserted by Lawson's
// incremental algorithm (Delaunay flips, never across a constrained edge);
// constraints by Sloan's edge flipping (Sloan 1993, "A fast algorithm for
// generating constrained Delaunay triangulations"). Every triangle is kept
// counter-clockwise in the frame given, so a face frame that keeps the face's
// orientation gives triangles that keep it.
//
// Robustness: predicates are evaluated in doubles with tolerances relative to
// the face's size; a point within 1e-9 of the face's size of an existing point
// is that point, and one within that distance of an edge is inserted on the
// edge (orientation tests are signed distances). Numbers are in the frame's
// units.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "engine/common/geometry_types.hpp"

namespace surfdeform {

class FaceTriangulation {
 public:
  struct Triangle {
    std::array<int, 3> v;   // point ids, counter-clockwise
    std::array<int, 3> n;   // triangle across the edge opposite v[k]; -1 on the face's side
    std::array<bool, 3> c;  // that edge is constrained (sides always are)
    uint32_t stamp = 0;     // changes whenever the triangle does
  };

  // The face (a, b, c), counter-clockwise: points 0, 1, 2.
  FaceTriangulation(const Vec2& a, const Vec2& b, const Vec2& c);

  // Adds point p on the side from point `from` to point `to`, which must be
  // an edge of the face's outline now (p strictly between them). Returns its id.
  int SplitBoundary(int from, int to, const Vec2& p);

  // Inserts p inside the face. Returns its id, or that of the existing point
  // it coincides with; -1 when p is not inside the face (or on its outline).
  int Insert(const Vec2& p);

  // Makes the segment a-b an edge of the triangulation and constrains it.
  // Points found on the segment split it. False when it crosses a constrained
  // edge (then the triangulation is unchanged but for the flips made), or
  // when the stop test (SetStop) says so.
  bool Constrain(int a, int b);

  // A test Constrain looks at every 64 flips, giving up once it is true:
  // on a long thin face, flipping one constraint in can take up to its
  // guard's (number crossed)^2 steps, each a walk round a point's fan.
  void SetStop(std::function<bool()> stop) { stop_ = std::move(stop); }

  // Delaunay flips over every unconstrained edge (after constraints, whose
  // insertion leaves other edges as they fell).
  void RestoreDelaunay();

  // Splits the edge opposite v[k] of triangle t at its midpoint (not on a
  // side). Returns the new point's id.
  int SplitInteriorEdge(int t, int k);

  // True when the edge opposite v[k] of triangle t lies on the face's outline.
  bool OnOutline(int t, int k) const { return tris_[t].n[k] < 0; }

  // The triangles changed or created since the last call (repeats possible).
  std::vector<int> TakeTouched() { return std::exchange(touched_, {}); }

  const std::vector<Vec2>& points() const { return pts_; }
  const std::vector<Triangle>& triangles() const { return tris_; }
  double size() const { return size_; }

 private:
  double Orient(int a, int b, const Vec2& p) const;
  bool InCircle(int t, const Vec2& p) const;
  int NewTriangle(int a, int b, int c);
  void Link(int t, int k, int u, int l);            // t's edge k and u's edge l are the same edge
  void Around(int a, std::vector<int>* out) const;  // the triangles around point a
  int FindEdge(int a, int b, int* k) const;         // triangle with directed edge a -> b, its index
  int EdgeIndex(int t, int a, int b) const;         // k with edge opposite v[k] = a -> b (in t)
  int Locate(const Vec2& p) const;
  int SplitEdge(int t, int k, const Vec2& p);
  void SplitTriangle(int t, int p);
  void Flip(int t, int k);
  void Legalize(std::vector<std::pair<int, int>>* stack);
  void LegalizeAround(int p);
  bool Crosses(int a, int b, int p, int q) const;  // segment p-q crosses a-b in their interiors
  void Touch(int t);

  std::vector<Vec2> pts_;
  std::vector<Triangle> tris_;
  std::vector<int> vtri_;  // a triangle incident to each point
  double size_ = 1.0;      // the face's diameter
  double eps_len_ = 0.0;   // coincidence distance
  uint32_t clock_ = 0;
  std::vector<int> touched_;
  std::function<bool()> stop_;
};

}  // namespace surfdeform
