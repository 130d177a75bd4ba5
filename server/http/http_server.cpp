// The HTTP server: the route table and its handlers, and the hooks httplib
// calls around them (pre- and post-routing, errors, exceptions, the access
// log). Over ~600 lines because they share one HttpServer::Impl (the service,
// the metrics, the request contexts, the options) and read as one flow; what
// does not need that state lives beside it: the body forms
// (deform_request.*), the request's id, clock and headers
// (request_basics.*), its context (request_context.hpp), the listener and
// the in-memory connection.
#include "http/http_server.hpp"

#include <httplib.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>
#include <thread>
#include <unordered_map>

#include <time.h>

#include "base/fault_points.hpp"
#include "http/connection_gate.hpp"
#include "http/deform_request.hpp"
#include "http/embedded_files.hpp"
#include "http/listener.hpp"
#include "http/log_writer.hpp"
#include "http/memory_stream.hpp"
#include "http/problem.hpp"
#include "http/request_basics.hpp"
#include "http/request_context.hpp"
#include "http/request_guard.hpp"
#include "proto/content_hash.hpp"
#include "service/content_coding.hpp"

namespace surfdeform::http {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct HttpServer::Impl {
  Impl(Service& s, HttpOptions o)
      : service(s),
        options(std::move(o)),
        log_writer(static_cast<size_t>(std::max(1, options.log_queue_lines))) {}

  Service& service;
  const HttpOptions options;
  Listener server;
  Metrics metrics;
  RequestContexts contexts;
  std::atomic<bool> ready{true};
  // Raised when the server stops with requests still at work: they stop at
  // their next checkpoint. Each connection's cancel flag is under it.
  CancelFlag stopping;
  LogWriter log_writer;
  int bound_port = 0;

  // One row per route: the method, httplib's pattern (a regex where the path
  // carries an id), the path template that names it in metrics and logs,
  // and its handler. Registration, the methods a path allows (405, OPTIONS)
  // and the metrics labels all come from this table (kRoutes, below).
  using Handler = void (Impl::*)(RequestContext&, const httplib::Request&, httplib::Response&);
  // A handler that reads its own body (POST /v1/deform, /v1/animate).
  using BodyHandler = void (Impl::*)(RequestContext&, const httplib::Request&, httplib::Response&,
                                     const httplib::ContentReader&);
  struct Route {
    const char* method;
    const char* pattern;
    const char* label;
    Handler handler;           // or
    BodyHandler body_handler;  // for a route that reads its own body
  };
  static const Route kRoutes[];
  static const size_t kRouteCount;

  // The route label of a path ("other" for none) and, in *allow, the methods
  // its routes take, with OPTIONS (empty for none).
  static std::string RouteOf(const std::string& path, std::string* allow = nullptr) {
    static const std::vector<std::regex> patterns = [] {
      std::vector<std::regex> p;
      for (size_t k = 0; k < kRouteCount; ++k) p.emplace_back(kRoutes[k].pattern);
      return p;
    }();
    std::string label = "other", methods;
    for (size_t k = 0; k < kRouteCount; ++k) {
      if (!std::regex_match(path, patterns[k])) continue;
      if (label == "other") label = kRoutes[k].label;
      methods += std::string(kRoutes[k].method) + ", ";
    }
    if (allow != nullptr) *allow = methods.empty() ? "" : methods + "OPTIONS";
    return label;
  }

  bool AllowsOrigin(const std::string& origin) const {
    for (const std::string& o : options.allowed_origins) {
      if (o == "*" || o == origin) return true;
    }
    return false;
  }

  void SetCors(const httplib::Request& req, httplib::Response& res) const {
    const std::string origin = req.get_header_value("Origin");
    if (origin.empty() || !AllowsOrigin(origin)) return;
    const bool any = options.allowed_origins.size() == 1 && options.allowed_origins[0] == "*";
    res.set_header("Access-Control-Allow-Origin", any ? "*" : origin);
    if (!any) res.set_header("Vary", "Origin");
    res.set_header("Access-Control-Expose-Headers",
                   "ETag, Server-Timing, X-Request-Id, X-Surfdeform-Stats, Retry-After, Location");
  }

  void Problem(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
               int http_status, const Status& status) {
    res.status = http_status;
    res.set_content(ProblemJson(status, http_status, req.path, ctx.id), kProblemType);
    if (http_status == 503) {
      res.set_header("Retry-After", std::to_string(service.RetryAfterSeconds()));
    }
  }

