#include "http/request_basics.hpp"

#include <time.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

namespace surfdeform::http {

using nlohmann::json;

// "http://host:port/x" -> "/x" (and "http://host" -> "/"); other paths as
// they are.
void StripSchemeAndAuthority(std::string& path) {
  const size_t scheme = path.find("://");
  if (path.empty() || path.front() == '/' || scheme == std::string::npos) return;
  const size_t slash = path.find('/', scheme + 3);
  path = slash == std::string::npos ? "/" : path.substr(slash);
}

// The calling thread's CPU time, in seconds: what a request cost its worker,
// whatever else runs on the machine (a load test's check compares refused
// requests with served ones by it, which other tenants do not move).
double ThreadCpuSeconds() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

bool IsSafeRequestId(const std::string& id) {
  if (id.empty() || id.size() > 64) return false;
  for (char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_' || c == '.';
    if (!ok) return false;
  }
  return true;
}

std::string NewRequestId() {
  thread_local std::mt19937_64 rng(std::random_device{}());
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
  return buf;
}

std::string ServerTiming(const std::vector<Timing>& timings) {
  std::string out;
  for (const Timing& t : timings) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s%s;dur=%.3f", out.empty() ? "" : ", ", t.name.c_str(), t.ms);
    out += buf;
  }
  return out;
}

std::string ToAscii(const std::string& json_text) {
  // Header values must stay ASCII: re-dump with \u escapes.
  return json::parse(json_text, nullptr, false).dump(-1, ' ', true, json::error_handler_t::replace);
}

// Accept-Encoding without its "br" entries (a header with nothing else
// left is dropped: identity).
void WithoutBrotli(httplib::Headers* headers) {
  auto it = headers->find("Accept-Encoding");
  if (it == headers->end()) return;
  std::string kept;
  std::stringstream entries(it->second);
  for (std::string entry; std::getline(entries, entry, ',');) {
    const size_t first = entry.find_first_not_of(' ');
    if (first == std::string::npos || entry.compare(first, 2, "br") == 0) continue;
    kept += (kept.empty() ? "" : ", ") + entry.substr(first);
  }
  if (kept.empty()) {
    headers->erase(it);
  } else {
    it->second = kept;
  }
}

}  // namespace surfdeform::http
