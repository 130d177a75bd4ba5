#include "engine/animation.hpp"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>

#include "base/format.hpp"
#include "engine/elapsed.hpp"
#include "engine/parallel.hpp"
#include "engine/surface_fields.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<double> NumbersOf(const SurfaceSpec& spec) {
  std::vector<double> out;
  SurfaceSpec copy = spec;
  WalkNumbers(copy, [&out](const auto&, double& v) { out.push_back(v); });
  return out;
}

void SetNumbers(const std::vector<double>& values, SurfaceSpec* spec) {
  size_t k = 0;
  WalkNumbers(*spec, [&](const auto&, double& v) { v = values[k++]; });
}

std::string NumberField(const SurfaceSpec& spec, size_t index) {
  SurfaceSpec copy = spec;
  std::string field;
  size_t k = 0;
  WalkNumbers(copy, [&](const auto& name, double&) {
    if (k++ == index) field = name();
  });
  return field;
}

// `key`'s shape against the first key's: the integers and the list sizes.
Status SameShape(const SurfaceSpec& first, const SurfaceSpec& key) {
  if (KindOf(first) != KindOf(key)) {
    return InvalidArgument(std::string("is \"") + std::string(KindName(KindOf(key))) +
                               "\" but keyframe 0 is \"" + std::string(KindName(KindOf(first))) +
                               "\": keyframes are surfaces of one kind",
                           "kind");
  }
  auto differ = [](const std::string& field, long long a, long long b) {
    return InvalidArgument("is " + std::to_string(b) + " but " + std::to_string(a) +
                               " in keyframe 0: keyframes must have one shape, since every "
                               "number is interpolated between them",
                           field);
  };
  if (const auto* a = std::get_if<BezierSpec>(&first)) {
    const auto& b = std::get<BezierSpec>(key);
    if (a->degree_u != b.degree_u) return differ("degree_u", a->degree_u, b.degree_u);
    if (a->degree_v != b.degree_v) return differ("degree_v", a->degree_v, b.degree_v);
    if (a->control_points.size() != b.control_points.size()) {
      return differ("control_points", static_cast<long long>(a->control_points.size()),
                    static_cast<long long>(b.control_points.size()));
    }
  }
  if (const auto* a = std::get_if<BSplineSpec>(&first)) {
    const auto& b = std::get<BSplineSpec>(key);
    if (a->degree_u != b.degree_u) return differ("degree_u", a->degree_u, b.degree_u);
    if (a->degree_v != b.degree_v) return differ("degree_v", a->degree_v, b.degree_v);
    if (a->count_u != b.count_u) return differ("count_u", a->count_u, b.count_u);
    if (a->count_v != b.count_v) return differ("count_v", a->count_v, b.count_v);
    auto size = [](const auto& v) { return static_cast<long long>(v.size()); };
    if (size(a->control_points) != size(b.control_points)) {
      return differ("control_points", size(a->control_points), size(b.control_points));
    }
    if (size(a->knots_u) != size(b.knots_u))
      return differ("knots_u", size(a->knots_u), size(b.knots_u));
    if (size(a->knots_v) != size(b.knots_v))
      return differ("knots_v", size(a->knots_v), size(b.knots_v));
    if (size(a->weights) != size(b.weights))
      return differ("weights", size(a->weights), size(b.weights));
  }
  if (const auto* a = std::get_if<GridSpec>(&first)) {
    const auto& b = std::get<GridSpec>(key);
    if (a->nu != b.nu) return differ("nu", a->nu, b.nu);
    if (a->nv != b.nv) return differ("nv", a->nv, b.nv);
    if (a->points.size() != b.points.size()) {
      return differ("points", static_cast<long long>(a->points.size()),
                    static_cast<long long>(b.points.size()));
    }
  }
  return Status::Ok();
}