  void Fail(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
            const Status& status) {
    if (status.code() == ErrorCode::kUnavailable && !faults::Armed(faults::Fault::kSheddingOff)) {
      HoldRefusal();
    }
    const int http_status = HttpStatusOf(status.code());
    if (http_status >= 500 && status.code() != ErrorCode::kUnavailable) {
      // The client reads "internal error" and the request id; the cause is here.
      Log(LogLevel::kError, json{{"event", "internal_error"},
                                 {"request_id", ctx.id},
                                 {"path", req.path},
                                 {"code", ErrorCodeName(status.code())},
                                 {"detail", status.message()}});
    }
    Problem(ctx, req, res, http_status, status);
  }

  // A refusal for overload is answered after a short pause. Load generators
  // and naive clients retry at once whatever Retry-After says; answered at
  // once, their retries (thousands a second) take the cores from the
  // requests being served. Paused, each connection costs a few refusals a
  // second; the pause holds a worker thread, not a core.
  static void HoldRefusal() { std::this_thread::sleep_for(std::chrono::milliseconds(250)); }

  void Send(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
            const Reply& reply, int http_status = 200) {
    const std::string etag = "\"" + reply.etag + "\"";
    res.set_header("ETag", etag);
    if (!reply.timings.empty()) res.set_header("Server-Timing", ServerTiming(reply.timings));
    if (reply.immutable) {
      res.set_header("Cache-Control", "public, max-age=31536000, immutable");
      res.set_header("Vary", "Accept");
    }
    if (const std::string stats = StatsHeaderText(reply); !stats.empty()) {
      res.set_header("X-Surfdeform-Stats", ToAscii(stats));
    }
    ctx.cache_hit = reply.cache_hit;
    // An answer the client holds (the service decided, for POST /v1/deform
    // before any work), or a GET of the representation it holds.
    if (reply.not_modified ||
        (req.method == "GET" && req.get_header_value("If-None-Match") == etag)) {
      res.status = 304;
      return;
    }
    res.status = http_status;
    const bool gzip = AcceptsGzip(req.get_header_value("Accept-Encoding"));
    if (!reply.gzip_body.empty()) {
      res.set_header("Vary", "Accept-Encoding");
      if (gzip) {
        // Another representation, another entity tag (the service's
        // If-None-Match takes both).
        res.headers.erase("ETag");
        res.set_header("ETag", "\"" + reply.etag + "-gzip\"");
        res.set_header("Content-Encoding", "gzip");
        res.set_content(reply.gzip_body, reply.content_type.c_str());
        EncodedAlready(req);
        return;
      }
    } else if (gzip && HttplibWouldGzip(reply.content_type)) {
      // What httplib would gzip at its default level, at level 1 (the
      // entity tag stays, as httplib left it).
      std::string packed = GzipFast(reply.body);
      if (!packed.empty()) {
        res.set_header("Vary", "Accept-Encoding");
        res.set_header("Content-Encoding", "gzip");
        res.set_content(std::move(packed), reply.content_type.c_str());
        EncodedAlready(req);
        return;
      }
    }
    res.set_content(reply.body, reply.content_type.c_str());
  }

  // The reply's body is encoded already: httplib, which reads the request's
  // Accept-Encoding after the handler, must not encode it again.
  static void EncodedAlready(const httplib::Request& req) {
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
  }

  // A service call's answer: its problem, or its reply.
  void Answer(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
              const Result<Reply>& reply) {
    if (!reply.ok()) return Fail(ctx, req, res, reply.status());
    Send(ctx, req, res, *reply);
  }

  // The answer of a call that creates a resource by content id: 201 with its
  // Location (`collection` + the id), or 200 for one that existed.
  void Created(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
               const Result<Reply>& reply, const char* collection, std::string Reply::*id) {
    if (!reply.ok()) return Fail(ctx, req, res, reply.status());
    res.set_header("Location", collection + (*reply).*id);
    Send(ctx, req, res, *reply, reply->cache_hit ? 200 : 201);
  }

  // A request's context, its id and its count in flight, from the moment
  // its head is parsed (or found unparsable).
  RequestContext& BeginRequest(const httplib::Request& req, httplib::Response& res) {
    RequestContext& ctx = contexts.Begin(req);
    ctx.active = true;
    ctx.start = Clock::now();
    ctx.cpu_start = ThreadCpuSeconds();
    const std::string given = req.get_header_value("X-Request-Id");
    ctx.id = IsSafeRequestId(given) ? given : NewRequestId();
    // The connection's flag (raised when its client hangs up), or outside
    // the gate (ServeBytes) the server's own.
    const CancelFlag* connection = connection_phase::Cancel();
    ctx.cancel = connection != nullptr ? connection : &stopping;
    metrics.RequestStarted();
    res.set_header("X-Request-Id", ctx.id);
    return ctx;
  }

