// Stage 4 of the subdivision: the welded edge graph.
//
// Edges are matched by position, not by vertex index: vertices at one
// position are welded (to the smallest input index there), so a texture seam,
// whose two sides have their own vertices, still shares its edges' points
// and does not open a crack. Each face refers to its three edges and knows
// which way each runs; a face with two corners at one position is degenerate
// and is left as it is.
#pragma once

#include <array>
#include <vector>

#include "engine/common/mesh.hpp"
#include "engine/subdivision/ids.hpp"

namespace surfdeform::subdivision {

struct GraphEdge {
  WeldedId w0, w1;  // welded ends, w0 < w1; the edge's parameter t runs from w0 to w1
  VertexId v0, v1;  // an input vertex at each end (of the edge's first face)
  uint32_t faces_begin = 0, faces_end = 0;  // into EdgeGraph::edge_faces
};

struct GraphFace {
  std::array<VertexId, 3> corner{};
  std::array<EdgeId, 3> edge{};    // edge k joins corner k and corner k + 1
  std::array<bool, 3> reversed{};  // edge k's t runs from corner k + 1 to corner k
  bool degenerate = false;         // two corners at one position: no edges
};

struct EdgeGraph {
  IdVector<VertexId, WeldedId> weld;
  IdVector<EdgeId, GraphEdge> edges;  // grouped by w0, then by w1
  std::vector<FaceId> edge_faces;     // the faces of each edge, by face
  IdVector<FaceId, GraphFace> faces;  // one per input triangle

  // The faces of an edge: edge_faces[faces_begin .. faces_end).
  const FaceId* FacesBegin(EdgeId e) const { return edge_faces.data() + edges[e].faces_begin; }
  const FaceId* FacesEnd(EdgeId e) const { return edge_faces.data() + edges[e].faces_end; }
};

// Welds the mesh's vertices by exact position. O(n log n).
IdVector<VertexId, WeldedId> WeldByPosition(const std::vector<Vec3>& positions);

// The edge graph of `mesh`. Deterministic; O(n log n) in the triangles.
EdgeGraph BuildEdgeGraph(const Mesh& mesh);

}  // namespace surfdeform::subdivision
