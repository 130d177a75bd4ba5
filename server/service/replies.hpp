// Every reply the service writes, built in one place: the JSON bodies (a
// sheet's summary, the sheet, /v1/info), the X-Surfdeform-Stats header of a
// deformation and of an animation, and a deformed mesh encoded as asked.
// Every number written is finite, or the request is refused (kInvalidArgument
// naming the JSON path).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "base/status.hpp"
#include "engine/deform/deform.hpp"
#include "engine/sheet/sheet_field.hpp"
#include "meshio/animation_glb.hpp"
#include "meshio/mesh_import.hpp"
#include "proto/api.hpp"
#include "service/model_store.hpp"
#include "service/reply.hpp"
#include "service/reply_stats.hpp"
#include "service/service_limits.hpp"
#include "service/surface_store.hpp"

namespace surfdeform {

// JSON text; invalid UTF-8 in strings replaced, not thrown on.
std::string Dump(const nlohmann::json& j);

// The JSON path of the first number in `j` that is not finite ("" if none):
// nlohmann writes such a number as null, which a client would read as
// "absent" or choke on.
std::string FirstNonFiniteNumber(const nlohmann::json& j, const std::string& path = "");

// `j` as text, refused where a number in it is not finite; `what` names it
// in the error ("reply", "statistics").
Result<std::string> DumpFinite(const nlohmann::json& j, std::string_view what);
// That error: the number at path `at` of `what` is not finite.
Status NonFiniteNumber(std::string_view what, const std::string& at);

// The X-Surfdeform-Stats header's content, finite (else kInvalidArgument
// naming the number) and bounded. Header lines have limits on the way:
// cpp-httplib's clients (the CLI) read at most 8 KB a line, and nginx fails a
// response whose headers outgrow proxy_buffer_size (4 KB by default) with
// 502. The per-item lists ("each": a rigid model's parts, an animation's
// frames; "clusters": a text's) are cut to their first items, longest first,
// until the text fits kMaxStatsHeaderBytes (as StatsJsonText writes it);
// "each_omitted" ("clusters_omitted") beside a list counts what was cut.
inline constexpr size_t kMaxStatsHeaderBytes = 2048;
Result<nlohmann::json> BoundedStats(nlohmann::json stats);

// `stats`, when their numbers are all finite; else kInvalidArgument naming
// the first that is not. A reply's stats are checked so when it is made.
Result<std::shared_ptr<const ReplyStats>> CheckedStats(std::shared_ptr<const ReplyStats> stats);

// A reply of these bytes: its media type, and its ETag (`etag`, else a
// digest of the bytes).
Reply BytesReply(std::string body, std::string content_type, std::string etag = {});

// A JSON reply: the body (finite numbers only), its media type and ETag.
Result<Reply> JsonReply(const nlohmann::json& body);

// POST /v1/surfaces's reply: the id, the grid, the method, the quality.
nlohmann::json SheetSummary(const StoredSurface& s, bool cached);
// GET /v1/surfaces/{id}: the summary, the canonical request, and every
// sample's surface point and flat position.
nlohmann::json SheetJson(const StoredSurface& s);

// POST /v1/models's reply and GET /v1/models/{id}: the id, the file's
// format and size, the imported counts and bounds, and the axis that
// "up": "auto" resolves to (placement.hpp's rule), with why.
nlohmann::json ModelSummary(const StoredModel& m);

// Where and how long uploads and flattened surfaces are kept (the second
// level's Retention): for upload replies ("kept") and GET /v1/info.
nlohmann::json RetentionJson(const Retention& kept);

// How a GLB in `format` is encoded for these output options.
GlbEncoding GlbEncodingOf(const proto::OutputOptions& output, proto::OutputFormat format);

// How the service encodes an answer beyond what the request asks: the
// threads its ticket allows, where a Draco GLB is cut into pieces, and a
// meshopt answer's vertex order when it keeps one.
struct EncodeContext {
  // The answer's ETag when its key names it (kept answers); else the body's
  // digest is taken.
  std::string etag;
  int threads = 1;
  size_t glb_split_vertices = 0;
  std::shared_ptr<const MeshoptOrder> meshopt_order;
  std::string object_name = "surfdeform";  // a 3MF's object
};

// A deformed mesh encoded as asked, and the reply around it: `timings` gain
// the encoding's; a GLB's stats its compression (and pieces, when cut).
Result<Reply> MeshReply(const Mesh& mesh, const proto::OutputOptions& output,
                        proto::OutputFormat format, const ImportedMesh& imported, bool hit,
                        std::vector<Timing> timings, std::shared_ptr<EncodedMeshStats> stats,
                        const EncodeContext& encode = {});

// An answer served from the kept ones: its stats as it was made, written
// with "answer_kept" and "cached" (nothing was flattened for it) true
// (StatsHeaderText), and no timings of the work it did not do.
void MarkKept(Reply* reply);

// 304 for an answer whose ETag the request's If-None-Match names.
Reply NotModified(std::string etag);

// GET /v1/info: the limits, where uploads are kept, the formats, every
// named choice of the request.
nlohmann::json InfoJson(const ServiceLimits& limits, const Retention& kept);
// The limits on fonts and texts (GET /v1/info's "font_limits", GET /v1/fonts).
nlohmann::json FontLimitsJson(const FontLimits& limits);

}  // namespace surfdeform