  // Before the body is read: request id, CORS preflight, framing checks.
  httplib::Server::HandlerResponse PreRouting(const httplib::Request& req, httplib::Response& res) {
    RequestContext& ctx = BeginRequest(req, res);
    // An absolute-form target (RFC 9112 section 3.2.2: "GET http://host/x")
    // names the resource by its path, as an origin-form one does. The
    // Request is not const where httplib made it; only its handler
    // interface is, and routing reads the path after this.
    StripSchemeAndAuthority(const_cast<httplib::Request&>(req).path);
    // Content-Length is parsed once, by the framing checks; the watchdog and
    // the body readers use what they found.
    std::optional<Rejection> rejection =
        CheckFraming(req, service.limits().max_body_bytes, &ctx.body_length);
    if (!rejection) rejection = CheckPath(req.path);
    connection_phase::HeadIn(ctx.body_length);
    // The test build's fault points (base/fault_points.hpp); a no-op in production.
    faults::Disarm();
    if (req.has_header("X-Surfdeform-Fault")) {
      faults::ArmForThisThread(req.get_header_value("X-Surfdeform-Fault"));
    }
    SetCors(req, res);
    // Range requests are ignored (RFC 9110 allows it): httplib 0.11.4 would
    // multiply overlapping ranges into a huge response.
    const_cast<httplib::Request&>(req).ranges.clear();
    const_cast<httplib::Request&>(req).headers.erase("Range");
    // Brotli is never offered: httplib 0.11.4 compresses at quality 11,
    // 0.7 s of a worker for a 0.5 MB JSON reply (gzip: 30 ms), and seconds
    // for a large sheet, which a short request could ask for again and
    // again. gzip stays.
    WithoutBrotli(&const_cast<httplib::Request&>(req).headers);

    if (rejection) {
      metrics.Rejected(std::to_string(rejection->http_status));
      // The body was not read, so the connection cannot carry another
      // request: httplib 0.11.4 decides keep-alive before routing, so the
      // response goes out through a content provider that ends the
      // connection once the body is written (returning false).
      auto body = std::make_shared<std::string>(
          ProblemJson(rejection->status, rejection->http_status, req.path, ctx.id));
      res.status = rejection->http_status;
      res.set_header("Connection", "close");
      res.set_content_provider(body->size(), kProblemType,
                               [body](size_t offset, size_t length, httplib::DataSink& sink) {
                                 sink.write(body->data() + offset, length);
                                 return false;
                               });
      // The logger does not run for a connection ended this way.
      Finish(ctx, req, res.status, body->size());
      connection_phase::Responding(body->size());
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.method == "OPTIONS") {
      res.status = 204;
      std::string allow;
      RouteOf(req.path, &allow);
      res.set_header("Allow", allow.empty() ? "OPTIONS" : allow);
      if (req.has_header("Origin") && AllowsOrigin(req.get_header_value("Origin"))) {
        res.set_header("Access-Control-Allow-Methods", "GET, POST, OPTIONS");
        res.set_header("Access-Control-Allow-Headers",
                       "Content-Type, Accept, If-None-Match, X-Request-Id, X-Surfdeform-Params, "
                       "X-Surfdeform-Surface-Id, X-Surfdeform-Model-Id");
        res.set_header("Access-Control-Max-Age", "600");
      }
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  }

  // After every route: the headers every response carries. An ETag over the
  // body where the route set none (the body is deterministic for the same
  // state), and the total time in Server-Timing.
  void PostRouting(const httplib::Request& req, httplib::Response& res) {
    const RequestContext& ctx = contexts.Of(req);
    connection_phase::Responding(res.body.size());
    // Ranges are not served (PreRouting): httplib's file handler would
    // still say 206 over the whole file, with no Content-Range.
    if (res.status == 206 && !res.has_header("Content-Range")) res.status = 200;
    if (res.status == 200 && !res.body.empty() && !res.has_header("ETag")) {
      const std::string etag = "\"" + proto::Sha256Hex(res.body, 32) + "\"";
      res.set_header("ETag", etag);
      if (req.method == "GET" && req.get_header_value("If-None-Match") == etag) {
        res.status = 304;  // no body, and no length of one
        res.body.clear();
        res.headers.erase("Content-Length");
        res.headers.erase("Content-Type");
      }
    }
    if (ctx.active) {
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - ctx.start).count();
      char total[48];
      std::snprintf(total, sizeof total, "total;dur=%.3f", ms);
      std::string timing = res.get_header_value("Server-Timing");
      res.headers.erase("Server-Timing");
      res.set_header("Server-Timing", timing.empty() ? std::string(total) : timing + ", " + total);
    }
  }

