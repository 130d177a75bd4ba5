// surfdeform batch: many meshes, one set of parameters, an output folder.
// Requests run in parallel (one connection per worker); the surface is
// flattened once up front and then named by id. Resumable: an output that
// exists is skipped unless --force, and outputs are written atomically, so an
// interrupted run leaves no half-written file behind. On a terminal, a
// progress bar with rate and ETA; otherwise one plain line per file.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "cli/commands.hpp"

namespace surfdeform::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Job {
  std::string input;  // a mesh file, or how a text is named in messages
  std::string output;
  std::string text;  // batch --texts: the text (then no mesh file)
};

// The progress bar (terminal) or plain lines, from any worker.
class Progress {
 public:
  Progress(size_t total, bool terminal) : total_(total), terminal_(terminal), t0_(Clock::now()) {}

  void Line(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (terminal_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(terminal_ ? stderr : stdout, "%s\n", text.c_str());
    if (terminal_) DrawLocked();
    std::fflush(stdout);
  }
  void Done(bool failed) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    failed_ += failed ? 1 : 0;
    if (terminal_) DrawLocked();
  }
  void Finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (terminal_) std::fprintf(stderr, "\n");
  }

 private:
  void DrawLocked() {
    const double s = std::chrono::duration<double>(Clock::now() - t0_).count();
    const double rate = s > 0.0 ? static_cast<double>(done_) / s : 0.0;
    const double eta = rate > 0.0 ? static_cast<double>(total_ - done_) / rate : 0.0;
    constexpr int kWidth = 30;
    const int filled = total_ == 0 ? kWidth : static_cast<int>(kWidth * done_ / total_);
    std::fprintf(stderr, "\r[%s%s] %zu/%zu  %.1f files/s  ETA %d:%02d%s",
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '-').c_str(), done_,
                 total_, rate, static_cast<int>(eta) / 60, static_cast<int>(eta) % 60,
                 failed_ ? ("  " + std::to_string(failed_) + " failed").c_str() : "");
    std::fflush(stderr);
  }

  std::mutex mutex_;
  const size_t total_;
  const bool terminal_;
  const Clock::time_point t0_;
  size_t done_ = 0;
  size_t failed_ = 0;
};

bool CollectInputs(const std::vector<std::string>& inputs, std::vector<std::string>* files,
                   std::string* error) {
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(in, ec)) {
        if (entry.is_regular_file() && IsMeshFileName(entry.path().string())) {
          found.push_back(entry.path().string());
        }
      }
      if (ec) {
        *error = "cannot list " + in + ": " + ec.message();
        return false;
      }
      std::sort(found.begin(), found.end());
      files->insert(files->end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in, ec)) {
      files->push_back(in);
    } else {
      *error = "no such file or folder: " + in;
      return false;
    }
  }
  return true;
}

// Jobs whose output exists are skipped unless `force`; two jobs that would
// write the same file are a usage error, not a silent overwrite.
bool ClaimOutputs(std::vector<Job> all, bool force, std::vector<Job>* work, size_t* skipped) {
  std::map<std::string, std::string> claimed;
  std::error_code ec;
  for (Job& job : all) {
    if (auto [it, fresh] = claimed.emplace(job.output, job.input); !fresh) {
      std::fprintf(stderr, "surfdeform: %s and %s would both write %s\n", it->second.c_str(),
                   job.input.c_str(), job.output.c_str());
      return false;
    }
    if (!force && fs::exists(job.output, ec)) {
      ++*skipped;
      continue;
    }
    work->push_back(std::move(job));
  }
  return true;
}

bool MakeOutputDir(const std::string& out_dir) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "surfdeform: cannot create %s: %s\n", out_dir.c_str(),
                 ec.message().c_str());
    return false;
  }
  return true;
}

// A text as a file name: letters and digits kept (any script), the rest
// one "-", at most 48 bytes, after its line number.
std::string TextFileName(size_t line, const std::string& text) {
  char number[16];
  std::snprintf(number, sizeof number, "%03zu-", line);
  std::string name = number;
  bool dash = false;
  for (unsigned char ch : text) {
    const bool keep = ch >= 0x80 || std::isalnum(ch) != 0;
    if (keep) {
      name += static_cast<char>(ch);
      dash = false;
    } else if (!dash) {
      name += '-';
      dash = true;
    }
    if (name.size() >= 52) break;
  }
  while (!name.empty() &&
         (name.back() == '-' || (static_cast<unsigned char>(name.back()) & 0xC0) == 0xC0)) {
    name.pop_back();  // no trailing dash, nor a cut UTF-8 sequence's lead byte
  }
  return name;
}

int RunJobs(const Connection& c, const DeformOptions& o, OutputKind kind, std::vector<Job> work,
            size_t skipped, int jobs);

// --ext's output kind; a message for one that is none.
std::optional<OutputKind> BatchKind(const std::string& extension) {
  const auto kind = OutputKindOf("x" + extension);
  if (!kind) {
    std::fprintf(stderr, "surfdeform: --ext: .drc, .glb, .obj or .ply, got %s\n",
                 extension.c_str());
  }
  return kind;
}

}  // namespace

