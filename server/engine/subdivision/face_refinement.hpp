// Stage 7 of the subdivision: each face's final triangles.
//
// A face with no point on its sides and no kept face point stays as it is
// when its estimate, or its centroid's measured deviation, is within the
// tolerance. Otherwise it is re-triangulated from its kept points
// (face_retriangulation.hpp), and with a tolerance refined: the triangle that
// strays most (triangle_deviation.hpp) has its interior edge split that
// strays most at its middle (or its longest, when the deviation is inside;
// a triangle that is the whole face gets its centroid), until every triangle
// is within kFaceShare of the tolerance, or a split cannot help (a piece
// 1e-6 of the face's size, a sliver beside a side that strays itself), or
// the budget is spent.
#pragma once

#include <array>
#include <vector>

#include "engine/subdivision/face_retriangulation.hpp"

namespace surfdeform::subdivision {

struct FaceOutput {
  std::vector<std::array<int, 3>> triangles;  // local ids (0-2 corners); empty: as it is
  std::vector<LocalPoint> points;             // local ids 3, 4, ...
  size_t face_points_kept = 0;
  Tally tally;
  bool failed = false;  // an invariant of the triangulation broke (a bug)
};

// Every face, in parallel; stops early once `budget` is out of time.
IdVector<FaceId, FaceOutput> RefineFaces(const FaceStageInputs& in, Budget* budget);

// One face.
FaceOutput RefineFace(const FaceStageInputs& in, FaceId f, Budget* budget, int* hint);

}  // namespace surfdeform::subdivision