  // httplib's own errors (404, 400 from its parser, 413 from its payload
  // limit) and handlers that set an error status without a body.
  void OnError(const httplib::Request& req, httplib::Response& res) {
    if (res.get_header_value("Content-Type") == kProblemType) return;
    RequestContext& ctx = contexts.Of(req);
    if (!ctx.active) {
      // httplib refused the request line or a header before pre-routing
      // (pipelined behind a request the gate passed; the gate refuses such
      // heads itself): nothing after it can be framed.
      BeginRequest(req, res);
      connection_phase::CloseAfterResponse();
      if (res.status == 416) {
        return Problem(ctx, req, res, 416,
                       Status(ErrorCode::kMalformed,
                              "the Range header could not be parsed (ranges are not served: "
                              "send the request without one)",
                              "Range"));
      }
      if (res.status == 414) {  // httplib knows only that it is longer
        return Problem(ctx, req, res, 414, RequestLineTooLong(kMaxRequestLineBytes + 1).status);
      }
      return Problem(ctx, req, res, res.status,
                     Status(ErrorCode::kMalformed,
                            "the request line or a header field could not be parsed (METHOD TARGET "
                            "HTTP/1.1, then NAME: VALUE lines of at most " +
                                std::to_string(kMaxHeaderLineBytes) + " bytes, all ending in CRLF)",
                            "request-line"));
    }
    if (res.status != 404 && res.status != 405) {
      // httplib stopped reading the body (a multipart body it could not
      // parse, a length it refused): the rest of it is not a request.
      connection_phase::CloseAfterResponse();
    }
    if (res.status == 400 && req.is_multipart_form_data()) {
      return Problem(ctx, req, res, 400,
                     Status(ErrorCode::kMalformed,
                            "the multipart/form-data body could not be parsed: each part needs "
                            "the boundary of the Content-Type header, a Content-Disposition "
                            "with a name, and a blank line before its content; the body ends "
                            "with the boundary followed by \"--\"",
                            "body"));
    }
    std::string allow;
    const std::string route = RouteOf(req.path, &allow);
    if (res.status == 404 && route != "other") {
      res.set_header("Allow", allow);
      Problem(ctx, req, res, 405,
              Status(ErrorCode::kMalformed,
                     req.method + " is not allowed on " + req.path + "; allowed: " + allow));
      return;
    }
    const int status = res.status;
    std::string detail = status == 404 ? "no such resource: see /openapi.yaml for the routes"
                                       : std::string(StatusTitle(status));
    Problem(ctx, req, res, status,
            Status(status >= 500 ? ErrorCode::kInternal : ErrorCode::kMalformed, detail));
  }

  void OnException(const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    RequestContext& ctx = contexts.Of(req);
    std::string what = "unknown exception";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    Log(LogLevel::kError,
        json{{"event", "exception"}, {"request_id", ctx.id}, {"path", req.path}, {"what", what}});
    res.headers.erase("X-Surfdeform-Stats");
    Problem(ctx, req, res, 500, Status(ErrorCode::kInternal, "internal error"));
  }

  // Never waits for the log's reader (log_writer.hpp).
  void Log(LogLevel level, const json& line) {
    if (level < options.log_level) return;
    log_writer.Write(line.dump(-1, ' ', true, json::error_handler_t::replace));
  }

  void AccessLog(const httplib::Request& req, const httplib::Response& res) {
    RequestContext& ctx = contexts.Of(req);
    // Not counted already (by an early rejection, whose connection ends
    // without the logger).
    if (!ctx.finished) Finish(ctx, req, res.status, res.body.size());
    contexts.End(req);
  }

  // Metrics and the access log line, once per request.
  void Finish(RequestContext& ctx, const httplib::Request& req, int status, size_t bytes_out) {
    double ms = 0.0;
    if (ctx.active) {
      ms = std::chrono::duration<double, std::milli>(Clock::now() - ctx.start).count();
      metrics.RequestFinished(RouteOf(req.path), req.method, status, ms / 1000.0,
                              ThreadCpuSeconds() - ctx.cpu_start, req.body.size() + ctx.bytes_in,
                              bytes_out);
    }
    const LogLevel level = status >= 500   ? LogLevel::kError
                           : status >= 400 ? LogLevel::kWarn
                                           : LogLevel::kInfo;
    Log(level, json{{"event", "request"},
                    {"request_id", ctx.id},
                    {"method", req.method},
                    {"path", req.path},
                    {"status", status},
                    {"bytes_in", req.body.size() + ctx.bytes_in},
                    {"bytes_out", bytes_out},
                    {"duration_ms", ms},
                    {"cache_hit", ctx.cache_hit},
                    {"remote", req.remote_addr}});
    ctx.finished = true;
    faults::Disarm();
  }

