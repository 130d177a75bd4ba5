#include "service/disk_tier.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <random>
#include <unordered_map>

#include "proto/content_hash.hpp"

namespace surfdeform {
namespace {

namespace fs = std::filesystem;
using FileTime = fs::file_time_type;

// A file's first line; the header then holds the value's length, its
// SHA-256 and the key, each on a line of its own.
constexpr std::string_view kMagic = "surfdeform-object 1\n";
// The largest value kept (a 512 x 512 sheet is ~17 MB encoded; a model is
// at most the body limit).
constexpr size_t kMaxValueBytes = size_t{1} << 31;

bool WriteAll(int fd, std::string_view bytes) {
  size_t at = 0;
  while (at < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
    if (n > 0) {
      at += static_cast<size_t>(n);
    } else if (!(n < 0 && errno == EINTR)) {
      return false;
    }
  }
  return true;
}

bool ReadFile(const fs::path& path, std::string* out) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat st {};
  bool ok = ::fstat(fd, &st) == 0 && st.st_size >= 0 &&
            static_cast<size_t>(st.st_size) <= kMaxValueBytes + 4096;
  if (ok) {
    out->resize(static_cast<size_t>(st.st_size));
    size_t at = 0;
    while (ok && at < out->size()) {
      const ssize_t n = ::read(fd, out->data() + at, out->size() - at);
      if (n > 0) {
        at += static_cast<size_t>(n);
      } else if (!(n < 0 && errno == EINTR)) {
        ok = false;
      }
    }
    out->resize(at);
  }
  ::close(fd);
  return ok;
}

// The value in a file's bytes, when they are whole and name `key`.
bool Unpack(std::string_view file, const std::string& key, std::string* value) {
  if (file.substr(0, kMagic.size()) != kMagic) return false;
  file.remove_prefix(kMagic.size());
  auto line = [&file](std::string_view* out) {
    const size_t end = file.find('\n');
    if (end == std::string_view::npos) return false;
    *out = file.substr(0, end);
    file.remove_prefix(end + 1);
    return true;
  };
  std::string_view length, digest, name;
  if (!line(&length) || !line(&digest) || !line(&name) || name != key) return false;
  if (length.empty() || length.size() > 12 ||
      length.find_first_not_of("0123456789") != std::string_view::npos) {
    return false;
  }
  if (std::stoull(std::string(length)) != file.size()) return false;
  if (proto::Sha256Hex(file) != digest) return false;
  value->assign(file.data(), file.size());
  return true;
}

class DiskTier final : public SharedTier {
 public:
  DiskTier(DiskTierOptions options, int lock_fd)
      : options_(std::move(options)), root_(options_.dir), lock_fd_(lock_fd) {
    shared_options_.ttl_s = 0;
    stats_.enabled = true;
    stats_.kind = "disk";
    Index();
  }
  ~DiskTier() override {
    if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the directory's lock
  }

  const SharedTierOptions& options() const override { return shared_options_; }
  Retention retention() const override { return Retention{"disk", true, 0, options_.budget_bytes}; }

  Lookup Get(const std::string& key, std::string* value) override {
    const std::string name = NameOf(key);
    {
      std::lock_guard lock(mutex_);
      ++stats_.commands;
      if (files_.count(name) == 0) {
        ++stats_.misses;
        return Lookup::kMiss;
      }
    }
    std::string file;
    const fs::path path = PathOf(name);
    const bool read = ReadFile(path, &file);
    std::lock_guard lock(mutex_);
    if (!read || !Unpack(file, key, value)) {
      // Damaged, cut short, foreign, or gone behind our back: never trusted.
      std::error_code ec;
      fs::remove(path, ec);
      Forget(name);
      ++(read ? stats_.corrupt : stats_.errors);
      ++stats_.misses;
      return Lookup::kMiss;
    }
    ++stats_.hits;
    Touch(name, path);
    return Lookup::kHit;
  }

  void Put(const std::string& key, std::string_view value) override {
    if (value.size() > kMaxValueBytes || value.size() > options_.budget_bytes) return;
    const std::string name = NameOf(key);
    const std::string header = std::string(kMagic) + std::to_string(value.size()) + "\n" +
                               proto::Sha256Hex(value) + "\n" + key + "\n";
    thread_local std::mt19937_64 rng(std::random_device{}());
    const fs::path tmp = root_ / "tmp" / (name + "." + std::to_string(rng()));
    const fs::path path = PathOf(name);
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    bool ok = fd >= 0 && WriteAll(fd, header) && WriteAll(fd, value) && ::fsync(fd) == 0;
    if (fd >= 0) ok = ::close(fd) == 0 && ok;
    ok = ok && ::rename(tmp.c_str(), path.c_str()) == 0;
    if (!ok) {
      fs::remove(tmp, ec);
      std::lock_guard lock(mutex_);
      ++stats_.errors;
      return;
    }
    SyncDirectory(path.parent_path());
    const size_t size = header.size() + value.size();
    std::lock_guard lock(mutex_);
    ++stats_.writes;
    Forget(name);
    const auto now = FileTime::clock::now();
    files_[name] = {size, now};
    by_age_.emplace(now, name);
    total_ += size;
    Evict();
  }

