// animate_bench: the paper's headline application (Figures 12-13) on this
// engine. The bunny on an animated 16x16 Bezier (Figure 10's patch bending
// and unbending: its heights x0.5, x1, x0.5 at times 0, 1, 2, cubic), 60
// frames. Prints, in one run: the time per frame by stage (flattening warm
// and cold, deformation, encoding), frames per second, output bytes per
// frame against separate Draco frames, and the ratios the targets are
// stated in: frames per second, a frame against a standalone
// deformation of it (cold flattening, deformation, Draco encode), and the
// warm flattening against the cold one at the same stress.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/animation/animation.hpp"
#include "engine/deform/deform.hpp"
#include "engine/flatten/flatten.hpp"
#include "harness.hpp"
#include "meshio/animation_glb.hpp"
#include "meshio/mesh_export.hpp"
#include "meshio/mesh_import.hpp"
#include "service/allocator_tuning.hpp"
#include "support/surface_file.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

using bench::Median;
const auto Ms = bench::MsSince;

// Figure 10 with its heights scaled.
BezierSpec Scaled(const BezierSpec& b, double k) {
  BezierSpec s = b;
  for (Vec3& p : s.control_points) p.z() *= k;
  return s;
}

int Run(int frames, int repeat) {
  const BezierSpec fig10 = testing::LoadBezierFile(testing::DataPath("figure10.json"));
  AnimationSpec spec;
  spec.keyframes = {{0.0, Scaled(fig10, 0.5)}, {1.0, fig10}, {2.0, Scaled(fig10, 0.5)}};
  spec.frames = frames;
  spec.fps = 30;
  const SamplingOptions sampling{16, 16};
  FlattenOptions flatten;  // the defaults, as the service uses them
  auto imported = ImportMesh(bench::ReadFile(testing::DataPath("bunny.ply")));
  if (!imported.ok()) {
    std::fprintf(stderr, "bunny: %s\n", imported.status().ToString().c_str());
    return 1;
  }
  std::printf(
      "animate_bench: bunny (%zu vertices, %zu triangles) on Figure 10 bending x0.5 -> "
      "x1 -> x0.5 (cubic), %d frames, 16x16, %d runs (medians)\n",
      imported->mesh.positions.size(), imported->mesh.triangles.size(), frames, repeat);

  std::vector<double> warm_ms, cold_ms, prepare_ms, deform_ms, encode_ms, total_ms;
  std::vector<double> draco_ms, standalone_ms;
  std::vector<double> warm_distance_ms, warm_solve_ms, cold_distance_ms, cold_solve_ms;
  int warm_count = 1;  // frames started warm (the last, on a key, starts cold)
  double worst_stress_gap = 0.0;
  int warm_iterations = 0, cold_iterations = 0;
  size_t glb_bytes = 0, glb_plain_bytes = 0, draco_bytes = 0;
  for (int run = 0; run < repeat; ++run) {
    const auto t0 = Clock::now();
    // 1. Flattening, warm-started frame to frame.
    auto sheets = FlattenAnimation(spec, sampling, flatten);
    if (!sheets.ok()) {
      std::fprintf(stderr, "%s\n", sheets.status().ToString().c_str());
      return 1;
    }
    const double flatten_all = Ms(t0);
    // 2. The model, placed once and refined for every frame (adaptive).
    const auto t1 = Clock::now();
    std::vector<SheetMap> maps;
    maps.reserve(frames);
    for (int k = 0; k < frames; ++k) maps.emplace_back(*sheets->surfaces[k], sheets->sheets[k]);
    std::vector<const SheetMap*> map_ptrs;
    for (const SheetMap& m : maps) map_ptrs.push_back(&m);
    PlacementOptions placement;
    placement.fit = true;
    Mesh mesh = imported->mesh;
    auto model = PrepareModel(map_ptrs, std::move(mesh),
                              {.placement = placement, .subdivision = SubdivisionOptions{}});
    if (!model.ok()) {
      std::fprintf(stderr, "%s\n", model.status().ToString().c_str());
      return 1;
    }
    const double prepare = Ms(t1);
    // 3. Every frame through its map.
    const auto t2 = Clock::now();
    MorphAnimation anim;
    anim.base = &model->mesh;
    anim.fps = spec.fps;
    for (int k = 0; k < frames; ++k) {
      auto frame =
          DeformPrepared(maps[k], *model, k, {.placement = placement, .geometry_only = true});
      if (!frame.ok()) {
        std::fprintf(stderr, "frame %d: %s\n", k, frame.status().ToString().c_str());
        return 1;
      }
      std::vector<Vec3f> p(frame->mesh.positions.size());
      for (size_t v = 0; v < p.size(); ++v) p[v] = frame->mesh.positions[v].cast<float>();
      anim.positions.push_back(std::move(p));
    }
    const double deform = Ms(t2);
    // 4. One GLB of morph targets, meshopt-compressed.
    const auto t3 = Clock::now();
    auto glb = WriteAnimationGlb(anim, {});
    const double encode = Ms(t3);
    if (!glb.ok()) {
      std::fprintf(stderr, "%s\n", glb.status().ToString().c_str());
      return 1;
    }
    total_ms.push_back(Ms(t0));
    glb_bytes = glb->size();
    AnimationGlbOptions plain;
    plain.compression = AnimationCompression::kNone;
    glb_plain_bytes = WriteAnimationGlb(anim, plain)->size();
    double dist_sum = 0.0, solve_sum = 0.0;
    int warm_frames = 0;
    warm_iterations = 0;
    for (int k = 1; k < frames; ++k) {
      if (!sheets->frames[k].warm) continue;
      ++warm_frames;
      dist_sum += sheets->frames[k].quality.distance_ms;
      solve_sum += sheets->frames[k].quality.solve_ms;
      warm_iterations += sheets->frames[k].quality.iterations;
    }
    // The sequence's wall time per frame: its distances are measured while
    // earlier frames are solved, so per-frame shares would not add up. It
    // includes building the frames' surfaces and the first frame (cold).
    warm_ms.push_back(flatten_all / frames);
    warm_distance_ms.push_back(dist_sum / warm_frames);
    warm_solve_ms.push_back(solve_sum / warm_frames);
    warm_count = warm_frames;
    prepare_ms.push_back(prepare / frames);
    deform_ms.push_back(deform / frames);
    encode_ms.push_back(encode / frames);

    // The peer, in the same run: each frame as a standalone deformation
    // (cold flattening, deformation, Draco), as POST /v1/deform does it.
    double cold_sum = 0.0, draco_sum = 0.0, standalone_sum = 0.0, cd = 0.0, cs = 0.0;
    cold_iterations = 0;
    draco_bytes = 0;
    for (int k = 0; k < frames; ++k) {
      const auto s0 = Clock::now();
      auto surface = MakeSurface(SurfaceAtFrame(spec, k));
      auto cold = FlattenSurface(**surface, sampling, flatten);
      cold_sum += Ms(s0);
      cd += cold->quality.distance_ms;
      cs += cold->quality.solve_ms;
      if (sheets->frames[k].warm) cold_iterations += cold->quality.iterations;
      const double gap =
          std::abs(cold->quality.stress - sheets->frames[k].quality.stress) / cold->quality.stress;
      worst_stress_gap = std::max(worst_stress_gap, gap);
      Mesh m = imported->mesh;
      auto out = Deform(SheetMap(**surface, *cold), std::move(m),
                        {.placement = placement, .subdivision = SubdivisionOptions{}});
      const auto s1 = Clock::now();
      auto drc = ExportMesh(out->mesh, MeshFormat::kDraco, {});
      draco_sum += Ms(s1);
      draco_bytes += drc->size();
      standalone_sum += Ms(s0);
    }
    cold_ms.push_back(cold_sum / frames);
    cold_distance_ms.push_back(cd / frames);
    cold_solve_ms.push_back(cs / frames);
    draco_ms.push_back(draco_sum / frames);
    standalone_ms.push_back(standalone_sum / frames);
  }
  const double warm = Median(warm_ms), cold = Median(cold_ms);
  const double per_frame = Median(total_ms) / frames;
  const double standalone = Median(standalone_ms);
  std::printf("\nper frame (ms):\n");
  std::printf(
      "  flatten, warm-started     %8.3f  (wall per frame; %.1f iterations; distances %.3f "
      "on one thread, solve %.3f)\n",
      warm, static_cast<double>(warm_iterations) / warm_count, Median(warm_distance_ms),
      Median(warm_solve_ms));
  std::printf(
      "  flatten, cold (peer)      %8.3f  (%.1f iterations; distances %.3f, solve %.3f)"
      "   warm is %.2fx faster\n",
      cold, static_cast<double>(cold_iterations) / warm_count, Median(cold_distance_ms),
      Median(cold_solve_ms), cold / warm);
  std::printf("  place + subdivide         %8.3f\n", Median(prepare_ms));
  std::printf("  deform                    %8.3f\n", Median(deform_ms));
  std::printf("  encode (morph targets)    %8.3f\n", Median(encode_ms));
  std::printf("  all stages                %8.3f  -> %.0f frames per second\n", per_frame,
              1000.0 / per_frame);
  std::printf("  standalone deform (peer)  %8.3f  (cold flatten + deform + Draco %.3f)\n",
              standalone, Median(draco_ms));
  std::printf("  frame / standalone        %8.3f\n", per_frame / standalone);
  std::printf("stress, warm against cold: largest relative difference %.2e\n", worst_stress_gap);
  std::printf(
      "bytes per frame: GLB meshopt %.0f, GLB uncompressed %.0f, Draco .drc frames %.0f "
      "(meshopt / Draco %.2f)\n",
      static_cast<double>(glb_bytes) / frames, static_cast<double>(glb_plain_bytes) / frames,
      static_cast<double>(draco_bytes) / frames,
      static_cast<double>(glb_bytes) / static_cast<double>(draco_bytes));
  return 0;
}

}  // namespace
}  // namespace surfdeform

int main(int argc, char** argv) {
  CLI::App app{"animate_bench: an animation's frames against standalone deformations"};
  int frames = 60, repeat = 3;
  app.add_option("--frames", frames, "frames")->check(CLI::Range(2, 10000));
  app.add_option("--repeat", repeat, "runs (medians)")->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);
  // As surfdeform-server runs (both the animation and the standalone peer).
  surfdeform::TuneAllocatorForServing();
  return surfdeform::Run(frames, repeat);
}