  // POST /v1/deform, /v1/animate and /v1/models read their own bodies: past
  // the work-in-flight limit and its queue, the body is read and dropped as
  // it arrives (no copy, no parse) and the request refused, so that a
  // refusal costs a small part of what serving it would, and the connection
  // stays usable (checklist 26).
  using ServiceCall = Result<Reply> (Service::*)(const DeformRequest&);
  void DeformRoute(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                   const httplib::ContentReader& reader) {
    WithBody(ctx, req, res, reader,
             [&](const DeformBody& b) { Deform(ctx, req, res, b, &Service::Deform); });
  }
  void AnimateRoute(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                    const httplib::ContentReader& reader) {
    WithBody(ctx, req, res, reader,
             [&](const DeformBody& b) { Deform(ctx, req, res, b, &Service::Animate); });
  }
  void UploadFontRoute(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                       const httplib::ContentReader& reader) {
    WithBody(ctx, req, res, reader, [&](const DeformBody& b) {
      ThrowIfArmed();
      const Result<std::string_view> font = UploadedMesh(req, b);  // the raw body or one part
      if (!font.ok()) return Fail(ctx, req, res, font.status());
      Created(ctx, req, res, service.UploadFont(*font, ctx.cancel), "/v1/fonts/", &Reply::model_id);
    });
  }
  void UploadModelRoute(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                        const httplib::ContentReader& reader) {
    WithBody(ctx, req, res, reader, [&](const DeformBody& b) { UploadModel(ctx, req, res, b); });
  }
  template <class Use>
  void WithBody(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                const httplib::ContentReader& reader, const Use& use) {
    const bool multipart = req.is_multipart_form_data();
    DeformBody body;
    bool read = false;
    // The test build's shedding_off fault sends such a request on, as if
    // there were no early refusal (base/fault_points.hpp).
    if (service.Saturated() && !faults::Armed(faults::Fault::kSheddingOff)) {
      auto drop = [&ctx](const char*, size_t n) {
        ctx.bytes_in += n;
        connection_phase::BodyProgress(ctx.bytes_in);
        return true;
      };
      read = multipart ? reader([](const httplib::MultipartFormData&) { return true; }, drop)
                       : reader(drop);
      if (!read) return;  // the connection failed: nobody to answer
      connection_phase::Handling();
      metrics.Rejected("overload");
      return Fail(ctx, req, res,
                  Status(ErrorCode::kUnavailable,
                         "the server is busy: every slot is taken and the queue is full; retry "
                         "after the Retry-After seconds"));
    }
    if (multipart) {
      httplib::MultipartFormData* part = nullptr;
      read = reader(
          [&](const httplib::MultipartFormData& header) {
            part = &body.parts.emplace(header.name, header)->second;
            return true;
          },
          [&](const char* data, size_t n) {
            ctx.bytes_in += n;
            connection_phase::BodyProgress(ctx.bytes_in);
            if (part != nullptr) part->content.append(data, n);
            return true;
          });
    } else {
      body.raw.reserve(std::min(service.limits().max_body_bytes, ctx.body_length));
      read = reader([&](const char* data, size_t n) {
        ctx.bytes_in += n;
        connection_phase::BodyProgress(ctx.bytes_in);
        body.raw.append(data, n);
        return true;
      });
    }
    if (!read) return;  // httplib answers (or the connection is gone)
    connection_phase::Handling();
    use(body);
  }

  // POST /v1/models: the mesh file as the raw body or a multipart "mesh" part.
  void UploadModel(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                   const DeformBody& body) {
    ThrowIfArmed();
    const Result<std::string_view> mesh = UploadedMesh(req, body);
    if (!mesh.ok()) return Fail(ctx, req, res, mesh.status());
    Created(ctx, req, res,
            service.UploadModel(*mesh, req.get_header_value("X-Surfdeform-Model-Id"), ctx.cancel),
            "/v1/models/", &Reply::model_id);
  }

  // POST /v1/deform and POST /v1/animate: one mesh and its parameters, in the
  // same body forms.
  void Deform(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
              const DeformBody& body, ServiceCall call) {
    ThrowIfArmed();  // the body is in: the connection can go on
    Result<DeformRequest> d = DeformRequestOf(req, body);
    if (!d.ok()) return Fail(ctx, req, res, d.status());
    d->cancel = ctx.cancel;
    Answer(ctx, req, res, (service.*call)(*d));
  }

