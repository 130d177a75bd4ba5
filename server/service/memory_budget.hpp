// What a request's work takes in memory, estimated from its counts before
// the work, against the per-request budget (ServiceLimits::
// request_memory_bytes). The bytes per unit were measured with VmHWM on
// single requests to a fresh Release server (BENCHMARKS.md, "Hostile
// input"), rounded up.
#pragma once

#include <cstddef>
#include <string>

#include "base/status.hpp"

namespace surfdeform {

// A sampled and flattened grid, per sample (measured 2.1 KB at 128^2 and
// 256^2, range 3; ranges 1 and 2 take about as much).
inline constexpr double kSheetBytesPerSample = 2560;
// A point of the distance lattice while the distances are measured (the
// position, derivatives and normal: sizeof(LatticePoint), 192 B), and a
// point of a path kept for the next edit (a Vec2).
inline constexpr double kLatticeBytesPerPoint = 208;
inline constexpr double kPathBytesPerPoint = 16;
// Each distance pair a sample has past range 3's 24 (2r(r + 1) within range
// r): measured 79 B (256^2 at range 5 and 8: 5.25 and 11.9 KB a sample).
inline constexpr double kSheetBytesPerExtraPair = 96;
// An animation's sheets and maps, per frame and sample (measured 430 B,
// 600 frames of 32^2).
inline constexpr double kAnimationBytesPerFrameSample = 512;
// The same for a surface closed in u (a whole cylinder or cone), whose every
// frame's map is continued past the seam (three periods of columns and their
// locator, beside the given sheet's): measured 1.1 KB, 600 frames of 32^2.
// Continued past both seams (a whole torus), three times that (nine
// copies; an estimate, scaled from the measure).
inline constexpr double kClosedAnimationBytesPerFrameSample = 1536;
// And per pair past range 3, per frame and sample: the anchors' kept paths
// (measured 2.5 B: 200 frames of 64^2, 330 B a frame-sample at range 3, 624 B
// at range 8).
inline constexpr double kAnimationBytesPerFrameExtraPair = 3;
// A subdivided, deformed and encoded mesh, per output vertex (measured
// 372 B at 789k and 377 B at 1.61M vertices, OBJ out: the bunny refined on a
// short wave; Draco 310-344 B, GLB 296 B, PLY 330 B).
inline constexpr double kSubdivisionBytesPerVertex = 384;
// A crossing of a model's edge with a grid line (or a mesh surface's edge),
// kept to be measured and marked: 64 B (the crossing, its curvature and
// kink), doubled for what measuring it takes.
inline constexpr double kSubdivisionBytesPerCrossing = 128;
// An animation's refinement passes over the refined model, per vertex of it
// and per frame measured at once (one a thread): the edge graph, the grid's
// marks, the refined edges and faces and their assembly of a whole
// subdivision whose input is the refined model (measured 924 B at 290k
// vertices: 125 + 280 + 235 + 187 + 97; 1.2 KB at 80k), rounded up.
inline constexpr double kSubdivisionPassBytesPerVertex = 1280;
// An animation's model, per frame and vertex after the subdivision: the
// positions the refinement keeps for every frame, the frames' deformed
// vertices and their share of the GLB (measured 230 B: the bunny refined to
// 431k and 449k vertices at 2 and 4 frames; 74 B for 100 frames of a label
// refined to 24.8k vertices, less the sheets), rounded up.
inline constexpr double kAnimationBytesPerFrameVertex = 256;
// A surface given as a mesh: per vertex, the conformal start (measured
// 3.8 KB at 90.6k and 194k vertices: what is taken before the pairs are
// listed), and per vertex pair within max(range, 3) rings, the pairs, their
// distances and the solve (106 B at range 3, 1.63M pairs; 194 B at range 5,
// 4.08M pairs), both rounded up.
inline constexpr double kMeshSheetBytesPerVertex = 4096;
inline constexpr double kMeshSheetBytesPerPair = 224;
// An animation whose keyframes are meshes, per frame and mesh vertex: the
// frame's flat mesh (its vertices, triangles, neighbours, flat positions
// and normals) and its surface's triangle index, kept for every frame
// (measured 275 B: 20 and 60 frames of a 10.2k-vertex mesh, 32 x 32).
inline constexpr double kMeshAnimationBytesPerFrameVertex = 320;
// A keyframe that is a mesh, per vertex: its positions as the
// interpolation's numbers (3 doubles), all keys' kept while the frames are
// flattened. Counted, not measured: keys of one uploaded mesh cost a request
// some 70 bytes each, and each brings its mesh's vertices.
inline constexpr double kMeshKeyBytesPerVertex = 24;
// A resampled polyline's point: the marks and the JSON reply built from
// them (measured 2.06 KB at 262k points; 170 B of it the reply's text).
inline constexpr double kMapBytesPerOutputPoint = 2048;

// A part, per triangle: the body, its checks (CGAL's halfedge mesh and
// AABB boxes for the self-intersection test) and its file (measured 225 B
// and 230 B: a whole torus's body at 512^2 and 256^2 samples, 3MF out),
// rounded up.
inline constexpr double kPartBytesPerTriangle = 256;

// Distance pairs per sample past range 3's (0 up to range 3).
double ExtraPairsPerSample(int range);

// kLimitExceeded naming `field` when `bytes` (the estimate for `what`) is
// over `budget`.
Status CheckMemory(double bytes, size_t budget, const std::string& what, const std::string& field);

// The largest count of units of `bytes_per_unit` that fit `budget`, at most
// `limit`.
size_t CountWithin(size_t budget, double bytes_per_unit, size_t limit);

}  // namespace surfdeform
