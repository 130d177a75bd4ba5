#include "engine/subdivision/face_triangulation.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>

namespace surfdeform {
namespace {

int Next(int k) { return k == 2 ? 0 : k + 1; }
int Prev(int k) { return k == 0 ? 2 : k - 1; }

}  // namespace

FaceTriangulation::FaceTriangulation(const Vec2& a, const Vec2& b, const Vec2& c) {
  pts_ = {a, b, c};
  size_ = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  eps_len_ = 1e-9 * size_;
  const int t = NewTriangle(0, 1, 2);
  tris_[t].c = {true, true, true};
}

double FaceTriangulation::Orient(int a, int b, const Vec2& p) const {
  const Vec2 ab = pts_[b] - pts_[a];
  const double len = ab.norm();
  return len > 0.0 ? Cross2(ab, p - pts_[a]) / len : 0.0;
}

bool FaceTriangulation::InCircle(int t, const Vec2& p) const {
  const Triangle& tr = tris_[t];
  const Vec2 a = pts_[tr.v[0]] - p, b = pts_[tr.v[1]] - p, c = pts_[tr.v[2]] - p;
  const double a2 = a.squaredNorm(), b2 = b.squaredNorm(), c2 = c.squaredNorm();
  const double det = a2 * Cross2(b, c) + b2 * Cross2(c, a) + c2 * Cross2(a, b);
  const double mag =
      a2 * std::abs(Cross2(b, c)) + b2 * std::abs(Cross2(c, a)) + c2 * std::abs(Cross2(a, b));
  // Strictly inside, beyond rounding: cocircular points (a regular grid) never flip.
  return det > 1e-10 * mag;
}

void FaceTriangulation::Touch(int t) {
  tris_[t].stamp = ++clock_;
  touched_.push_back(t);
}

int FaceTriangulation::NewTriangle(int a, int b, int c) {
  Triangle t;
  t.v = {a, b, c};
  t.n = {-1, -1, -1};
  t.c = {false, false, false};
  tris_.push_back(t);
  const int id = static_cast<int>(tris_.size()) - 1;
  for (int v : t.v) {
    if (static_cast<size_t>(v) >= vtri_.size()) vtri_.resize(v + 1, -1);
    vtri_[v] = id;
  }
  Touch(id);
  return id;
}

int FaceTriangulation::EdgeIndex(int t, int a, int b) const {
  // A programmer invariant: callers pass an edge of t.
  const Triangle& tr = tris_[t];
  for (int k = 0; k < 2; ++k) {
    if (tr.v[Next(k)] == a && tr.v[Prev(k)] == b) return k;
  }
  assert(tr.v[0] == a && tr.v[1] == b);
  return 2;
}

void FaceTriangulation::Link(int t, int k, int u, int l) {
  tris_[t].n[k] = u;
  if (u >= 0) tris_[u].n[l] = t;
}

void FaceTriangulation::Around(int a, std::vector<int>* out) const {
  out->clear();
  const int t0 = vtri_[a];
  // Counter-clockwise around a; if the outline stops us, clockwise from t0.
  int t = t0;
  for (size_t guard = 0; guard <= tris_.size(); ++guard) {
    out->push_back(t);
    const Triangle& tr = tris_[t];
    const int i = tr.v[0] == a ? 0 : tr.v[1] == a ? 1 : 2;
    t = tr.n[Next(i)];
    if (t < 0 || t == t0) break;
  }
  if (t == t0) return;
  t = t0;
  for (size_t guard = 0; guard <= tris_.size(); ++guard) {
    const Triangle& tr = tris_[t];
    const int i = tr.v[0] == a ? 0 : tr.v[1] == a ? 1 : 2;
    t = tr.n[Prev(i)];
    if (t < 0) break;
    out->push_back(t);
  }
}

int FaceTriangulation::FindEdge(int a, int b, int* k) const {
  std::vector<int> around;
  Around(a, &around);
  for (int t : around) {
    const Triangle& tr = tris_[t];
    const int i = tr.v[0] == a ? 0 : tr.v[1] == a ? 1 : 2;
    if (tr.v[Next(i)] == b) {
      *k = Prev(i);
      return t;
    }
  }
  return -1;
}

int FaceTriangulation::Locate(const Vec2& p) const {
  int t = static_cast<int>(tris_.size()) - 1;
  for (size_t steps = 0; steps < 2 * tris_.size() + 8; ++steps) {
    const Triangle& tr = tris_[t];
    int next = -2;
    for (int k = 0; k < 3; ++k) {
      if (Orient(tr.v[Next(k)], tr.v[Prev(k)], p) < -eps_len_) {
        next = tr.n[k];
        break;
      }
    }
    if (next == -2) return t;
    if (next == -1) return -1;  // beyond a side of the (convex) face
    t = next;
  }
  // The walk can cycle in a constrained triangulation: scan.
  for (size_t u = 0; u < tris_.size(); ++u) {
    const Triangle& tr = tris_[u];
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      inside = Orient(tr.v[Next(k)], tr.v[Prev(k)], p) >= -eps_len_;
    }
    if (inside) return static_cast<int>(u);
  }
  return -1;
}

