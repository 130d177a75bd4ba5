#include "engine/animation/animation.hpp"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>

#include "base/format.hpp"
#include "engine/animation/mesh_animation.hpp"
#include "engine/common/disk_mesh.hpp"
#include "engine/common/elapsed.hpp"
#include "engine/common/parallel.hpp"
#include "engine/surface/surface_fields.hpp"

namespace surfdeform {
namespace {

using Clock = std::chrono::steady_clock;

// A surface's numbers, in order: its fields' (WalkNumbers), or a mesh's
// vertex coordinates.
std::vector<double> NumbersOf(const SurfaceSpec& spec) {
  std::vector<double> out;
  if (const auto* m = std::get_if<MeshSpec>(&spec)) {
    if (m->disk == nullptr) return out;
    out.reserve(3 * m->disk->positions.size());
    for (const Vec3& p : m->disk->positions) out.insert(out.end(), {p.x(), p.y(), p.z()});
    return out;
  }
  SurfaceSpec copy = spec;
  WalkNumbers(copy, [&out](const auto&, double& v) { out.push_back(v); });
  return out;
}

void SetNumbers(const std::vector<double>& values, SurfaceSpec* spec) {
  if (auto* m = std::get_if<MeshSpec>(spec)) {
    auto disk = std::make_shared<DiskMesh>(*m->disk);
    for (size_t v = 0; v < disk->positions.size(); ++v) {
      disk->positions[v] = Vec3(values[3 * v], values[3 * v + 1], values[3 * v + 2]);
    }
    m->disk = std::move(disk);
    m->flattened = nullptr;
    return;
  }
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
  if (const auto* a = std::get_if<MeshSpec>(&first)) {
    const auto& b = std::get<MeshSpec>(key);
    // Unresolved (a request as parsed): checked once the service resolves them.
    if (a->disk == nullptr || b.disk == nullptr) return Status::Ok();
    const DiskMesh &x = *a->disk, &y = *b.disk;
    if (x.positions.size() != y.positions.size() || x.triangles != y.triangles) {
      return InvalidArgument(
          Format(
              "is a mesh of %zu vertices and %zu triangles (after welding) but keyframe "
              "0's has %zu and %zu%s: keyframes of kind \"mesh\" must be one mesh moving, "
              "the same vertices and triangles in the same order (a simulation's frames "
              "exported alike)",
              y.positions.size(), y.triangles.size(), x.positions.size(), x.triangles.size(),
              x.positions.size() == y.positions.size() && x.triangles.size() == y.triangles.size()
                  ? ", joined differently"
                  : ""),
          "model_id");
    }
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

std::vector<Vec2> CarryOn(std::span<const std::vector<Vec2>* const> newest_first) {
  static constexpr double kCarry[3][3] = {{1, 0, 0}, {2, -1, 0}, {3, -3, 1}};
  const double* c = kCarry[newest_first.size() - 1];
  std::vector<Vec2> out(newest_first[0]->size(), Vec2::Zero());
  for (size_t h = 0; h < newest_first.size(); ++h) {
    const std::vector<Vec2>& x = *newest_first[h];
    for (size_t i = 0; i < x.size(); ++i) out[i] += c[h] * x[i];
  }
  return out;
}

Status AnimationFrameError(const AnimationSpec& spec, int frame, const Status& s, double budget_ms,
                           double spent_ms) {
  const std::string message = "frame " + std::to_string(frame) + " (time " +
                              std::to_string(FrameTime(spec, frame)) + "): " + s.message();
  return s.code() == ErrorCode::kDeadlineExceeded
             ? Status::DeadlineExceeded(message, "animation", budget_ms, spent_ms)
             : Status(s.code(), message, s.field());
}

Status AnimationBudgetLeft(const AnimationSpec& spec, int done, double budget_ms, double spent_ms,
                           FlattenOptions* o) {
  if (budget_ms <= 0.0) return Status::Ok();
  o->time_budget_ms = budget_ms - spent_ms;
  if (o->time_budget_ms > 0.0) return Status::Ok();
  return Status::DeadlineExceeded("the animation's flattening ran past its time budget of " +
                                      std::to_string(static_cast<long long>(budget_ms)) +
                                      " ms after " + std::to_string(done) + " of " +
                                      std::to_string(spec.frames) + " frames",
                                  "animation", budget_ms, spent_ms);
}

namespace {

// One animation's flattening: every frame's surface, the distances measured
// ahead on worker threads, the frames solved in order on the calling thread.
//
// Distances. Every kPathAnchorEvery-th frame, the last one and the frames on
// keys are anchors: measured afresh, keeping the paths they follow. A frame
// between two anchors is measured along the blend of their paths
// (FlattenDistancesBetween: no relaxation, about 40% of the work). On Figure
// 10 bending (animate_bench) the sheets' stress stays within 6e-7 of the
// frames flattened alone (the bound is 1e-6); anchors 16 frames apart
// would not keep that. The frames' distances do not depend on one another's
// sheets, so they are measured ahead, a frame per thread at a time, and
// solved in order by one Flattener (the factored Laplacian is shared), each
// frame warm-started from the previous frames' sheets. Which frames are
// anchors depends on the spec alone, so a frame's sheet does not depend on
// the thread count.
//
// Measuring runs as tasks in the order the solves need them: a frame's
// distances (an anchor's with its paths, or a frame between along the blend
// of the anchors around it). Anchors run three segments ahead of the frames
// between that blend them, so that those rarely wait. `workers - 1` threads
// take tasks in order; the calling thread solves frame after frame and, while
// the next frame's distances are not ready, takes tasks too, so no core idles
// while measuring is left (batches that met at a join kept two cores 1.55
// busy on average).
class AnimationFlattening {
 public:
  AnimationFlattening(const AnimationSpec& spec, const SamplingOptions& sampling,
                      const FlattenOptions& options, const FrameProgress& progress)
      : spec_(spec),
        sampling_(sampling),
        options_(options),
        progress_(progress),
        t0_(Clock::now()),
        workers_(std::min(ResolveThreads(options.threads), spec.frames)),
        frame_threads_(workers_ > 1 ? 1 : options.threads),
        flattener_(options) {}

  Result<AnimatedSheets> Run() && {
    SURFDEFORM_RETURN_IF_ERROR(MakeSurfaces());
    ChooseAnchors();
    QueueTasks();
    SURFDEFORM_RETURN_IF_ERROR(MeasureAndSolve());
    out_.total_ms = MsSince(t0_);
    return std::move(out_);
  }

 private:
  struct Task {
    int frame;
    int anchor;   // its index in `anchors_`, or -1 for a frame between
    int segment;  // a frame between's: from anchors_[segment] to the next
  };
  enum class AnchorState : char { kPending, kMeasured, kFailed };

  Status FrameError(int k, const Status& s) const {
    return AnimationFrameError(spec_, k, s, options_.time_budget_ms, MsSince(t0_));
  }

  Status BudgetLeft(int done, FlattenOptions* o) const {
    return AnimationBudgetLeft(spec_, done, options_.time_budget_ms, MsSince(t0_), o);
  }

  Status MakeSurfaces() {
    out_.surfaces.reserve(spec_.frames);
    out_.sheets.reserve(spec_.frames);
    const std::vector<std::vector<double>> numbers = KeyNumbers(spec_);
    for (int k = 0; k < spec_.frames; ++k) {
      auto surface = MakeSurface(SurfaceAt(spec_, numbers, k));
      if (!surface.ok()) return FrameError(k, surface.status());
      out_.surfaces.push_back(std::move(*surface));
    }
    return Status::Ok();
  }

  void ChooseAnchors() {
    for (int k = 0; k < spec_.frames; ++k) {
      if (k % kPathAnchorEvery == 0 || k == spec_.frames - 1 || OnKey(spec_, k)) {
        anchors_.push_back(k);
      }
    }
    anchor_count_ = static_cast<int>(anchors_.size());
    paths_.resize(anchor_count_);
    anchor_state_.assign(anchor_count_, AnchorState::kPending);
    measured_.assign(spec_.frames, NotComputed());
    measure_ms_.assign(spec_.frames, 0.0);
    ready_.assign(spec_.frames, 0);
  }

  // The tasks, in the order the solves need them: anchors three segments
  // ahead of the frames between them.
  void QueueTasks() {
    tasks_.reserve(spec_.frames);
    int queued_anchors = 0;
    auto queue_anchors_to = [&](int last) {
      for (; queued_anchors <= std::min(last, anchor_count_ - 1); ++queued_anchors) {
        tasks_.push_back({anchors_[queued_anchors], queued_anchors, -1});
      }
    };
    const int segments = anchor_count_ - 1;
    for (int s = 0; s < segments; ++s) {
      queue_anchors_to(s + 3);
      for (int k = anchors_[s] + 1; k < anchors_[s + 1]; ++k) tasks_.push_back({k, -1, s});
    }
    queue_anchors_to(anchor_count_ - 1);
  }

  // The start of frame k's solve: none on a key, which starts cold as the
  // key alone would (its sheet is then bit for bit the static surface's:
  // deformations of the keys match POST /v1/deform on them exactly); else
  // the last sheets carried on by the polynomial through up to three of them
  // (3 X[k-1] - 3 X[k-2] + X[k-3]): the sheet moves smoothly, so the start
  // is off by O(dt^3) instead of O(dt), and the solve takes fewer iterations
  // (Figure 10 bending: 5.2 instead of 11.9).
  const FlatSheet* WarmStart(int k, FlatSheet* carried) const {
    const FlatSheet* warm = k > 0 && !OnKey(spec_, k) ? &out_.sheets.back() : nullptr;
    if (warm == nullptr) return nullptr;
    const std::vector<Vec2>* last[3] = {&warm->flat, nullptr, nullptr};
    size_t history = 1;
    while (history < 3 && out_.sheets.size() > history &&
           out_.sheets[out_.sheets.size() - 1 - history].flat.size() == warm->flat.size()) {
      last[history] = &out_.sheets[out_.sheets.size() - 1 - history].flat;
      ++history;
    }
    if (history == 1) return warm;
    carried->nu = warm->nu;
    carried->nv = warm->nv;
    carried->flat = CarryOn(std::span(last, history));
    return carried;
  }

  Status Solve(int k, Result<MeasuredGrid>& d, double distance_ms) {
    if (!d.ok()) return FrameError(k, d.status());
    FlattenOptions o = options_;
    SURFDEFORM_RETURN_IF_ERROR(BudgetLeft(k, &o));
    flattener_.set_options(o);
    FlatSheet carried;
    const FlatSheet* warm = WarmStart(k, &carried);
    const int reused = d->distances.reused_paths;
    auto sheet = flattener_.Flatten(*out_.surfaces[k], warm, std::move(*d));
    if (!sheet.ok()) return FrameError(k, sheet.status());
    FrameFlattening f;
    f.time = FrameTime(spec_, k);
    f.warm = warm != nullptr;
    f.quality = sheet->quality;
    f.reused_paths = reused;
    // Measured ahead, on whichever thread took the frame.
    f.quality.distance_ms = distance_ms;
    f.quality.total_ms += f.quality.distance_ms;
    out_.frames.push_back(f);
    out_.sheets.push_back(std::move(*sheet));
    if (progress_) progress_(k, spec_.frames);
    return Status::Ok();
  }

  // The frame between's blends: the paths' parameters interpolated
  // (Lagrange) through the anchors around the frame, up to two on each side,
  // where every one of those measured the pair along a path; else linearly
  // between the two on either side. At least three anchors: with a straight
  // line through two, Figure 10 bending over 8 frames flattened to a stress
  // up to 1.2e-5 off the frames' own; such a frame is measured afresh.
  Result<MeasuredGrid> MeasureBetween(int k, int s, const FlattenOptions& o) {
    auto anchor_ok = [&](int i) { return anchor_state_[i] == AnchorState::kMeasured; };
    {
      // Anchors come earlier in the task order: whoever took them is
      // measuring them now.
      std::unique_lock lock(mu_);
      changed_.wait(lock, [&] {
        if (stop_) return true;
        for (int a = std::max(0, s - 1); a <= std::min(anchor_count_ - 1, s + 2); ++a) {
          if (anchor_state_[a] == AnchorState::kPending) return false;
        }
        return true;
      });
      // Nothing reads the result once the solves have stopped.
      if (stop_) return Status(ErrorCode::kInternal, "the animation's flattening stopped");
    }
    const int lo = s > 0 && anchor_ok(s - 1) ? s - 1 : s;
    const int hi = s + 2 < anchor_count_ && anchor_ok(s + 2) ? s + 2 : s + 1;
    if (!anchor_ok(s) || !anchor_ok(s + 1) || hi - lo < 2) {
      return FlattenDistances(*out_.surfaces[k], sampling_, o, frame_threads_);
    }
    WeightedPaths around[4];
    int n = 0;
    for (int m = lo; m <= hi; ++m) {
      double w = 1.0;
      for (int j = lo; j <= hi; ++j) {
        if (j != m) w *= static_cast<double>(k - anchors_[j]) / (anchors_[m] - anchors_[j]);
      }
      around[n++] = {&paths_[m], w};
    }
    const double t = static_cast<double>(k - anchors_[s]) / (anchors_[s + 1] - anchors_[s]);
    const WeightedPaths linear[] = {{&paths_[s], 1.0 - t}, {&paths_[s + 1], t}};
    const PathBlend blends[] = {PathBlend(around, n), PathBlend(linear)};
    return FlattenDistancesBetween(*out_.surfaces[k], sampling_, o, blends, frame_threads_);
  }

  // Runs one task (the lock not held) and publishes its result.
  void RunTask(const Task& task) {
    const auto started = Clock::now();
    FlattenOptions o = options_;
    const Status budget = BudgetLeft(task.frame, &o);
    Result<MeasuredGrid> r = !budget.ok() ? Result<MeasuredGrid>(budget)
                             : task.anchor >= 0
                                 ? FlattenDistances(*out_.surfaces[task.frame], sampling_, o,
                                                    frame_threads_, &paths_[task.anchor])
                                 : MeasureBetween(task.frame, task.segment, o);
    const double ms = MsSince(started);
    std::lock_guard lock(mu_);
    if (task.anchor >= 0) {
      anchor_state_[task.anchor] = r.ok() ? AnchorState::kMeasured : AnchorState::kFailed;
    }
    measured_[task.frame] = std::move(r);
    measure_ms_[task.frame] = ms;
    ready_[task.frame] = 1;
    changed_.notify_all();
  }

  // The next task for a measurer (none once all are taken or on stop).
  // Measurers stay this many frames ahead of the solves at most (memory):
  // room for the anchors three segments ahead and a segment per thread.
  const Task* Take(std::unique_lock<std::mutex>& lock, bool solver) {
    const int lookahead = (4 + workers_) * kPathAnchorEvery;
    if (!solver) {
      changed_.wait(lock, [&] {
        return stop_ || next_task_ >= tasks_.size() ||
               tasks_[next_task_].frame <= solved_ + lookahead;
      });
    }
    if (stop_ || next_task_ >= tasks_.size()) return nullptr;
    return &tasks_[next_task_++];
  }

  // The measurers, stopped and joined however the solves end.
  struct Measurers {
    AnimationFlattening& a;
    std::vector<std::thread> threads;
    ~Measurers() {
      {
        std::lock_guard lock(a.mu_);
        a.stop_ = true;
      }
      a.changed_.notify_all();
      for (std::thread& t : threads) t.join();
    }
  };

  // The solves, in order; between them this thread measures as well.
  Status MeasureAndSolve() {
    Measurers measurers{*this, {}};
    for (int w = 0; w + 1 < workers_; ++w) {
      measurers.threads.emplace_back([this] {
        for (;;) {
          std::unique_lock lock(mu_);
          const Task* task = Take(lock, false);
          if (task == nullptr) return;
          lock.unlock();
          RunTask(*task);
        }
      });
      parallel_detail::StartOffCallerCpu(measurers.threads.back(), w);
    }
    for (int k = 0; k < spec_.frames; ++k) {
      std::unique_lock lock(mu_);
      while (!ready_[k]) {
        const Task* task = Take(lock, true);
        if (task == nullptr) {
          changed_.wait(lock, [&] { return ready_[k] != 0; });
          break;
        }
        lock.unlock();
        RunTask(*task);
        lock.lock();
      }
      lock.unlock();
      SURFDEFORM_RETURN_IF_ERROR(Solve(k, measured_[k], measure_ms_[k]));
      // Anchor a serves the frames between of segments a - 2 to a + 1: all
      // measured once frame anchors[a + 2] is solved, so no task reads its
      // paths any more (freed outside the lock).
      for (int a = 0; a + 2 < anchor_count_; ++a) {
        if (anchors_[a + 2] == k) paths_[a] = DistancePaths{};
      }
      lock.lock();
      solved_ = k + 1;
      changed_.notify_all();
    }
    return Status::Ok();
  }

  const AnimationSpec& spec_;
  const SamplingOptions& sampling_;
  const FlattenOptions& options_;
  const FrameProgress& progress_;
  const Clock::time_point t0_;
  const int workers_;
  const int frame_threads_;
  Flattener flattener_;
  AnimatedSheets out_;
  std::vector<int> anchors_;
  int anchor_count_ = 0;
  std::vector<Task> tasks_;
  std::vector<DistancePaths> paths_;  // dropped once no frame left needs them
  std::vector<AnchorState> anchor_state_;
  std::vector<Result<MeasuredGrid>> measured_;
  std::vector<double> measure_ms_;
  std::vector<char> ready_;
  // Guards the task cursor, anchor_state_, ready_, solved_ and stop_; a slot
  // of measured_ and paths_ belongs to the task that fills it until it is
  // marked ready (or measured) under the lock.
  std::mutex mu_;
  std::condition_variable changed_;
  size_t next_task_ = 0;
  int solved_ = 0;
  bool stop_ = false;
};

}  // namespace

Result<AnimatedSheets> FlattenAnimation(const AnimationSpec& spec, const SamplingOptions& sampling,
                                        const FlattenOptions& options,
                                        const FrameProgress& progress) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateAnimation(spec, spec.frames));
  if (std::holds_alternative<MeshSpec>(spec.keyframes[0].surface)) {
    const std::vector<std::vector<double>> numbers = KeyNumbers(spec);
    return FlattenMeshAnimation(spec, sampling, options, progress, [&](int frame) {
      return std::get<MeshSpec>(SurfaceAt(spec, numbers, frame));
    });
  }
  return AnimationFlattening(spec, sampling, options, progress).Run();
}

}  // namespace surfdeform