  // The viewer's static files (GET and HEAD only; httplib refuses paths
  // that leave the mounted folders). Returns false when there is no viewer.
  bool MountViewer() {
    const std::string& root = options.web_root;
    if (root.empty() || !std::filesystem::is_directory(root + "/public")) return false;
    for (const auto& [ext, type] : std::initializer_list<std::pair<const char*, const char*>>{
             {"js", "text/javascript"},
             {"mjs", "text/javascript"},
             {"wasm", "application/wasm"},
             {"json", "application/json"},
             {"css", "text/css"},
             {"html", "text/html; charset=utf-8"},
             {"svg", "image/svg+xml"},
             {"ply", "application/octet-stream"},
             {"glb", "model/gltf-binary"},
             {"drc", "application/octet-stream"}}) {
      server.set_file_extension_and_mimetype_mapping(ext, type);
    }
    httplib::Headers cache = {{"Cache-Control", "no-cache"}};
    bool ok = server.set_mount_point("/", root + "/public", cache);
    ok = ok && server.set_mount_point("/samples", root + "/samples", cache);
    for (const char* package : {"three", "meshoptimizer"}) {
      const std::string dir = root + "/node_modules/" + package;
      if (std::filesystem::is_directory(dir)) {
        ok = ok && server.set_mount_point(std::string("/vendor/") + package, dir, cache);
      }
    }
    return ok;
  }

  void Routes() {
    // A mounted viewer serves GET / from its files first; the built-in page
    // stands in where it has none.
    MountViewer();
    for (size_t k = 0; k < kRouteCount; ++k) {
      const Route& route = kRoutes[k];
      if (route.body_handler != nullptr) {
        server.Post(route.pattern, [this, h = route.body_handler](
                                       const httplib::Request& req, httplib::Response& res,
                                       const httplib::ContentReader& reader) {
          (this->*h)(contexts.Of(req), req, res, reader);
        });
        continue;
      }
      auto handler = [this, h = route.handler](const httplib::Request& req,
                                               httplib::Response& res) {
        connection_phase::Handling();  // httplib has read the body
        ThrowIfArmed();
        (this->*h)(contexts.Of(req), req, res);
      };
      if (std::string(route.method) == "GET") {
        server.Get(route.pattern, handler);
      } else {
        server.Post(route.pattern, handler);
      }
    }
  }

  // The test build's "handler that throws" (base/fault_points.hpp): its text
  // must reach the log only, never the client.
  static void ThrowIfArmed() {
    if (faults::Armed(faults::Fault::kHandlerThrows)) {
      throw std::runtime_error("injected fault: internal detail /srv/secret");
    }
  }

  void Index(RequestContext&, const httplib::Request&, httplib::Response& res) {
    res.set_content(kIndexHtml, "text/html; charset=utf-8");
  }
  void Healthz(RequestContext&, const httplib::Request&, httplib::Response& res) {
    res.set_content("{\"status\":\"ok\"}", "application/json");
  }
  void Readyz(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    if (ready.load()) {
      res.set_content("{\"ready\":true}", "application/json");
    } else {
      Problem(ctx, req, res, 503,
              Status(ErrorCode::kUnavailable, "the server is shutting down (draining)"));
    }
  }
  void MetricsText(RequestContext&, const httplib::Request&, httplib::Response& res) {
    ServerStats stats;
    stats.surfaces = service.cache_stats();
    stats.shared = service.shared_tier_stats();
    stats.admission = service.admission_stats();
    stats.connections = server.connection_stats();
    stats.placements = service.placement_memo_stats();
    stats.models = service.model_cache_stats();
    stats.answers = service.answer_cache_stats();
    stats.edit_paths = service.edit_paths_stats();
    stats.log_lines_dropped = log_writer.dropped();
    res.set_content(metrics.Render(stats), "text/plain; version=0.0.4");
  }
  void OpenApi(RequestContext&, const httplib::Request&, httplib::Response& res) {
    res.set_content(kOpenApiYaml, "application/yaml");
  }
  void Info(RequestContext&, const httplib::Request&, httplib::Response& res) {
    // The service's limits and those of the HTTP edge (request_guard.hpp).
    json info = service.InfoJson();
    json& limits = info["limits"];
    limits["max_request_line_bytes"] = kMaxRequestLineBytes;
    limits["max_header_line_bytes"] = kMaxHeaderLineBytes;
    limits["max_header_fields"] = kMaxHeaderCount;
    limits["max_head_bytes"] = GateOptions{}.max_head_bytes;
    limits["max_bodies_per_address"] = options.max_bodies_per_address;
    limits["max_body_buffer_bytes"] = options.max_body_buffer_bytes;
    limits["max_body_seconds"] = options.max_body_seconds;
    limits["max_output_buffer_bytes"] = options.max_output_buffer_bytes;
    limits["min_transfer_bytes_per_s"] = options.min_transfer_bytes_per_s;
    res.set_content(info.dump(), "application/json");
  }
  // Whether the request's body is JSON; else it is answered with a 415
  // naming `route` and the type it got.
  bool TakesJson(RequestContext& ctx, const httplib::Request& req, httplib::Response& res,
                 const char* route) {
    const std::string type = req.get_header_value("Content-Type");
    if (type.rfind("application/json", 0) == 0) return true;
    Fail(ctx, req, res,
         Status(ErrorCode::kUnsupportedFormat,
                std::string(route) + " takes application/json, got \"" + type.substr(0, 64) + "\"",
                "Content-Type"));
    return false;
  }
  void CreateSurface(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    if (!TakesJson(ctx, req, res, "POST /v1/surfaces")) return;
    Created(ctx, req, res,
            service.CreateSurface(req.body, req.get_param_value("field"), ctx.cancel),
            "/v1/surfaces/", &Reply::surface_id);
  }
  void MakeText(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    if (!TakesJson(ctx, req, res, "POST /v1/text")) return;
    Answer(ctx, req, res, service.MakeText(req.body, req.get_header_value("Accept"), ctx.cancel));
  }
  void MakePart(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    if (!TakesJson(ctx, req, res, "POST /v1/parts")) return;
    Answer(ctx, req, res,
           service.MakePart(req.body, req.get_header_value("Accept"), req.get_param_value("report"),
                            ctx.cancel));
  }
  void MapOnSurface(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    if (!TakesJson(ctx, req, res, "POST /v1/surfaces/{id}/map")) return;
    Answer(ctx, req, res, service.MapOnSurface(req.matches[1].str(), req.body, ctx.cancel));
  }
  void SurfaceSvg(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res, service.GetSurfaceSvg(req.matches[1].str()));
  }
  void SurfaceField(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res,
           service.GetSurfaceField(req.matches[1].str(), req.get_param_value("n"),
                                   req.get_header_value("Accept")));
  }
  void Fonts(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res, service.ListFonts());
  }
  void FontSummary(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res, service.GetFont(req.matches[1].str()));
  }
  void ModelSummary(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res, service.GetModel(req.matches[1].str()));
  }
  void SurfaceSheet(RequestContext& ctx, const httplib::Request& req, httplib::Response& res) {
    Answer(ctx, req, res, service.GetSurface(req.matches[1].str()));
  }
};

