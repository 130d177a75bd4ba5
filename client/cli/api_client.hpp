// The command-line client's connection to a surfdeform server: requests with
// retries for what is safe to retry (connection errors, 503 with
// Retry-After), never for 4xx. Free of httplib in its header (httplib.h and
// Eigen must not meet in one translation unit; see docs/ARCHITECTURE.md).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace surfdeform::cli {

struct RetryPolicy {
  int attempts = 5;             // tries in all, the first included
  double first_delay_s = 0.25;  // then doubled each time (with jitter) ...
  double max_delay_s = 8.0;     // ... up to this, or the server's Retry-After
};

struct HttpReply {
  int status = 0;
  std::string body;
  std::string content_type;
  std::string stats;   // X-Surfdeform-Stats
  std::string timing;  // Server-Timing
};

// A failed exchange: no reply at all (after the retries), or a reply whose
// status is an error. `message` is for a person: with an error reply, the
// server's problem detail, its field, limit and actual value.
struct HttpFailure {
  bool unreachable = false;
  int status = 0;
  std::string message;
  std::string code;  // the problem's "code" ("unknown_model", ...), when there is one
};

class ApiClient {
 public:
  // `server`: "http://host:port" (or https://); `timeout_s` per request.
  ApiClient(std::string server, RetryPolicy retry, double timeout_s = 300.0);
  ~ApiClient();
  ApiClient(const ApiClient&) = delete;
  ApiClient& operator=(const ApiClient&) = delete;

  // Reports each retry (attempt number, what happened, delay) when set.
  void set_on_retry(std::function<void(int, const std::string&, double)> f);

  // On success (2xx) *out is the reply; else *failure says what went wrong.
  bool Get(const std::string& path, HttpReply* out, HttpFailure* failure);
  // With the routing headers of the ids the JSON names (surface_id,
  // model_id), by which a load balancer picks the replica that holds them.
  bool PostJson(const std::string& path, const std::string& json, HttpReply* out,
                HttpFailure* failure, const std::string& accept = "");
  // POST /v1/models: a mesh file's bytes, routed by `model_id` (its id).
  bool PostModel(const std::string& mesh, const std::string& model_id, HttpReply* out,
                 HttpFailure* failure);

  const std::string& server() const { return server_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string server_;
};

// The problem+json of an error reply as one line: "detail (field; limit L,
// actual A)"; the raw body when it is not problem+json.
std::string ProblemMessage(int status, const std::string& body);

}  // namespace surfdeform::cli
