#include "cli/api_client.hpp"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

namespace surfdeform::cli {
namespace {

std::string Num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// The routing headers for the ids `params` (JSON text) names.
httplib::Headers RoutingHeaders(const std::string& params) {
  httplib::Headers headers;
  const auto j = nlohmann::json::parse(params, nullptr, false);
  if (!j.is_object()) return headers;
  for (const auto& [key, header] : {std::pair{"surface_id", "X-Surfdeform-Surface-Id"},
                                    std::pair{"model_id", "X-Surfdeform-Model-Id"}}) {
    if (j.contains(key) && j[key].is_string()) headers.emplace(header, j[key].get<std::string>());
  }
  return headers;
}

std::string ProblemCode(const std::string& body) {
  const auto j = nlohmann::json::parse(body, nullptr, false);
  return j.is_object() && j.contains("code") && j["code"].is_string() ? j["code"].get<std::string>()
                                                                      : "";
}

}  // namespace

std::string ProblemMessage(int status, const std::string& body) {
  const auto j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("detail")) {
    std::string text = body.substr(0, 300);
    return "HTTP " + std::to_string(status) + (text.empty() ? "" : ": " + text);
  }
  std::string out = "HTTP " + std::to_string(status) + ": " + j.value("detail", "");
  std::string extra;
  if (j.contains("field") && j["field"].is_string()) extra = j["field"].get<std::string>();
  if (j.contains("limit") && j["limit"].is_number() && j.contains("actual")) {
    if (!extra.empty()) extra += "; ";
    extra +=
        "limit " + Num(j["limit"].get<double>()) + ", actual " + Num(j["actual"].get<double>());
  }
  if (!extra.empty()) out += " (" + extra + ")";
  return out;
}

struct ApiClient::Impl {
  Impl(const std::string& server, RetryPolicy r, double timeout) : client(server), retry(r) {
    const auto seconds = static_cast<time_t>(timeout);
    client.set_connection_timeout(10, 0);
    client.set_read_timeout(seconds, 0);
    client.set_write_timeout(seconds, 0);
    client.set_keep_alive(true);
    client.set_tcp_nodelay(true);
  }

  // Sends with retries. `send` performs one exchange.
  bool Exchange(const std::function<httplib::Result()>& send, HttpReply* out,
                HttpFailure* failure) {
    std::mt19937 rng(std::random_device{}());
    double delay = retry.first_delay_s;
    for (int attempt = 1;; ++attempt) {
      httplib::Result r = send();
      std::string why;
      double wait = delay * std::uniform_real_distribution<double>(0.5, 1.5)(rng);
      if (!r) {
        why = "cannot reach the server: " + httplib::to_string(r.error());
      } else if (r->status == 503) {
        why = "the server is busy (503)";
        const std::string after = r->get_header_value("Retry-After");
        if (!after.empty()) wait = std::max(wait, std::atof(after.c_str()));
      } else {
        out->status = r->status;
        out->body = r->body;
        out->content_type = r->get_header_value("Content-Type");
        out->stats = r->get_header_value("X-Surfdeform-Stats");
        out->timing = r->get_header_value("Server-Timing");
        if (r->status >= 200 && r->status < 300) return true;
        // 4xx: the request itself is wrong; 5xx other than 503: not retried
        // either (the server failed on this request, repeating it will too).
        failure->unreachable = false;
        failure->status = r->status;
        failure->message = ProblemMessage(r->status, r->body);
        failure->code = ProblemCode(r->body);
        return false;
      }
      if (attempt >= retry.attempts) {
        failure->unreachable = !r;
        failure->status = r ? r->status : 0;
        failure->message = r ? ProblemMessage(r->status, r->body) : why;
        if (!r) failure->message += " (after " + std::to_string(attempt) + " attempts)";
        return false;
      }
      wait = std::min(wait, retry.max_delay_s);
      if (on_retry) on_retry(attempt, why, wait);
      std::this_thread::sleep_for(std::chrono::duration<double>(wait));
      delay = std::min(delay * 2.0, retry.max_delay_s);
    }
  }

  httplib::Client client;
  RetryPolicy retry;
  std::function<void(int, const std::string&, double)> on_retry;
};

ApiClient::ApiClient(std::string server, RetryPolicy retry, double timeout_s)
    : impl_(std::make_unique<Impl>(server, retry, timeout_s)), server_(std::move(server)) {}
ApiClient::~ApiClient() = default;

void ApiClient::set_on_retry(std::function<void(int, const std::string&, double)> f) {
  impl_->on_retry = std::move(f);
}

bool ApiClient::Get(const std::string& path, HttpReply* out, HttpFailure* failure) {
  return impl_->Exchange([&] { return impl_->client.Get(path); }, out, failure);
}

bool ApiClient::PostJson(const std::string& path, const std::string& json, HttpReply* out,
                         HttpFailure* failure, const std::string& accept) {
  httplib::Headers headers = RoutingHeaders(json);
  if (!accept.empty()) headers.emplace("Accept", accept);
  return impl_->Exchange(
      [&] { return impl_->client.Post(path, headers, json, "application/json"); }, out, failure);
}

bool ApiClient::PostModel(const std::string& mesh, const std::string& model_id, HttpReply* out,
                          HttpFailure* failure) {
  const httplib::Headers headers = {{"X-Surfdeform-Model-Id", model_id}};
  return impl_->Exchange(
      [&] { return impl_->client.Post("/v1/models", headers, mesh, "application/octet-stream"); },
      out, failure);
}

}  // namespace surfdeform::cli