const HttpServer::Impl::Route HttpServer::Impl::kRoutes[] = {
    {"GET", "/", "/", &Impl::Index, nullptr},
    {"GET", "/healthz", "/healthz", &Impl::Healthz, nullptr},
    {"GET", "/readyz", "/readyz", &Impl::Readyz, nullptr},
    {"GET", "/metrics", "/metrics", &Impl::MetricsText, nullptr},
    {"GET", "/openapi.yaml", "/openapi.yaml", &Impl::OpenApi, nullptr},
    {"GET", "/v1/info", "/v1/info", &Impl::Info, nullptr},
    {"POST", "/v1/surfaces", "/v1/surfaces", &Impl::CreateSurface, nullptr},
    {"GET", R"(/v1/surfaces/([^/]+)/flat\.svg)", "/v1/surfaces/{id}/flat.svg", &Impl::SurfaceSvg,
     nullptr},
    {"GET", R"(/v1/surfaces/([^/]+)/field)", "/v1/surfaces/{id}/field", &Impl::SurfaceField,
     nullptr},
    {"GET", R"(/v1/surfaces/([^/]+))", "/v1/surfaces/{id}", &Impl::SurfaceSheet, nullptr},
    {"POST", "/v1/deform", "/v1/deform", nullptr, &Impl::DeformRoute},
    {"POST", R"(/v1/surfaces/([^/]+)/map)", "/v1/surfaces/{id}/map", &Impl::MapOnSurface, nullptr},
    {"POST", "/v1/animate", "/v1/animate", nullptr, &Impl::AnimateRoute},
    {"POST", "/v1/models", "/v1/models", nullptr, &Impl::UploadModelRoute},
    {"GET", R"(/v1/models/([^/]+))", "/v1/models/{id}", &Impl::ModelSummary, nullptr},
    {"GET", "/v1/fonts", "/v1/fonts", &Impl::Fonts, nullptr},
    {"POST", "/v1/text", "/v1/text", &Impl::MakeText, nullptr},
    {"POST", "/v1/parts", "/v1/parts", &Impl::MakePart, nullptr},
    {"POST", "/v1/fonts", "/v1/fonts", nullptr, &Impl::UploadFontRoute},
    {"GET", R"(/v1/fonts/([^/]+))", "/v1/fonts/{id}", &Impl::FontSummary, nullptr},
};
const size_t HttpServer::Impl::kRouteCount = std::size(HttpServer::Impl::kRoutes);