void FaceTriangulation::SplitTriangle(int t, int m) {
  const Triangle old = tris_[t];
  const int a = old.v[0], b = old.v[1], c = old.v[2];
  const int t1 = NewTriangle(b, c, m);
  const int t2 = NewTriangle(c, a, m);
  Triangle& tt = tris_[t];
  tt.v = {a, b, m};
  tt.c = {false, false, old.c[2]};
  tris_[t1].c = {false, false, old.c[0]};
  tris_[t2].c = {false, false, old.c[1]};
  vtri_[a] = t;
  vtri_[m] = t;
  Touch(t);
  Link(t, 0, t1, 1);   // b-m
  Link(t, 1, t2, 0);   // m-a
  Link(t1, 0, t2, 1);  // c-m
  tt.n[2] = old.n[2];  // a-b, unchanged neighbour
  if (old.n[0] >= 0) Link(t1, 2, old.n[0], EdgeIndex(old.n[0], c, b));
  if (old.n[1] >= 0) Link(t2, 2, old.n[1], EdgeIndex(old.n[1], a, c));
}

int FaceTriangulation::SplitEdge(int t, int k, const Vec2& p) {
  const int m = static_cast<int>(pts_.size());
  pts_.push_back(p);
  vtri_.resize(pts_.size(), -1);
  const Triangle ot = tris_[t];
  const int c = ot.v[k], a = ot.v[Next(k)], b = ot.v[Prev(k)];
  const int u = ot.n[k];
  const bool constrained = ot.c[k];
  const int t_ca = ot.n[Prev(k)];  // across c-a (opposite b)
  const int t_bc = ot.n[Next(k)];  // across b-c (opposite a)
  const bool c_ca = ot.c[Prev(k)], c_bc = ot.c[Next(k)];
  // t -> (c, a, m), t2 = (c, m, b).
  const int t2 = NewTriangle(c, m, b);
  tris_[t].v = {c, a, m};
  tris_[t].c = {constrained, false, c_ca};
  tris_[t2].c = {constrained, c_bc, false};
  vtri_[c] = t;
  vtri_[a] = t;
  vtri_[m] = t;
  Touch(t);
  Link(t, 1, t2, 2);  // m-c
  tris_[t].n[2] = t_ca;
  if (t_ca >= 0) Link(t, 2, t_ca, EdgeIndex(t_ca, a, c));
  if (t_bc >= 0) {
    Link(t2, 1, t_bc, EdgeIndex(t_bc, c, b));
  } else {
    tris_[t2].n[1] = -1;
  }
  if (u < 0) {
    tris_[t].n[0] = -1;
    tris_[t2].n[0] = -1;
    return m;
  }
  const Triangle ou = tris_[u];
  const int l = EdgeIndex(u, b, a);
  const int d = ou.v[l];
  const int u_ad = ou.n[Next(l)];  // u = (d, b, a): across a-d is opposite b = v[l+1]
  const int u_db = ou.n[Prev(l)];  // across d-b, opposite a = v[l+2]
  const bool c_ad = ou.c[Next(l)], c_db = ou.c[Prev(l)];
  // u -> (d, b, m), u2 = (d, m, a).
  const int u2 = NewTriangle(d, m, a);
  tris_[u].v = {d, b, m};
  tris_[u].c = {constrained, false, c_db};
  tris_[u2].c = {constrained, c_ad, false};
  vtri_[d] = u;
  vtri_[b] = u;
  Touch(u);
  Link(u, 1, u2, 2);  // m-d
  tris_[u].n[2] = u_db;
  if (u_db >= 0) Link(u, 2, u_db, EdgeIndex(u_db, b, d));
  if (u_ad >= 0) {
    Link(u2, 1, u_ad, EdgeIndex(u_ad, d, a));
  } else {
    tris_[u2].n[1] = -1;
  }
  Link(t, 0, u2, 0);  // a-m / m-a
  Link(t2, 0, u, 0);  // m-b / b-m
  return m;
}