  // One process per directory: its own flights are single already.
  Lock TryLock(const std::string&, std::string* token) override {
    token->clear();
    return Lock::kAcquired;
  }
  void Unlock(const std::string&, const std::string&) override {}

  bool Exists(const std::string& key) override {
    std::lock_guard lock(mutex_);
    return files_.count(NameOf(key)) != 0;
  }

  void CountCorrupt() override {
    std::lock_guard lock(mutex_);
    ++stats_.corrupt;
    if (stats_.hits > 0) --stats_.hits;
  }
  void CountLockWait(bool) override {}
  SharedTierStats stats() const override {
    std::lock_guard lock(mutex_);
    return stats_;
  }

 private:
  struct File {
    size_t bytes = 0;
    FileTime used;
  };

  static std::string NameOf(const std::string& key) { return proto::Sha256Hex(key); }
  fs::path PathOf(const std::string& name) const {
    return root_ / "objects" / name.substr(0, 2) / name;
  }

  static void SyncDirectory(const fs::path& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
  }

  // The files there are, from the directory (at start): their sizes and
  // when each was last used.
  void Index() {
    std::error_code ec;
    fs::remove_all(root_ / "tmp", ec);  // writes a crash cut short
    fs::create_directories(root_ / "tmp", ec);
    for (auto it = fs::recursive_directory_iterator(root_ / "objects", ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      if (!it->is_regular_file(ec)) continue;
      const std::string name = it->path().filename().string();
      if (name.size() != 64) continue;
      const size_t size = static_cast<size_t>(it->file_size(ec));
      const FileTime used = it->last_write_time(ec);
      files_[name] = {size, used};
      by_age_.emplace(used, name);
      total_ += size;
    }
    Evict();
  }

  // Under mutex_: removes `name` from the index.
  void Forget(const std::string& name) {
    auto it = files_.find(name);
    if (it == files_.end()) return;
    total_ -= it->second.bytes;
    auto [first, last] = by_age_.equal_range(it->second.used);
    for (auto a = first; a != last; ++a) {
      if (a->second == name) {
        by_age_.erase(a);
        break;
      }
    }
    files_.erase(it);
  }

  // Under mutex_: `name` was used now (its file's time too, for the next start).
  void Touch(const std::string& name, const fs::path& path) {
    auto it = files_.find(name);
    if (it == files_.end()) return;
    const size_t bytes = it->second.bytes;
    Forget(name);
    const auto now = FileTime::clock::now();
    files_[name] = {bytes, now};
    by_age_.emplace(now, name);
    total_ += bytes;
    std::error_code ec;
    fs::last_write_time(path, now, ec);
  }

  // Under mutex_: the least recently used files go until the rest fit.
  void Evict() {
    while (total_ > options_.budget_bytes && !by_age_.empty()) {
      const std::string name = by_age_.begin()->second;
      std::error_code ec;
      fs::remove(PathOf(name), ec);
      Forget(name);
    }
  }

  const DiskTierOptions options_;
  const fs::path root_;
  const int lock_fd_;
  SharedTierOptions shared_options_;
  mutable std::mutex mutex_;
  SharedTierStats stats_;
  std::unordered_map<std::string, File> files_;
  std::multimap<FileTime, std::string> by_age_;
  size_t total_ = 0;
};

}  // namespace

Result<std::unique_ptr<SharedTier>> CreateDiskTier(const DiskTierOptions& options) {
  auto bad = [&](const std::string& why) {
    return Status(ErrorCode::kInvalidArgument, "the data directory \"" + options.dir + "\" " + why,
                  "data-dir");
  };
  if (options.dir.empty()) return bad("is empty");
  std::error_code ec;
  fs::create_directories(fs::path(options.dir) / "objects", ec);
  if (ec) return bad("cannot be created: " + ec.message());
  const fs::path lock_path = fs::path(options.dir) / "lock";
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return bad(std::string("cannot be written: ") + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    return bad("is in use by another surfdeform-server (each server needs its own, or Redis)");
  }
  return std::unique_ptr<SharedTier>(new DiskTier(options, fd));
}

}  // namespace surfdeform
