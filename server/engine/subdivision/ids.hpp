// Typed ids for the subdivision's stages, where several kinds of id meet.
//
// An input vertex, a welded vertex (a position: the smallest input vertex
// there), an edge of the welded graph and a face (an input triangle) are all
// small integers; giving each its own type makes the compiler reject an edge
// id used as a face id. Modelled on Draco's IndexType. Cells and sides of the
// flat grid get one small index type, `CellGrid`, that owns their numbering.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace surfdeform::subdivision {

template <typename Tag>
class StrongId {
 public:
  constexpr StrongId() = default;
  constexpr explicit StrongId(uint32_t value) : value_(value) {}
  constexpr explicit StrongId(size_t value) : value_(static_cast<uint32_t>(value)) {}
  constexpr explicit StrongId(int value) : value_(static_cast<uint32_t>(value)) {}
  constexpr uint32_t value() const { return value_; }
  constexpr auto operator<=>(const StrongId&) const = default;

 private:
  uint32_t value_ = 0;
};

using VertexId = StrongId<struct VertexTag>;  // an input vertex, in the input's order
using WeldedId = StrongId<struct WeldedTag>;  // a position: the smallest input vertex there
using EdgeId = StrongId<struct EdgeTag>;      // an edge of the welded graph
using FaceId = StrongId<struct FaceTag>;      // an input triangle

// A vector indexed by one kind of id only.
template <typename Id, typename T>
class IdVector {
 public:
  IdVector() = default;
  explicit IdVector(size_t n, const T& value = T()) : items_(n, value) {}

  T& operator[](Id id) { return items_[id.value()]; }
  const T& operator[](Id id) const { return items_[id.value()]; }
  size_t size() const { return items_.size(); }
  bool empty() const { return items_.empty(); }
  void resize(size_t n) { items_.resize(n); }
  void assign(size_t n, const T& value) { items_.assign(n, value); }
  void reserve(size_t n) { items_.reserve(n); }
  template <typename... Args>
  T& emplace_back(Args&&... args) {
    return items_.emplace_back(std::forward<Args>(args)...);
  }
  auto begin() { return items_.begin(); }
  auto end() { return items_.end(); }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }
  std::vector<T>& raw() { return items_; }
  const std::vector<T>& raw() const { return items_; }

 private:
  std::vector<T> items_;
};

// A node or a cell of the flat grid by its two indices.
struct GridIndex {
  int i = 0;
  int j = 0;
};

// The numbering of the cells and the sides of an nu x nv grid of nodes, in
// one place. Cell (i, j) is i + (nu - 1) j (FlatLocator's). Sides: the side
// along u from node (i, j) to (i + 1, j) is i + (nu - 1) j; the side along v
// from node (i, j) to (i, j + 1) is (nu - 1) nv + i + nu j.
class CellGrid {
 public:
  CellGrid(int nu, int nv) : nu_(nu), nv_(nv) {}

  int cells_u() const { return nu_ - 1; }
  int cells_v() const { return nv_ - 1; }
  int cell_count() const { return (nu_ - 1) * (nv_ - 1); }
  int Cell(int i, int j) const { return i + (nu_ - 1) * j; }
  GridIndex CellAt(int cell) const { return {cell % (nu_ - 1), cell / (nu_ - 1)}; }
  bool HasCell(int i, int j) const { return i >= 0 && i < nu_ - 1 && j >= 0 && j < nv_ - 1; }

  int Node(int i, int j) const { return i + nu_ * j; }
  GridIndex NodeAt(int node) const { return {node % nu_, node / nu_}; }
  int node_count() const { return nu_ * nv_; }

  int SideAlongU(int i, int j) const { return i + (nu_ - 1) * j; }
  int SideAlongV(int i, int j) const { return (nu_ - 1) * nv_ + i + nu_ * j; }
  int side_count() const { return (nu_ - 1) * nv_ + nu_ * (nv_ - 1); }
  struct Side {
    bool along_u;
    GridIndex from;  // the node it starts at; it ends at from + (1, 0) or (0, 1)
  };
  Side SideAt(int side) const {
    const int u_sides = (nu_ - 1) * nv_;
    if (side < u_sides) return {true, {side % (nu_ - 1), side / (nu_ - 1)}};
    return {false, {(side - u_sides) % nu_, (side - u_sides) / nu_}};
  }

 private:
  int nu_, nv_;
};

}  // namespace surfdeform::subdivision