void FaceTriangulation::Flip(int t, int k) {
  const Triangle ot = tris_[t];
  const int c = ot.v[k], a = ot.v[Next(k)], b = ot.v[Prev(k)];
  const int u = ot.n[k];
  const Triangle ou = tris_[u];
  const int l = EdgeIndex(u, b, a);
  const int d = ou.v[l];
  const int t_ca = ot.n[Prev(k)], t_bc = ot.n[Next(k)];
  const bool c_ca = ot.c[Prev(k)], c_bc = ot.c[Next(k)];
  const int u_ad = ou.n[Next(l)], u_db = ou.n[Prev(l)];
  const bool c_ad = ou.c[Next(l)], c_db = ou.c[Prev(l)];
  // t -> (c, a, d), u -> (d, b, c).
  tris_[t].v = {c, a, d};
  tris_[t].c = {c_ad, false, c_ca};
  tris_[u].v = {d, b, c};
  tris_[u].c = {c_bc, false, c_db};
  Touch(t);
  Touch(u);
  vtri_[c] = t;
  vtri_[a] = t;
  vtri_[d] = u;
  vtri_[b] = u;
  Link(t, 1, u, 1);  // d-c / c-d
  tris_[t].n[0] = -1;
  tris_[t].n[2] = -1;
  tris_[u].n[0] = -1;
  tris_[u].n[2] = -1;
  if (u_ad >= 0) Link(t, 0, u_ad, EdgeIndex(u_ad, d, a));
  if (t_ca >= 0) Link(t, 2, t_ca, EdgeIndex(t_ca, a, c));
  if (t_bc >= 0) Link(u, 0, t_bc, EdgeIndex(t_bc, c, b));
  if (u_db >= 0) Link(u, 2, u_db, EdgeIndex(u_db, b, d));
}

void FaceTriangulation::Legalize(std::vector<std::pair<int, int>>* stack) {
  // Lawson: each flip strictly raises the smallest angle, so this ends.
  size_t guard = 0;
  const size_t limit = 64 * tris_.size() + 1024;
  while (!stack->empty() && guard++ < limit) {
    const auto [t, k] = stack->back();
    stack->pop_back();
    const Triangle& tr = tris_[t];
    const int u = tr.n[k];
    if (u < 0 || tr.c[k]) continue;
    const int l = EdgeIndex(u, tr.v[Prev(k)], tr.v[Next(k)]);
    const int d = tris_[u].v[l];
    if (!InCircle(t, pts_[d])) continue;
    // Only a convex quadrilateral can be flipped (always the case when d is
    // inside t's circumcircle, up to rounding).
    const int c = tr.v[k], a = tr.v[Next(k)], b = tr.v[Prev(k)];
    if (!(Orient(c, d, pts_[a]) < -eps_len_ && Orient(c, d, pts_[b]) > eps_len_)) continue;
    Flip(t, k);
    stack->push_back({t, 0});
    stack->push_back({t, 2});
    stack->push_back({u, 0});
    stack->push_back({u, 2});
  }
  stack->clear();
}

void FaceTriangulation::LegalizeAround(int p) {
  std::vector<int> around;
  Around(p, &around);
  std::vector<std::pair<int, int>> stack;
  for (int t : around) {
    const Triangle& tr = tris_[t];
    stack.push_back({t, tr.v[0] == p ? 0 : tr.v[1] == p ? 1 : 2});
  }
  Legalize(&stack);
}

int FaceTriangulation::SplitBoundary(int from, int to, const Vec2& p) {
  int k = -1;
  const int t = FindEdge(from, to, &k);
  if (t < 0 || tris_[t].n[k] >= 0) return -1;
  const int m = SplitEdge(t, k, p);
  LegalizeAround(m);
  return m;
}

int FaceTriangulation::Insert(const Vec2& p) {
  const int t = Locate(p);
  if (t < 0) return -1;
  const Triangle& tr = tris_[t];
  for (int v : tr.v) {
    if ((pts_[v] - p).norm() <= eps_len_) return v;
  }
  for (int k = 0; k < 3; ++k) {
    if (Orient(tr.v[Next(k)], tr.v[Prev(k)], p) <= eps_len_) {
      if (tr.n[k] < 0) return -1;  // on the outline: sides are fixed
      const int m = SplitEdge(t, k, p);
      LegalizeAround(m);
      return m;
    }
  }
  const int m = static_cast<int>(pts_.size());
  pts_.push_back(p);
  vtri_.resize(pts_.size(), -1);
  SplitTriangle(t, m);
  LegalizeAround(m);
  return m;
}

int FaceTriangulation::SplitInteriorEdge(int t, int k) {
  const Triangle& tr = tris_[t];
  if (tr.n[k] < 0) return -1;
  const Vec2 mid = 0.5 * (pts_[tr.v[Next(k)]] + pts_[tr.v[Prev(k)]]);
  const int m = SplitEdge(t, k, mid);
  LegalizeAround(m);
  return m;
}