HttpServer::HttpServer(Service& service, HttpOptions options)
    : impl_(std::make_unique<Impl>(service, std::move(options))) {
  Impl* s = impl_.get();
  httplib::Server& server = s->server;
  const int workers = std::max(2, s->options.worker_threads);
  GateOptions gate;
  gate.workers = workers;
  gate.max_body_bytes = service.limits().max_body_bytes;
  gate.head_timeout = std::chrono::milliseconds(std::max(1, s->options.head_timeout_ms));
  gate.idle_timeout = std::chrono::seconds(s->options.keep_alive_timeout_s);
  gate.min_bytes_per_s = std::max(1, s->options.min_transfer_bytes_per_s);
  gate.transfer_grace = std::chrono::seconds(std::max(0, s->options.transfer_grace_s));
  gate.max_requests_per_connection = std::max(1, s->options.keep_alive_max_requests);
  gate.read_timeout = std::chrono::seconds(s->options.read_timeout_s);
  gate.write_timeout = std::chrono::seconds(s->options.write_timeout_s);
  gate.send_buffer_bytes = std::max(0, s->options.send_buffer_bytes);
  gate.max_bodies_per_address = std::max(1, s->options.max_bodies_per_address);
  gate.max_body_buffer_bytes = s->options.max_body_buffer_bytes;
  gate.max_body_time = std::chrono::seconds(std::max(1, s->options.max_body_seconds));
  gate.max_output_buffer_bytes = s->options.max_output_buffer_bytes;
  gate.stopping = &s->stopping;
  s->server.UseGate(gate);
  server.set_payload_max_length(service.limits().max_body_bytes);
  // httplib's default sets SO_REUSEPORT on the listening socket: a second
  // server started on a port already served would bind without error, and
  // the kernel would then split connections between the two (with a surface
  // id minted by one unknown to the other). SO_REUSEADDR alone still lets a
  // restart bind while the last run's connections are in TIME_WAIT.
  server.set_socket_options([](socket_t sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  // Without it, a small response waits for the client's delayed ACK (Nagle),
  // tens of milliseconds per request on loopback (bench/service_bench).
  server.set_tcp_nodelay(true);
  server.set_read_timeout(s->options.read_timeout_s, 0);
  server.set_write_timeout(s->options.write_timeout_s, 0);
  server.set_keep_alive_timeout(s->options.keep_alive_timeout_s);
  server.set_keep_alive_max_count(
      static_cast<size_t>(std::max(1, s->options.keep_alive_max_requests)));
  server.set_pre_routing_handler(
      [s](const httplib::Request& req, httplib::Response& res) { return s->PreRouting(req, res); });
  server.set_post_routing_handler(
      [s](const httplib::Request& req, httplib::Response& res) { s->PostRouting(req, res); });
  server.set_error_handler(
      [s](const httplib::Request& req, httplib::Response& res) { s->OnError(req, res); });
  server.set_exception_handler([s](const httplib::Request& req, httplib::Response& res,
                                   std::exception_ptr ep) { s->OnException(req, res, ep); });
  server.set_logger(
      [s](const httplib::Request& req, const httplib::Response& res) { s->AccessLog(req, res); });
  s->Routes();
}

HttpServer::~HttpServer() = default;

bool HttpServer::Bind() {
  Impl& s = *impl_;
  bool ok;
  errno = 0;
  if (s.options.port == 0) {
    s.bound_port = s.server.bind_to_any_port(s.options.host);
    ok = s.bound_port > 0;
  } else {
    ok = s.server.bind_to_port(s.options.host, s.options.port);
    s.bound_port = s.options.port;
  }
  const int bind_errno = errno;
  if (ok) s.server.WidenBacklog(SOMAXCONN);
  if (!ok) {
    std::cerr << "surfdeform: cannot listen on " << s.options.host << ":" << s.options.port;
    if (bind_errno != 0) std::cerr << ": " << std::strerror(bind_errno);
    std::cerr << "\n";
  }
  return ok;
}

int HttpServer::port() const { return impl_->bound_port; }

void HttpServer::Run() { impl_->server.listen_after_bind(); }

void HttpServer::Drain() { impl_->ready.store(false); }

void HttpServer::Stop() { impl_->server.stop(); }

void HttpServer::Cancel() { impl_->stopping.Raise(); }

void HttpServer::Event(const std::string& json_line) { impl_->log_writer.Write(json_line); }

std::string HttpServer::ServeBytes(std::string_view input) {
  MemoryStream stream(input);
  bool closed = false;
  while (!stream.done() && !closed) {
    if (!impl_->server.ServeStream(stream, closed)) break;
  }
  return std::move(stream.output());
}

}  // namespace surfdeform::http
