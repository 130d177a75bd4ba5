// CGAL's headers in this one translation unit (they are heavy to compile).
#include "text/glyph_mesh.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <unordered_map>

namespace surfdeform {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int region = -1;
};
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fbb = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbb>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact_predicates_tag: constraints may cross (overlapping contours); CGAL
// adds their crossing points.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// The winding number of the contours about p (Sunday's crossing rule).
int WindingNumber(const std::vector<std::vector<Vec2>>& contours, const Vec2& p) {
  int w = 0;
  for (const auto& c : contours) {
    const size_t n = c.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec2& a = c[i];
      const Vec2& b = c[(i + 1) % n];
      const double side = (b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y());
      if (a.y() <= p.y()) {
        if (b.y() > p.y() && side > 0) ++w;
      } else if (b.y() <= p.y() && side < 0) {
        --w;
      }
    }
  }
  return w;
}

double Area2(const K::Point_2& a, const K::Point_2& b, const K::Point_2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
}

}  // namespace

Result<GlyphSolid> MeshGlyph(const std::vector<std::vector<Vec2>>& contours, bool even_odd,
                             double scale, double depth) {
  GlyphSolid out;
  if (contours.empty()) return out;
  Cdt cdt;
  try {
    for (const auto& c : contours) {
      std::vector<Cdt::Vertex_handle> vs;
      vs.reserve(c.size());
      Cdt::Face_handle hint;
      for (const Vec2& p : c) {
        vs.push_back(cdt.insert(K::Point_2(p.x(), p.y()), hint));
        hint = vs.back()->face();
      }
      for (size_t i = 0; i < vs.size(); ++i) {
        const auto a = vs[i], b = vs[(i + 1) % vs.size()];
        if (a != b) cdt.insert_constraint(a, b);
      }
    }
  } catch (const std::exception& e) {
    return Status(ErrorCode::kDegenerate,
                  std::string("the glyph cannot be triangulated: ") + e.what(), "text.string");
  }
  // Regions: faces joined across edges that are no contour. The winding
  // number is constant over a region: computed once, at the centroid of its
  // largest face.
  std::vector<bool> inside;
  for (auto f : cdt.all_face_handles()) f->info().region = -1;
  std::vector<Cdt::Face_handle> stack;
  for (auto f : cdt.finite_face_handles()) {
    if (f->info().region >= 0) continue;
    const int region = static_cast<int>(inside.size());
    Cdt::Face_handle best = f;
    double best_area = -1.0;
    f->info().region = region;
    stack.push_back(f);
    bool touches_infinite = false;
    while (!stack.empty()) {
      auto g = stack.back();
      stack.pop_back();
      const double a = Area2(g->vertex(0)->point(), g->vertex(1)->point(), g->vertex(2)->point());
      if (a > best_area) {
        best_area = a;
        best = g;
      }
      for (int i = 0; i < 3; ++i) {
        if (g->is_constrained(i)) continue;
        auto h = g->neighbor(i);
        if (cdt.is_infinite(h)) {
          touches_infinite = true;
          continue;
        }
        if (h->info().region >= 0) continue;
        h->info().region = region;
        stack.push_back(h);
      }
    }
    bool in = false;
    if (!touches_infinite) {
      const auto& p0 = best->vertex(0)->point();
      const auto& p1 = best->vertex(1)->point();
      const auto& p2 = best->vertex(2)->point();
      const Vec2 c((p0.x() + p1.x() + p2.x()) / 3.0, (p0.y() + p1.y() + p2.y()) / 3.0);
      const int w = WindingNumber(contours, c);
      in = even_odd ? (w % 2 != 0) : (w != 0);
    }
    inside.push_back(in);
  }
  const auto is_in = [&](Cdt::Face_handle f) {
    return !cdt.is_infinite(f) && f->info().region >= 0 && inside[f->info().region];
  };
  // Vertices of inside faces: one on the bottom (z = 0) and one on top.
  std::unordered_map<Cdt::Vertex_handle, uint32_t> index;
  std::vector<Vec2> flat;
  const auto id = [&](Cdt::Vertex_handle v) {
    auto [it, added] = index.emplace(v, static_cast<uint32_t>(flat.size()));
    if (added) flat.emplace_back(v->point().x() * scale, v->point().y() * scale);
    return it->second;
  };
  std::vector<std::array<uint32_t, 3>> top;
  std::vector<std::array<uint32_t, 2>> rim;  // boundary edges, counter-clockwise about the region
  double area2 = 0.0;
  for (auto f : cdt.finite_face_handles()) {
    if (!is_in(f)) continue;
    top.push_back({id(f->vertex(0)), id(f->vertex(1)), id(f->vertex(2))});
    area2 += Area2(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    for (int i = 0; i < 3; ++i) {
      if (!is_in(f->neighbor(i))) {
        rim.push_back({id(f->vertex(Cdt::ccw(i))), id(f->vertex(Cdt::cw(i)))});
      }
    }
  }
  out.area = 0.5 * area2;
  const auto n = static_cast<uint32_t>(flat.size());
  const bool solid = depth > 0.0;
  out.positions.reserve(solid ? 2 * n : n);
  for (const Vec2& p : flat) out.positions.emplace_back(p.x(), p.y(), solid ? depth : 0.0);
  out.triangles = top;  // counter-clockwise seen from +z: facing up
  if (!solid) return out;
  for (const Vec2& p : flat) out.positions.emplace_back(p.x(), p.y(), 0.0);
  out.triangles.reserve(2 * top.size() + 2 * rim.size());
  for (const auto& t : top) out.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  // A wall under each boundary edge a -> b (the region on its left): its
  // outward normal points right of a -> b.
  for (const auto& [a, b] : rim) {
    out.triangles.push_back({a + n, b + n, b});
    out.triangles.push_back({a + n, b, a});
  }
  return out;
}

}  // namespace surfdeform