// Cubic Hermite on [t0, t1] with end values p0, p1 and slopes m0, m1, in
// difference form (p0 plus the change): a number that is the same on the
// keys around it stays exactly that number on every frame (an angle_deg of
// 360 is 360, not 360.00000000000006, which the surface would refuse).
double Hermite(double t, double t0, double t1, double p0, double p1, double m0, double m1) {
  const double h = t1 - t0;
  const double s = (t - t0) / h;
  const double s2 = s * s, s3 = s2 * s;
  return p0 + (-2 * s3 + 3 * s2) * (p1 - p0) + (s3 - 2 * s2 + s) * h * m0 + (s3 - s2) * h * m1;
}

// Frame k lands exactly on a keyframe's time (always frame 0).
bool OnKey(const AnimationSpec& spec, int frame) {
  if (frame == 0) return true;
  if (spec.keyframes.size() == 1) return false;
  const double t = FrameTime(spec, frame);
  for (const Keyframe& k : spec.keyframes) {
    if (k.time == t) return true;
  }
  return false;
}

}  // namespace

Status ValidateAnimation(const AnimationSpec& spec, int max_frames) {
  if (spec.keyframes.empty()) {
    return InvalidArgument("needs at least one keyframe", "keyframes");
  }
  if (spec.frames < 1 || spec.frames > max_frames) {
    if (spec.frames > max_frames) {
      return Status::LimitExceeded("this server animates at most " + std::to_string(max_frames) +
                                       " frames, asked for " + std::to_string(spec.frames),
                                   "frames", max_frames, spec.frames);
    }
    return InvalidArgument("must be at least 1, got " + std::to_string(spec.frames), "frames");
  }
  if (!(spec.fps >= kMinFps && spec.fps <= kMaxFps)) {
    return InvalidArgument(
        Format("must be from %g to %g frames per second, got %g", kMinFps, kMaxFps, spec.fps),
        "fps");
  }
  if (spec.keyframes.size() == 1 && !std::holds_alternative<WaveSpec>(spec.keyframes[0].surface)) {
    return InvalidArgument(
        std::string("a single keyframe must be a wave (whose time advances); a \"") +
            std::string(KindName(KindOf(spec.keyframes[0].surface))) +
            "\" needs a second keyframe to move",
        "keyframes");
  }
  const SurfaceSpec& first = spec.keyframes[0].surface;
  if (std::holds_alternative<MeshSpec>(first)) {
    return InvalidArgument(
        "surfaces of kind \"mesh\" are not animated yet: deform along each frame's mesh "
        "with POST /v1/deform",
        "keyframes[0].surface.kind");
  }
  for (size_t k = 0; k < spec.keyframes.size(); ++k) {
    const std::string key = "keyframes[" + std::to_string(k) + "]";
    const Keyframe& kf = spec.keyframes[k];
    if (!(std::abs(kf.time) <= kMaxKeyTime)) {
      return InvalidArgument(
          Format("must be a time within +-%g seconds, got %g", kMaxKeyTime, kf.time),
          key + ".time");
    }
    if (k > 0 && !(kf.time > spec.keyframes[k - 1].time)) {
      return InvalidArgument(
          Format("must be later than keyframe %zu's (%g)", k - 1, spec.keyframes[k - 1].time),
          key + ".time");
    }
    SURFDEFORM_RETURN_IF_ERROR(SameShape(first, kf.surface).WithFieldPrefix(key + ".surface"));
    const std::vector<double> numbers = NumbersOf(kf.surface);
    for (size_t n = 0; n < numbers.size(); ++n) {
      if (!std::isfinite(numbers[n])) {
        return InvalidArgument("must be finite", key + ".surface." + NumberField(kf.surface, n));
      }
    }
  }
  return Status::Ok();
}

double FrameTime(const AnimationSpec& spec, int frame) {
  const double t0 = spec.keyframes.front().time;
  if (spec.keyframes.size() == 1) return t0 + frame / spec.fps;
  if (spec.frames <= 1) return t0;
  const double t1 = spec.keyframes.back().time;
  // The last frame lands on the last key exactly.
  if (frame >= spec.frames - 1) return t1;
  return t0 + (t1 - t0) * frame / (spec.frames - 1);
}

