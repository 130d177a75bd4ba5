// Animated surfaces: keyframe validation and interpolation, the warm-started
// sequence of sheets, and a model deformed through every frame.
#include "engine/animation/animation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/deform/deform.hpp"
#include "support/surface_file.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"

namespace surfdeform {
namespace {

constexpr double kPi = std::numbers::pi;

BezierSpec Figure10(double height_scale) {
  BezierSpec b = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  for (Vec3& p : b.control_points) p.z() *= height_scale;
  return b;
}

AnimationSpec Pair(const SurfaceSpec& a, const SurfaceSpec& b, int frames) {
  AnimationSpec s;
  s.keyframes = {{0.0, a}, {1.0, b}};
  s.frames = frames;
  return s;
}

TEST(Animation, KeyframesThatDoNotMatchNameTheKeyAndTheField) {
  BezierSpec cubic = Figure10(1.0);
  BezierSpec quadratic;
  quadratic.degree_u = quadratic.degree_v = 2;
  quadratic.control_points.assign(9, Vec3::Zero());
  Status s = ValidateAnimation(Pair(cubic, quadratic, 10), 100);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(s.field(), "keyframes[1].surface.degree_u");

  s = ValidateAnimation(Pair(cubic, CylinderSpec{}, 10), 100);
  EXPECT_EQ(s.field(), "keyframes[1].surface.kind");

  BezierSpec bad = cubic;
  bad.control_points[5].y() = std::numeric_limits<double>::infinity();
  s = ValidateAnimation(Pair(cubic, bad, 10), 100);
  EXPECT_EQ(s.field(), "keyframes[1].surface.control_points[5][1]");

  AnimationSpec late = Pair(cubic, cubic, 10);
  late.keyframes[1].time = 0.0;
  EXPECT_EQ(ValidateAnimation(late, 100).field(), "keyframes[1].time");

  s = ValidateAnimation(Pair(cubic, cubic, 101), 100);
  EXPECT_EQ(s.code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(s.field(), "frames");
  EXPECT_EQ(s.limit(), 100);

  AnimationSpec single;
  single.keyframes = {{0.0, cubic}};
  EXPECT_EQ(ValidateAnimation(single, 100).field(), "keyframes");
  single.keyframes = {{0.0, WaveSpec{}}};
  EXPECT_TRUE(ValidateAnimation(single, 100).ok());
}

TEST(Animation, FramesSpanTheKeysAndHitThemExactly) {
  const CylinderSpec a{1.0, 2.0, 180.0, {}}, b{3.0, 2.0, 180.0, {}};
  AnimationSpec spec = Pair(a, b, 5);
  spec.keyframes[1].time = 2.0;
  EXPECT_DOUBLE_EQ(FrameTime(spec, 0), 0.0);
  EXPECT_DOUBLE_EQ(FrameTime(spec, 2), 1.0);
  EXPECT_DOUBLE_EQ(FrameTime(spec, 4), 2.0);
  // Two keys: cubic Catmull-Rom is the straight line.
  EXPECT_NEAR(std::get<CylinderSpec>(SurfaceAtFrame(spec, 1)).radius, 1.5, 1e-12);
  EXPECT_EQ(std::get<CylinderSpec>(SurfaceAtFrame(spec, 4)).radius, 3.0);
  // Three keys: C1 through the middle one, and through the keys exactly.
  spec.keyframes.push_back({3.0, CylinderSpec{1.0, 2.0, 180.0, {}}});
  spec.frames = 31;
  // Frames every 0.1 time units over [0, 3].
  auto radius = [&](double t) {
    const int frame = static_cast<int>(std::lround(t * 10));
    return std::get<CylinderSpec>(SurfaceAtFrame(spec, frame)).radius;
  };
  EXPECT_EQ(radius(2.0), 3.0);
  EXPECT_EQ(radius(0.0), 1.0);
  // Catmull-Rom slope at the middle key: (1 - 1) / (3 - 0) = 0, so it peaks there.
  EXPECT_LT(radius(1.9), 3.0);
  EXPECT_LT(radius(2.1), 3.0);
  // Slope 0 at the key: the one-sided differences are second order there
  // (straight lines would give +1 and -2).
  const double left = (radius(2.0) - radius(1.9)) / 0.1, right = (radius(2.1) - radius(2.0)) / 0.1;
  EXPECT_NEAR(left, 0.0, 0.15);
  EXPECT_NEAR(right, 0.0, 0.45);
  spec.interpolation = Interpolation::kLinear;
  EXPECT_NEAR(radius(1.0), 2.0, 1e-12);

  AnimationSpec wave;
  wave.keyframes = {{0.0, WaveSpec{}}};
  wave.fps = 25;
  wave.frames = 10;
  EXPECT_NEAR(std::get<WaveSpec>(SurfaceAtFrame(wave, 5)).time, 0.2, 1e-15);
}

TEST(Animation, WarmStartsSaveIterationsAtTheSameStress) {
  AnimationSpec spec = Pair(Figure10(0.5), Figure10(1.0), 8);
  FlattenOptions o;
  auto sheets = FlattenAnimation(spec, {16, 16}, o);
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  ASSERT_EQ(sheets->sheets.size(), 8u);
  int warm = 0, cold = 0;
  for (int k = 1; k < spec.frames; ++k) {
    // The last frame is on the last key: it starts cold, as the key alone.
    EXPECT_EQ(sheets->frames[k].warm, k < spec.frames - 1) << k;
    auto surface = MakeSurface(SurfaceAtFrame(spec, k));
    auto alone = FlattenSurface(**surface, {16, 16}, o);
    ASSERT_TRUE(alone.ok());
    EXPECT_NEAR(sheets->frames[k].quality.stress, alone->quality.stress,
                1e-6 * alone->quality.stress)
        << k;
    if (sheets->frames[k].warm) {
      warm += sheets->frames[k].quality.iterations;
      cold += alone->quality.iterations;
    }
    // One canonical frame: sample 0 at the origin, the first edge along +X.
    EXPECT_LT(sheets->sheets[k].flat[0].norm(), 1e-12);
    EXPECT_LT(std::abs(sheets->sheets[k].flat[1].y()), 1e-12);
    // And it moves little between frames: no jump, no spin.
    double moved = 0.0;
    for (size_t i = 0; i < sheets->sheets[k].flat.size(); ++i) {
      moved = std::max(moved, (sheets->sheets[k].flat[i] - sheets->sheets[k - 1].flat[i]).norm());
    }
    EXPECT_LT(moved, 0.5) << k;
  }
  EXPECT_LT(warm, cold);
}

// Frames between anchors are measured along the anchors' paths (no
// relaxation), and flatten to the stress of the frame alone all the same.
TEST(Animation, FramesBetweenAnchorsReuseTheirPathsAtTheSameStress) {
  AnimationSpec spec = Pair(Figure10(0.5), Figure10(1.0), 2 * kPathAnchorEvery + 3);
  auto sheets = FlattenAnimation(spec, {16, 16}, FlattenOptions{});
  ASSERT_TRUE(sheets.ok()) << sheets.status().ToString();
  for (int k = 0; k < spec.frames; ++k) {
    const bool anchor = k % kPathAnchorEvery == 0 || k == spec.frames - 1;
    if (anchor) {
      EXPECT_EQ(sheets->frames[k].reused_paths, 0) << k;
    } else {
      EXPECT_GT(sheets->frames[k].reused_paths, 1000) << k;
    }
    auto surface = MakeSurface(SurfaceAtFrame(spec, k));
    auto alone = FlattenSurface(**surface, {16, 16}, {});
    ASSERT_TRUE(alone.ok());
    EXPECT_NEAR(sheets->frames[k].quality.stress, alone->quality.stress,
                1e-6 * alone->quality.stress)
        << k;
  }
}

// Which frames are anchors, and so every sheet, depends on the spec alone:
// one thread (measuring and solving in turn) and three (two measuring ahead
// while the third solves, measuring too when it would wait) give the same
// sheets, bit for bit.
TEST(Animation, SheetsDoNotDependOnTheThreadCount) {
  AnimationSpec spec = Pair(Figure10(0.5), Figure10(1.0), 3 * kPathAnchorEvery + 2);
  FlattenOptions one, three;
  one.threads = 1;
  three.threads = 3;
  auto a = FlattenAnimation(spec, {12, 12}, one);
  auto b = FlattenAnimation(spec, {12, 12}, three);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a->sheets.size(), b->sheets.size());
  for (size_t k = 0; k < a->sheets.size(); ++k) {
    EXPECT_EQ(a->frames[k].reused_paths, b->frames[k].reused_paths) << k;
    EXPECT_EQ(a->frames[k].quality.iterations, b->frames[k].quality.iterations) << k;
    ASSERT_EQ(a->sheets[k].flat.size(), b->sheets[k].flat.size());
    for (size_t i = 0; i < a->sheets[k].flat.size(); ++i) {
      EXPECT_EQ(a->sheets[k].flat[i], b->sheets[k].flat[i]) << k << " " << i;
    }
  }
}

// A frame that cannot be flattened ends the sequence with its own error,
// whichever thread measured it, and the threads still measuring ahead stop.
TEST(Animation, AFrameThatFailsStopsTheSequenceWithItsError) {
  // A flat patch mirrored across the x axis: halfway, every control point is
  // on the axis, and the surface collapses onto it (no normal anywhere).
  BezierSpec start = Figure10(0.0), mirrored = Figure10(0.0);
  for (Vec3& p : mirrored.control_points) p.y() = -p.y();
  AnimationSpec spec = Pair(start, mirrored, 2 * kPathAnchorEvery + 3);
  spec.interpolation = Interpolation::kLinear;
  const int halfway = spec.frames / 2;
  ASSERT_NE(halfway % kPathAnchorEvery, 0);  // a frame between anchors
  for (int threads : {1, 3}) {
    FlattenOptions o;
    o.threads = threads;
    auto sheets = FlattenAnimation(spec, {12, 12}, o);
    ASSERT_FALSE(sheets.ok()) << threads;
    EXPECT_EQ(sheets.status().code(), ErrorCode::kDegenerate) << sheets.status().ToString();
    EXPECT_EQ(sheets.status().message().rfind("frame " + std::to_string(halfway) + " ", 0), 0u)
        << sheets.status().ToString();
  }
}

TEST(Animation, ANumberTheSameOnTheKeysIsExactlyThatOnEveryFrame) {
  // A can whose radius grows: its angle stays 360 on all 600 frames (the
  // cubic's rounding gave 360.00000000000006 on some, which a cylinder
  // refuses), and the radius stays between its keys.
  AnimationSpec spec =
      Pair(CylinderSpec{2.0, 3.0, 360.0, {}}, CylinderSpec{3.0, 3.0, 360.0, {}}, 600);
  spec.keyframes.push_back({2.0, CylinderSpec{2.5, 3.0, 360.0, {}}});
  ASSERT_TRUE(ValidateAnimation(spec, 1000).ok());
  for (int k = 0; k < spec.frames; ++k) {
    const CylinderSpec c = std::get<CylinderSpec>(SurfaceAtFrame(spec, k));
    ASSERT_EQ(c.angle_deg, 360.0) << "frame " << k;
    ASSERT_EQ(c.height, 3.0) << "frame " << k;
  }
}

TEST(Animation, ATimeBudgetStopsTheSequence) {
  AnimationSpec spec = Pair(Figure10(0.5), Figure10(1.0), 6 * kPathAnchorEvery);
  for (int threads : {1, 3}) {
    FlattenOptions o;
    o.threads = threads;
    o.time_budget_ms = 2.0;
    auto sheets = FlattenAnimation(spec, {24, 24}, o);
    ASSERT_FALSE(sheets.ok()) << threads;
    EXPECT_EQ(sheets.status().code(), ErrorCode::kDeadlineExceeded) << sheets.status().ToString();
  }
}

// The model placed on every frame's sheet and mapped through every frame.
struct Animated {
  AnimatedSheets sheets;
  std::vector<SheetMap> maps;
  PreparedModel model;
};

Animated Animate(const AnimationSpec& spec, int n, const FlattenOptions& f, Mesh mesh,
                 const PlacementOptions& placement, const SubdivisionOptions& subdivision) {
  Animated a;
  auto sheets = FlattenAnimation(spec, {n, n}, f);
  EXPECT_TRUE(sheets.ok()) << sheets.status().ToString();
  a.sheets = std::move(*sheets);
  a.maps.reserve(a.sheets.sheets.size());
  std::vector<const SheetMap*> maps;
  for (size_t k = 0; k < a.sheets.sheets.size(); ++k) {
    a.maps.emplace_back(*a.sheets.surfaces[k], a.sheets.sheets[k]);
  }
  for (const SheetMap& m : a.maps) maps.push_back(&m);
  auto model =
      PrepareModel(maps, std::move(mesh), {.placement = placement, .subdivision = subdivision});
  EXPECT_TRUE(model.ok()) << model.status().ToString();
  a.model = std::move(*model);
  return a;
}

Mesh Frame(const Animated& a, size_t k, const PlacementOptions& placement) {
  auto r = DeformPrepared(a.maps[k], a.model, k, {.placement = placement});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r->mesh) : Mesh{};
}

TEST(Animation, TheEndFramesEqualDeformationsOnTheStaticKeys) {
  // Frames on a key are flattened from the key alone: bit for bit the
  // static flattening.
  const FlattenOptions f;
  const BezierSpec first = Figure10(0.6), last = Figure10(1.0);
  const AnimationSpec spec = Pair(first, last, 6);
  const Mesh plate = testing::FlatGrid(-2.0, -1.5, 4.0, 3.0, 24, 18, 0.1);
  const PlacementOptions placement = testing::KeepCoordinates(plate, Vec2(5.0, 4.5));
  SubdivisionOptions off;
  off.mode = SubdivisionMode::kOff;
  const Animated a = Animate(spec, 16, f, plate, placement, off);
  const Mesh frame_first = Frame(a, 0, placement);
  const Mesh frame_last = Frame(a, 5, placement);
  double apart = 0.0;
  for (const auto& [k, spec_k] :
       {std::pair{0, SurfaceSpec(first)}, std::pair{5, SurfaceSpec(last)}}) {
    testing::Target t;
    t.surface = testing::MakeValid(spec_k);
    auto sheet = FlattenSurface(*t.surface, {16, 16}, f);
    ASSERT_TRUE(sheet.ok()) << sheet.status().ToString();
    t.sheet = std::move(*sheet);
    auto alone = Deform(SheetMap(*t.surface, t.sheet), plate, {.placement = placement});
    ASSERT_TRUE(alone.ok()) << alone.status().ToString();
    const Mesh& frame = k == 0 ? frame_first : frame_last;
    double worst = 0.0;
    for (size_t v = 0; v < plate.positions.size(); ++v) {
      worst = std::max(worst, (frame.positions[v] - alone->mesh.positions[v]).norm());
      worst = std::max(worst, (frame.normals[v] - alone->mesh.normals[v]).norm());
    }
    EXPECT_LT(worst, 1e-9) << "frame " << k;
  }
  for (size_t v = 0; v < plate.positions.size(); ++v) {
    apart = std::max(apart, (frame_first.positions[v] - frame_last.positions[v]).norm());
  }
  EXPECT_GT(apart, 0.1);  // the two ends are different shapes
}

// Figure 10 at `height_scale`, its control net shrunk in x and y by `shrink`.
BezierSpec Shrunk(double height_scale, double shrink) {
  BezierSpec b = Figure10(height_scale);
  for (Vec3& p : b.control_points) p.head<2>() *= shrink;
  return b;
}

// The model deformed on `spec` alone (its own flattening at n x n), as
// POST /v1/deform would.
Mesh Static(const SurfaceSpec& spec, int n, const Mesh& model, const PlacementOptions& placement,
            const SubdivisionOptions& subdivision) {
  testing::Target t;
  t.surface = testing::MakeValid(spec);
  auto sheet = FlattenSurface(*t.surface, {n, n}, {});
  EXPECT_TRUE(sheet.ok()) << sheet.status().ToString();
  if (!sheet.ok()) return {};
  t.sheet = std::move(*sheet);
  auto r = Deform(SheetMap(*t.surface, t.sheet), Mesh(model),
                  {.placement = placement, .subdivision = subdivision});
  EXPECT_TRUE(r.ok()) << r.status().ToString();
  return r.ok() ? std::move(r->mesh) : Mesh{};
}

// Centred where the API's default "center" puts it: the image of the
// surface point (1/2, 1/2); `scale` 0 fits.
PlacementOptions AtTheSheetCentre(double scale) {
  PlacementOptions placement;
  placement.center_mode = CenterMode::kSheetCenter;
  placement.fit = scale == 0.0;
  placement.scale = scale == 0.0 ? 1.0 : scale;
  return placement;
}

double Apart(const Mesh& a, const Mesh& b, size_t n) {
  double worst = 0.0;
  for (size_t v = 0; v < n; ++v) worst = std::max(worst, (a.positions[v] - b.positions[v]).norm());
  return worst;
}

TEST(Animation, TheSheetCentreFollowsTheSurfaceAndTheKeysAreTheStaticDeformations) {
  // A pair whose sheet shrinks, moves and turns under the model: the image
  // of (u, v) = (1/2, 1/2) is elsewhere on the last sheet than on the first.
  const BezierSpec first = Shrunk(0.3, 1.0), last = Shrunk(1.2, 0.8);
  const AnimationSpec spec = Pair(first, last, 7);
  const Mesh plate = testing::FlatGrid(-2.0, -1.5, 4.0, 3.0, 6, 4, 0.1);
  PlacementOptions placement = AtTheSheetCentre(0.7);
  placement.rotation_deg = 20.0;
  SubdivisionOptions sub;
  sub.tolerance = 0.01;
  const Animated a = Animate(spec, 16, {}, plate, placement, sub);
  ASSERT_EQ(a.model.placements.size(), 7u);
  const Vec2 moved = a.model.placements.back().target - a.model.placements.front().target;
  EXPECT_GT(moved.norm(), 0.3) << "the centre's sheet point moves between the keys";
  EXPECT_GT(a.model.mesh.positions.size(), plate.positions.size()) << "refined";
  // Both ends: every input vertex where the static deformation on the key
  // puts it (the refinements differ: the animation's serves every frame).
  for (const auto& [k, key] : {std::pair{0, first}, std::pair{6, last}}) {
    const Mesh alone = Static(key, 16, plate, placement, sub);
    const Mesh frame = Frame(a, k, placement);
    ASSERT_FALSE(alone.positions.empty());
    ASSERT_GE(frame.positions.size(), plate.positions.size());
    EXPECT_LT(Apart(frame, alone, plate.positions.size()), 1e-9) << "frame " << k;
  }
}

TEST(Animation, FitFitsEveryFrameAndTheTightestFrameDecides) {
  // The sheet shrinks as the surface bends: a scale fitted to the first
  // sheet leaves the last one.
  const BezierSpec first = Shrunk(0.2, 1.0), last = Shrunk(1.0, 0.75);
  const AnimationSpec spec = Pair(first, last, 6);
  const Mesh plate = testing::FlatGrid(-2.0, -1.5, 4.0, 3.0, 12, 9, 0.1);
  const PlacementOptions placement = AtTheSheetCentre(0.0);
  SubdivisionOptions off;
  off.mode = SubdivisionMode::kOff;
  const Animated a = Animate(spec, 16, {}, plate, placement, off);
  EXPECT_EQ(a.model.fit_frame, 5) << "the last, smallest sheet decides";
  const double scale = a.model.placements.front().scale;
  for (const Placement& pl : a.model.placements) EXPECT_EQ(pl.scale, scale);
  for (int k = 0; k < spec.frames; ++k) {
    auto r = DeformPrepared(a.maps[k], a.model, k, {.placement = placement});
    ASSERT_TRUE(r.ok()) << "frame " << k << ": " << r.status().ToString();
    EXPECT_EQ(r->stats.outside, 0u) << "frame " << k;
    EXPECT_EQ(r->stats.fit_frame, 5);
  }
  // The scale is the last key's own fit (to the bisection's 1e-5), and
  // smaller than the first key's.
  auto fitted = [&](const SurfaceSpec& key) {
    const std::unique_ptr<Surface> surface = testing::MakeValid(key);
    auto sheet = FlattenSurface(*surface, {16, 16}, {});
    EXPECT_TRUE(sheet.ok());
    const SheetMap map(*surface, *sheet);
    auto pl = ComputePlacement(map, plate.positions, placement);
    EXPECT_TRUE(pl.ok()) << pl.status().ToString();
    return pl.ok() ? pl->scale : 0.0;
  };
  EXPECT_NEAR(scale, fitted(last), 2e-5 * scale);
  EXPECT_LT(scale, 0.95 * fitted(first));
}

TEST(Animation, APlateOnACylinderOfAnimatedRadiusWrapsAsTheClosedFormSays) {
  const double height = 3.0;
  // The arc keeps its length: radius 2 over 180 degrees to radius 4 over 90.
  AnimationSpec spec =
      Pair(CylinderSpec{2.0, height, 180.0, {}}, CylinderSpec{4.0, height, 90.0, {}}, 7);
  spec.interpolation = Interpolation::kLinear;
  const Mesh plate = testing::ThinPlate(4.0, 2.0, 0.2);
  const Vec2 at(kPi, height / 2);  // the middle of the sheet at frame 0
  const PlacementOptions placement = testing::KeepCoordinates(plate, at);
  const Animated a = Animate(spec, 16, {}, plate, placement, {});
  for (int k = 0; k < spec.frames; ++k) {
    const CylinderSpec c = std::get<CylinderSpec>(SurfaceAtFrame(spec, k));
    const Mesh out = Frame(a, k, placement);
    // The exact unrolling is canonical: the arc from angle 0, height along +Y.
    for (size_t v = 0; v < a.model.input_vertices; ++v) {
      const Vec3& p = plate.positions[v];
      const double s = p.x() + at.x(), b = p.y() + at.y(), h = p.z();
      const double angle = s / c.radius;
      const Vec3 exact((c.radius + h) * std::cos(angle), (c.radius + h) * std::sin(angle), b);
      EXPECT_LT((out.positions[v] - exact).norm(), 1e-9) << "frame " << k << " vertex " << v;
    }
  }
}

TEST(Animation, EveryFrameHasOneTopologyThatMeetsTheTolerance) {
  // A coarse plate bent ever more: the subdivision chosen for all frames.
  const AnimationSpec spec = Pair(Figure10(0.2), Figure10(1.0), 4);
  const Mesh plate = testing::ThinPlate(4.0, 3.0, 0.1);
  const PlacementOptions placement = testing::KeepCoordinates(plate, Vec2(5.0, 4.5));
  SubdivisionOptions sub;
  sub.tolerance = 0.01;
  const Animated a = Animate(spec, 16, {}, plate, placement, sub);
  EXPECT_GT(a.model.mesh.positions.size(), plate.positions.size());
  EXPECT_LE(a.model.subdivision.max_deviation, 0.01);
  EXPECT_GE(a.model.subdivision_passes, 1);
  // Each frame on its own asks for no more points than the shared topology has.
  for (int k = 0; k < spec.frames; ++k) {
    SubdivisionOptions again = sub;
    auto r = Subdivide(a.model.mesh, a.model.placed, a.maps[k], placement.outside, again);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->stats.vertices_after, r->stats.vertices_before) << "frame " << k;
    EXPECT_LE(r->stats.max_deviation, 0.01) << k;
    const Mesh out = Frame(a, k, placement);
    EXPECT_EQ(out.positions.size(), a.model.mesh.positions.size());
  }
}

}  // namespace
}  // namespace surfdeform