int RunBatch(const Connection& c, const DeformOptions& o, const std::vector<std::string>& inputs,
             const std::string& out_dir, const std::string& extension, int jobs, bool force) {
  const auto kind = BatchKind(extension);
  if (!kind) return kExitUsage;
  std::vector<std::string> files;
  std::string error;
  if (!CollectInputs(inputs, &files, &error)) {
    std::fprintf(stderr, "surfdeform: %s\n", error.c_str());
    return kExitLocalFile;
  }
  if (!MakeOutputDir(out_dir)) return kExitLocalFile;
  // Outputs: the input's name with the output's extension.
  std::vector<Job> all;
  for (const std::string& in : files) {
    all.push_back({in, (fs::path(out_dir) / fs::path(in).stem()).string() + extension, ""});
  }
  std::vector<Job> work;
  size_t skipped = 0;
  if (!ClaimOutputs(std::move(all), force, &work, &skipped)) return kExitUsage;
  return RunJobs(c, o, *kind, std::move(work), skipped, jobs);
}

int RunTextBatch(const Connection& c, const DeformOptions& o, const std::string& texts_path,
                 const std::string& out_dir, const std::string& extension, int jobs, bool force) {
  const auto kind = BatchKind(extension);
  if (!kind) return kExitUsage;
  std::string bytes, message;
  if (!ReadFileBytes(texts_path, &bytes, &message)) {
    std::fprintf(stderr, "surfdeform: %s: %s\n", texts_path.c_str(), message.c_str());
    return kExitLocalFile;
  }
  if (!MakeOutputDir(out_dir)) return kExitLocalFile;
  std::vector<Job> all;
  std::istringstream lines(bytes);
  size_t number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    all.push_back({"line " + std::to_string(number) + " \"" + line + "\"",
                   (fs::path(out_dir) / TextFileName(number, line)).string() + extension, line});
  }
  std::vector<Job> work;
  size_t skipped = 0;
  if (!ClaimOutputs(std::move(all), force, &work, &skipped)) return kExitUsage;
  return RunJobs(c, o, *kind, std::move(work), skipped, jobs);
}

namespace {

int RunJobs(const Connection& c, const DeformOptions& o, OutputKind kind, std::vector<Job> work,
            size_t skipped, int jobs) {
  // The surface, flattened once, then named by id in every request.
  DeformOptions by_id = o;
  if (!o.surface_file.empty() && !work.empty()) {
    DeformRequest probe;
    if (CliError e; !BuildDeformRequest(o, kind, &probe, &e)) {
      std::fprintf(stderr, "surfdeform: %s\n", e.message.c_str());
      return e.exit_code();
    }
    const proto::CreateSurfaceRequest surface_request{*probe.params.surface, {}};
    ApiClient client(c.server, c.retry, c.timeout_s);
    HttpReply r;
    HttpFailure f;
    if (!UploadSurfaceMesh(client, probe, &f) ||
        !client.PostJson("/v1/surfaces", proto::ToJson(surface_request).dump(), &r, &f)) {
      std::fprintf(stderr, "surfdeform: the surface: %s\n", f.message.c_str());
      return f.unreachable || f.status >= 500 ? kExitUnavailable : kExitRefused;
    }
    by_id.surface_file.clear();
    by_id.surface_id = nlohmann::json::parse(r.body).value("id", "");
  }
  DeformRequest request;
  if (CliError e; !BuildDeformRequest(by_id, kind, &request, &e)) {
    std::fprintf(stderr, "surfdeform: %s\n", e.message.c_str());
    return e.exit_code();
  }

  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  Progress progress(work.size(), terminal);
  if (skipped > 0) {
    progress.Line("skipping " + std::to_string(skipped) +
                  " file(s) whose output exists (--force to redo them)");
  }
  std::atomic<size_t> next{0};
  std::atomic<size_t> failed{0};
  std::vector<std::thread> workers;
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(work.size())));
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&] {
      ApiClient client(c.server, c.retry, c.timeout_s);
      if (c.verbose) {
        client.set_on_retry([&](int attempt, const std::string& why, double wait) {
          char buf[64];
          std::snprintf(buf, sizeof buf, "; waiting %.1f s", wait);
          progress.Line("retry " + std::to_string(attempt) + ": " + why + buf);
        });
      }
      for (size_t k = next++; k < work.size(); k = next++) {
        const auto t0 = Clock::now();
        std::string message;
        int code = kExitOk;
        if (work[k].text.empty()) {
          code = DeformFile(client, request, work[k].input, work[k].output, &message);
        } else {  // a text: its own parameters, no mesh file
          DeformOptions one = by_id;
          one.text = work[k].text;
          DeformRequest with_text;
          CliError e;
          code = BuildDeformRequest(one, kind, &with_text, &e)
                     ? DeformFile(client, with_text, "", work[k].output, &message)
                     : (message = e.message, e.exit_code());
        }
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        if (code == kExitOk) {
          if (!terminal) {
            char buf[32];
            std::snprintf(buf, sizeof buf, " (%.0f ms)", ms);
            progress.Line("ok " + work[k].input + " -> " + work[k].output + ": " + message + buf);
          }
        } else {
          ++failed;
          progress.Line("FAILED " + work[k].input + ": " + message);
        }
        progress.Done(code != kExitOk);
      }
    });
  }
  for (std::thread& w : workers) w.join();
  progress.Finish();
  std::fprintf(stderr, "%zu done, %zu skipped, %zu failed\n", work.size() - failed.load(), skipped,
               failed.load());
  return failed.load() == 0 ? kExitOk : kExitPartial;
}

}  // namespace
}  // namespace surfdeform::cli
