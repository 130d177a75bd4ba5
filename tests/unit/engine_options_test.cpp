// A request's settings as the engine's options: every setting carried as
// given, and how the work runs added by the service alone.
#include "service/engine_options.hpp"

#include <gtest/gtest.h>

#include "service/limit_checks.hpp"

namespace surfdeform {
namespace {

TEST(EngineOptions, FlatteningCarriesTheSettingsAndRunsAsTheServiceSays) {
  FlattenSettings given;
  given.method = FlattenMethod::kPaper;
  given.range = 2;
  given.tolerance = 1e-5;
  given.max_iterations = 50;
  given.step = 0.01;
  given.exact_developable = false;
  given.lattice_factor = 3;
  given.relax_steps = 1;
  CancelFlag cancel;
  const RequestClock clock(60000.0, &cancel);
  const FlattenOptions f = FlattenFor(given, 3, clock, 250.0);
  EXPECT_EQ(f.method, FlattenMethod::kPaper);
  EXPECT_EQ(f.range, 2);
  EXPECT_EQ(f.tolerance, 1e-5);
  EXPECT_EQ(f.max_iterations, 50);
  EXPECT_EQ(f.step, 0.01);
  EXPECT_FALSE(f.exact_developable);
  EXPECT_EQ(f.lattice_factor, 3);
  EXPECT_EQ(f.relax_steps, 1);
  EXPECT_EQ(f.threads, 3);
  EXPECT_EQ(f.time_budget_ms, 250.0);
  EXPECT_EQ(f.cancel, &cancel);     // the request's cancellation reaches the engine
  EXPECT_EQ(f.max_mesh_pairs, 0u);  // set where a mesh's size is known
  // A request's defaults are the engine's.
  const FlattenOptions defaults = WithRunDefaults<FlattenOptions>(FlattenSettings{});
  EXPECT_EQ(defaults.range, FlattenOptions{}.range);
  EXPECT_EQ(defaults.tolerance, FlattenOptions{}.tolerance);
  EXPECT_EQ(defaults.threads, 0);
}

TEST(EngineOptions, PlacementIsYUpForGltfInputAndRunsOnTheRequestsThreads) {
  PlacementSettings given;
  given.up = UpAxis::kAuto;
  given.fit = true;
  given.fit_margin = 0.1;
  given.outside = OutsideMode::kClamp;
  ImportedMesh obj;
  obj.format = MeshFormat::kObj;
  const PlacementOptions p = PlacementFor(given, obj, 2);
  EXPECT_EQ(p.up, UpAxis::kAuto);
  EXPECT_TRUE(p.fit);
  EXPECT_EQ(p.fit_margin, 0.1);
  EXPECT_EQ(p.outside, OutsideMode::kClamp);
  EXPECT_EQ(p.threads, 2);
  EXPECT_FALSE(p.y_up_input);
  for (MeshFormat gltf : {MeshFormat::kGlb, MeshFormat::kGltf}) {
    ImportedMesh m;
    m.format = gltf;
    EXPECT_TRUE(PlacementFor(given, m, 2).y_up_input);
  }
}

TEST(EngineOptions, SubdivisionGetsTheServiceLimitsAndWhatIsLeftOfTheBudget) {
  ServiceLimits limits;
  limits.max_output_vertices = 12345;
  limits.max_output_triangles = 23456;
  limits.request_time_budget_ms = 60000.0;
  const RequestWork work(limits);
  SubdivisionSettings given;
  given.mode = SubdivisionMode::kUniform;
  given.epsilon = 0.5;
  given.tolerance = 0.002;
  const SubdivisionOptions s = SubdivisionFor(given, limits, work);
  EXPECT_EQ(s.mode, SubdivisionMode::kUniform);
  EXPECT_EQ(s.epsilon, 0.5);
  EXPECT_EQ(s.tolerance, 0.002);
  EXPECT_EQ(s.max_vertices, MaxOutputVertices(limits));
  EXPECT_EQ(s.max_triangles, 23456u);
  EXPECT_GT(s.time_budget_ms, 0.0);
  EXPECT_LE(s.time_budget_ms, 60000.0);
  EXPECT_EQ(s.threads, work.threads());
}

}  // namespace
}  // namespace surfdeform
