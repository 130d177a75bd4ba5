// Content-Encoding for answers whose own encoding leaves redundancy (meshopt
// and quantized GLB, plain GLB, OBJ, PLY; not Draco): gzip at zlib's
// fastest level, made with the answer when the request accepts it and kept
// with it. Free of Eigen: the HTTP layer reads Accept-Encoding with it too.
#pragma once

#include <string>
#include <string_view>

namespace surfdeform {

// Whether an Accept-Encoding header accepts gzip (a "gzip", "x-gzip" or "*"
// entry without q=0), RFC 9110 section 12.5.3.
bool AcceptsGzip(std::string_view accept_encoding);

// Whether httplib 0.11.4 would gzip a reply of this type itself where the
// client accepts it (text, JSON, SVG, ...): at zlib's default level, 22 ms
// for the 0.4 MB JSON of a live edit's field, against 3.5 ms at level 1
// (168 KB instead of 153). The HTTP layer gzips these at level 1 instead.
bool HttplibWouldGzip(std::string_view content_type);

// `bytes` as one gzip member at zlib `level` (0-9, or -1 for zlib's
// default; empty on failure).
std::string Gzip(std::string_view bytes, int level);
// At level 1, zlib's fastest.
inline std::string GzipFast(std::string_view bytes) { return Gzip(bytes, 1); }

}  // namespace surfdeform