bool FaceTriangulation::Crosses(int a, int b, int p, int q) const {
  const double op = Orient(a, b, pts_[p]), oq = Orient(a, b, pts_[q]);
  if (!((op < -eps_len_ && oq > eps_len_) || (op > eps_len_ && oq < -eps_len_))) return false;
  const double oa = Orient(p, q, pts_[a]), ob = Orient(p, q, pts_[b]);
  return (oa < -eps_len_ && ob > eps_len_) || (oa > eps_len_ && ob < -eps_len_);
}

// 84 lines, on purpose: its three phases (the wedge at a that holds the
// direction to b, the march to b collecting the crossed edges, Sloan's flips)
// share the crossing list and the on-segment splits, which recurse into
// Constrain; apart, each would take and return that state.
bool FaceTriangulation::Constrain(int a, int b) {
  if (a == b) return true;
  auto mark = [this](int t, int k) {
    tris_[t].c[k] = true;
    const int u = tris_[t].n[k];
    if (u >= 0) tris_[u].c[EdgeIndex(u, tris_[t].v[Prev(k)], tris_[t].v[Next(k)])] = true;
  };
  int k = -1;
  if (int t = FindEdge(a, b, &k); t >= 0) {
    mark(t, k);
    return true;
  }
  const Vec2 pa = pts_[a], ab = pts_[b] - pa;
  const double len2 = ab.squaredNorm();
  // A point strictly between a and b on the segment splits it.
  auto on_segment = [&](int p) {
    if (p == a || p == b || std::abs(Orient(a, b, pts_[p])) > eps_len_) return false;
    const double w = (pts_[p] - pa).dot(ab) / len2;
    return w > 0.0 && w < 1.0;
  };
  // The triangle around a that the segment leaves through, and the edge it crosses.
  std::deque<std::pair<int, int>> crossing;
  int p = -1, q = -1, t = -1;
  std::vector<int> around;
  Around(a, &around);
  for (int u : around) {
    const Triangle& tr = tris_[u];
    const int i = tr.v[0] == a ? 0 : tr.v[1] == a ? 1 : 2;
    const int x = tr.v[Next(i)], y = tr.v[Prev(i)];
    if (on_segment(x)) return Constrain(a, x) && Constrain(x, b);
    if (on_segment(y)) return Constrain(a, y) && Constrain(y, b);
    // The wedge at a that holds the direction to b: x to its right, y to its
    // left (a wedge behind a has them the other way round).
    if (t < 0 && Orient(a, b, pts_[x]) < -eps_len_ && Orient(a, b, pts_[y]) > eps_len_) {
      t = u;
      p = x;
      q = y;
    }
  }
  if (t < 0) return false;
  // March to b, collecting the crossed edges (p right of a->b, q left).
  for (size_t guard = 0; guard <= tris_.size(); ++guard) {
    int kk = -1;
    const int cur = FindEdge(p, q, &kk);
    if (cur < 0 || tris_[cur].c[kk]) return false;  // crosses a constraint or a side
    crossing.push_back({p, q});
    const int u = tris_[cur].n[kk];
    const int r = tris_[u].v[EdgeIndex(u, q, p)];
    if (r == b) break;
    if (on_segment(r)) return Constrain(a, r) && Constrain(r, b);
    if (Orient(a, b, pts_[r]) < 0.0) {
      p = r;
    } else {
      q = r;
    }
  }
  // Sloan: flip crossing edges whose quadrilateral is convex until none cross.
  size_t guard = 0;
  const size_t limit = 16 * (crossing.size() + 1) * (crossing.size() + 1) + 1024;
  while (!crossing.empty()) {
    if (++guard > limit) return false;
    if (guard % 64 == 0 && stop_ && stop_()) return false;
    const auto [x, y] = crossing.front();
    crossing.pop_front();
    int kk = -1;
    const int cur = FindEdge(x, y, &kk);
    if (cur < 0) continue;
    const Triangle& tr = tris_[cur];
    const int u = tr.n[kk];
    if (u < 0 || tr.c[kk]) return false;
    const int c = tr.v[kk];
    const int d = tris_[u].v[EdgeIndex(u, y, x)];
    const bool convex = Orient(c, d, pts_[x]) < -eps_len_ && Orient(c, d, pts_[y]) > eps_len_;
    if (!convex) {
      crossing.push_back({x, y});
      continue;
    }
    Flip(cur, kk);
    if (Crosses(a, b, c, d)) crossing.push_back({c, d});
  }
  if (int tt = FindEdge(a, b, &k); tt >= 0) {
    mark(tt, k);
    return true;
  }
  return false;
}

void FaceTriangulation::RestoreDelaunay() {
  std::vector<std::pair<int, int>> stack;
  for (size_t t = 0; t < tris_.size(); ++t) {
    for (int k = 0; k < 3; ++k) stack.push_back({static_cast<int>(t), k});
  }
  Legalize(&stack);
}

}  // namespace surfdeform