namespace {

// Every key's numbers (NumbersOf), once per animation.
std::vector<std::vector<double>> KeyNumbers(const AnimationSpec& spec) {
  std::vector<std::vector<double>> out;
  out.reserve(spec.keyframes.size());
  for (const Keyframe& k : spec.keyframes) out.push_back(NumbersOf(k.surface));
  return out;
}

// SurfaceAtFrame with the keys' numbers given.
SurfaceSpec SurfaceAt(const AnimationSpec& spec, const std::vector<std::vector<double>>& numbers,
                      int frame) {
  const auto& keys = spec.keyframes;
  const double t = FrameTime(spec, frame);
  if (keys.size() == 1) {
    SurfaceSpec s = keys[0].surface;
    std::get<WaveSpec>(s).time += t - keys[0].time;
    return s;
  }
  // The span [k, k + 1] that holds t (the last span for t at the end).
  size_t k = 0;
  while (k + 2 < keys.size() && t >= keys[k + 1].time) ++k;
  const double t0 = keys[k].time, t1 = keys[k + 1].time;
  const std::vector<double>& p0 = numbers[k];
  const std::vector<double>& p1 = numbers[k + 1];
  std::vector<double> out(p0.size());
  if (t == t0 || t == t1) {  // exactly a key: its numbers, bit for bit
    out = t == t0 ? p0 : p1;
  } else if (spec.interpolation == Interpolation::kLinear) {
    const double s = (t - t0) / (t1 - t0);
    for (size_t n = 0; n < out.size(); ++n) out[n] = p0[n] + s * (p1[n] - p0[n]);
  } else {
    // Catmull-Rom slopes: centred differences over the neighbouring keys,
    // one-sided at the ends.
    const std::vector<double>& before = k > 0 ? numbers[k - 1] : p0;
    const std::vector<double>& after = k + 2 < keys.size() ? numbers[k + 2] : p1;
    const double tb = k > 0 ? keys[k - 1].time : t0;
    const double ta = k + 2 < keys.size() ? keys[k + 2].time : t1;
    for (size_t n = 0; n < out.size(); ++n) {
      const double m0 = (p1[n] - before[n]) / (t1 - tb);
      const double m1 = (after[n] - p0[n]) / (ta - t0);
      out[n] = Hermite(t, t0, t1, p0[n], p1[n], m0, m1);
    }
  }
  SurfaceSpec s = keys[k].surface;
  SetNumbers(out, &s);
  return s;
}

}  // namespace

SurfaceSpec SurfaceAtFrame(const AnimationSpec& spec, int frame) {
  return SurfaceAt(spec, KeyNumbers(spec), frame);
}

Result<AnimatedSheets> FlattenAnimation(const AnimationSpec& spec, const SamplingOptions& sampling,
                                        const FlattenOptions& options,
                                        const FrameProgress& progress) {
  const auto t0 = Clock::now();
  SURFDEFORM_RETURN_IF_ERROR(ValidateAnimation(spec, spec.frames));
  AnimatedSheets out;
  out.surfaces.reserve(spec.frames);
  out.sheets.reserve(spec.frames);
  // An error of frame k, prefixed with the frame; a deadline is the
  // animation's (its budget and the time spent on all frames).
  auto as_frame_error = [&](int k, const Status& s) {
    const std::string message = "frame " + std::to_string(k) + " (time " +
                                std::to_string(FrameTime(spec, k)) + "): " + s.message();
    return s.code() == ErrorCode::kDeadlineExceeded
               ? Status::DeadlineExceeded(message, "animation", options.time_budget_ms, MsSince(t0))
               : Status(s.code(), message, s.field());
  };
  const std::vector<std::vector<double>> numbers = KeyNumbers(spec);
  for (int k = 0; k < spec.frames; ++k) {
    auto surface = MakeSurface(SurfaceAt(spec, numbers, k));
    if (!surface.ok()) return as_frame_error(k, surface.status());
    out.surfaces.push_back(std::move(*surface));
  }
  // What is left of the budget, for the next step; an error once it is spent.
  auto budget_left = [&](int done, FlattenOptions* o) -> Status {
    if (options.time_budget_ms <= 0.0) return Status::Ok();
    o->time_budget_ms = options.time_budget_ms - MsSince(t0);
    if (o->time_budget_ms > 0.0) return Status::Ok();
    return Status::DeadlineExceeded(
        "the animation's flattening ran past its time budget of " +
            std::to_string(static_cast<long long>(options.time_budget_ms)) + " ms after " +
            std::to_string(done) + " of " + std::to_string(spec.frames) + " frames",
        "animation", options.time_budget_ms, MsSince(t0));
  };
  // Distances. Every kPathAnchorEvery-th frame, the last one and the frames
  // on keys are anchors: measured afresh, keeping the paths they follow. A
  // frame between two anchors is measured along the blend of their paths
  // (FlattenDistancesBetween: no relaxation, about 40% of the work). On
  // Figure 10 bending (animate_bench) the sheets' stress stays within 6e-7
  // of the frames flattened alone (the bound is 1e-6); anchors 16
  // frames apart would not keep that. The frames' distances do not depend on
  // one another's sheets, so they are measured ahead, a frame per thread at a
  // time, and solved in order by one Flattener (the factored Laplacian is
  // shared), each frame warm-started from the previous frames' sheets. Which
  // frames are anchors depends on the spec alone, so a frame's sheet does not
  // depend on the thread count.
  std::vector<int> anchors;
  for (int k = 0; k < spec.frames; ++k) {
    if (k % kPathAnchorEvery == 0 || k == spec.frames - 1 || OnKey(spec, k)) anchors.push_back(k);
  }
  const int workers = std::min(ResolveThreads(options.threads), spec.frames);
  const int frame_threads = workers > 1 ? 1 : options.threads;
  Flattener flattener(options);
  auto solve = [&](int k, Result<MeasuredGrid>& d, double distance_ms) -> Status {
    if (!d.ok()) return as_frame_error(k, d.status());
    FlattenOptions o = options;
    SURFDEFORM_RETURN_IF_ERROR(budget_left(k, &o));
    flattener.set_options(o);
    // A frame on a key starts cold, as the key alone would: its sheet is
    // then bit for bit the static surface's (deformations of the keys
    // match POST /v1/deform on them exactly).
    const FlatSheet* warm = k > 0 && !OnKey(spec, k) ? &out.sheets.back() : nullptr;
    // The start is the last sheets carried on, by the polynomial through up
    // to three of them (3 X[k-1] - 3 X[k-2] + X[k-3]): the sheet moves
    // smoothly, so the start is off by O(dt^3) instead of O(dt), and the
    // solve takes fewer iterations (Figure 10 bending: 5.2 instead of 11.9).
    FlatSheet carried;
    if (warm != nullptr) {
      static constexpr double kCarry[3][3] = {{1, 0, 0}, {2, -1, 0}, {3, -3, 1}};
      int history = 1;
      while (history < 3 && out.sheets.size() > static_cast<size_t>(history) &&
             out.sheets[out.sheets.size() - 1 - history].flat.size() == warm->flat.size()) {
        ++history;
      }
      if (history > 1) {
        const double* c = kCarry[history - 1];
        carried.nu = warm->nu;
        carried.nv = warm->nv;
        carried.flat.assign(warm->flat.size(), Vec2::Zero());
        for (int h = 0; h < history; ++h) {
          const std::vector<Vec2>& x = out.sheets[out.sheets.size() - 1 - h].flat;
          for (size_t i = 0; i < x.size(); ++i) carried.flat[i] += c[h] * x[i];
        }
        warm = &carried;
      }
    }
    const int reused = d->distances.reused_paths;
    auto sheet = flattener.Flatten(*out.surfaces[k], warm, std::move(*d));
    if (!sheet.ok()) return as_frame_error(k, sheet.status());
    FrameFlattening f;
    f.time = FrameTime(spec, k);
    f.warm = warm != nullptr;
    f.quality = sheet->quality;
    f.reused_paths = reused;
    // Measured ahead, on whichever thread took the frame.
    f.quality.distance_ms = distance_ms;
    f.quality.total_ms += f.quality.distance_ms;
    out.frames.push_back(f);
    out.sheets.push_back(std::move(*sheet));
    if (progress) progress(k, spec.frames);
    return Status::Ok();
  };
  // Measuring, as tasks in the order the solves need them: a frame's
  // distances (an anchor's with its paths, or a frame between along the
  // blend of the anchors around it). Anchors run three segments ahead of the
  // frames between that blend them, so that those rarely wait. `workers - 1`
  // threads take tasks in order; the calling thread solves frame after frame
  // and, while the next frame's distances are not ready, takes tasks too, so
  // no core idles while measuring is left (batches that met at a join kept
  // two cores 1.55 busy on average).
  const int anchor_count = static_cast<int>(anchors.size());
  const int segments = anchor_count - 1;
  struct Task {
    int frame;
    int anchor;   // its index in `anchors`, or -1 for a frame between
    int segment;  // a frame between's: from anchors[segment] to the next
  };
  std::vector<Task> tasks;
  tasks.reserve(spec.frames);
  int queued_anchors = 0;
  auto queue_anchors_to = [&](int last) {
    for (; queued_anchors <= std::min(last, anchor_count - 1); ++queued_anchors) {
      tasks.push_back({anchors[queued_anchors], queued_anchors, -1});
    }
  };
  for (int s = 0; s < segments; ++s) {
    queue_anchors_to(s + 3);
    for (int k = anchors[s] + 1; k < anchors[s + 1]; ++k) tasks.push_back({k, -1, s});
  }
  queue_anchors_to(anchor_count - 1);

  enum class AnchorState : char { kPending, kMeasured, kFailed };
  std::vector<DistancePaths> paths(anchor_count);  // dropped once no frame left needs them
  std::vector<AnchorState> anchor_state(anchor_count, AnchorState::kPending);
  std::vector<Result<MeasuredGrid>> measured(spec.frames, NotComputed());
  std::vector<double> measure_ms(spec.frames, 0.0);
  std::vector<char> ready(spec.frames, 0);
  // Guards the task cursor, anchor_state, ready, `solved` and `stop`; a
  // slot of `measured` and `paths` belongs to the task that fills it until
  // it is marked ready (or measured) under the lock.
  std::mutex mu;
  std::condition_variable changed;
  size_t next_task = 0;
  int solved = 0;
  bool stop = false;
  // Measurers stay this many frames ahead of the solves at most (memory):
  // room for the anchors three segments ahead and a segment per thread.
  const int lookahead = (4 + workers) * kPathAnchorEvery;

  // The frame between's blends: the paths' parameters interpolated
  // (Lagrange) through the anchors around the frame, up to two on each side,
  // where every one of those measured the pair along a path; else linearly
  // between the two on either side. At least three anchors: with a straight
  // line through two, Figure 10 bending over 8 frames flattened to a stress
  // up to 1.2e-5 off the frames' own; such a frame is measured afresh.
  auto measure_between = [&](int k, int s, const FlattenOptions& o) -> Result<MeasuredGrid> {
    auto anchor_ok = [&](int i) { return anchor_state[i] == AnchorState::kMeasured; };
    {
      // Anchors come earlier in the task order: whoever took them is
      // measuring them now.
      std::unique_lock lock(mu);
      changed.wait(lock, [&] {
        if (stop) return true;
        for (int a = std::max(0, s - 1); a <= std::min(anchor_count - 1, s + 2); ++a) {
          if (anchor_state[a] == AnchorState::kPending) return false;
        }
        return true;
      });
      // Nothing reads the result once the solves have stopped.
      if (stop) return Status(ErrorCode::kInternal, "the animation's flattening stopped");
    }
    const int lo = s > 0 && anchor_ok(s - 1) ? s - 1 : s;
    const int hi = s + 2 < anchor_count && anchor_ok(s + 2) ? s + 2 : s + 1;
    if (!anchor_ok(s) || !anchor_ok(s + 1) || hi - lo < 2) {
      return FlattenDistances(*out.surfaces[k], sampling, o, frame_threads);
    }
    WeightedPaths around[4];
    int n = 0;
    for (int m = lo; m <= hi; ++m) {
      double w = 1.0;
      for (int j = lo; j <= hi; ++j) {
        if (j != m) w *= static_cast<double>(k - anchors[j]) / (anchors[m] - anchors[j]);
      }
      around[n++] = {&paths[m], w};
    }
    const double t = static_cast<double>(k - anchors[s]) / (anchors[s + 1] - anchors[s]);
    const WeightedPaths linear[] = {{&paths[s], 1.0 - t}, {&paths[s + 1], t}};
    const PathBlend blends[] = {PathBlend(around, n), PathBlend(linear)};
    return FlattenDistancesBetween(*out.surfaces[k], sampling, o, blends, frame_threads);
  };
  // Runs one task (the lock not held) and publishes its result.
  auto run = [&](const Task& task) {
    const auto started = Clock::now();
    FlattenOptions o = options;
    const Status budget = budget_left(task.frame, &o);
    Result<MeasuredGrid> r = !budget.ok() ? Result<MeasuredGrid>(budget)
                             : task.anchor >= 0
                                 ? FlattenDistances(*out.surfaces[task.frame], sampling, o,
                                                    frame_threads, &paths[task.anchor])
                                 : measure_between(task.frame, task.segment, o);
    const double ms = MsSince(started);
    std::lock_guard lock(mu);
    if (task.anchor >= 0) {
      anchor_state[task.anchor] = r.ok() ? AnchorState::kMeasured : AnchorState::kFailed;
    }
    measured[task.frame] = std::move(r);
    measure_ms[task.frame] = ms;
    ready[task.frame] = 1;
    changed.notify_all();
  };
  // The next task for a measurer (none once all are taken or on stop).
  auto take = [&](std::unique_lock<std::mutex>& lock, bool solver) -> const Task* {
    if (!solver) {
      changed.wait(lock, [&] {
        return stop || next_task >= tasks.size() || tasks[next_task].frame <= solved + lookahead;
      });
    }
    if (stop || next_task >= tasks.size()) return nullptr;
    return &tasks[next_task++];
  };
  // The measurers, stopped and joined however the solves end.
  struct Measurers {
    std::mutex& mu;
    std::condition_variable& changed;
    bool& stop;
    std::vector<std::thread> threads;
    ~Measurers() {
      {
        std::lock_guard lock(mu);
        stop = true;
      }
      changed.notify_all();
      for (std::thread& t : threads) t.join();
    }
  } measurers{mu, changed, stop, {}};
  for (int w = 0; w + 1 < workers; ++w) {
    measurers.threads.emplace_back([&] {
      for (;;) {
        std::unique_lock lock(mu);
        const Task* task = take(lock, false);
        if (task == nullptr) return;
        lock.unlock();
        run(*task);
      }
    });
    parallel_detail::StartOffCallerCpu(measurers.threads.back(), w);
  }
  // The solves, in order; between them this thread measures as well.
  for (int k = 0; k < spec.frames; ++k) {
    std::unique_lock lock(mu);
    while (!ready[k]) {
      const Task* task = take(lock, true);
      if (task == nullptr) {
        changed.wait(lock, [&] { return ready[k] != 0; });
        break;
      }
      lock.unlock();
      run(*task);
      lock.lock();
    }
    lock.unlock();
    SURFDEFORM_RETURN_IF_ERROR(solve(k, measured[k], measure_ms[k]));
    // Anchor a serves the frames between of segments a - 2 to a + 1: all
    // measured once frame anchors[a + 2] is solved, so no task reads its
    // paths any more (freed outside the lock).
    for (int a = 0; a + 2 < anchor_count; ++a) {
      if (anchors[a + 2] == k) paths[a] = DistancePaths{};
    }
    lock.lock();
    solved = k + 1;
    changed.notify_all();
  }
  out.total_ms = MsSince(t0);
  return out;
}

}  // namespace surfdeform
