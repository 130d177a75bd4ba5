#include "service/content_coding.hpp"

#include <zlib.h>

#include "base/header_lists.hpp"

namespace surfdeform {

bool AcceptsGzip(std::string_view header) {
  return AnyHeaderListItem(header, [](const HeaderListItem& item) {
    return !item.refused && (EqualsIgnoringCase(item.value, "gzip") ||
                             EqualsIgnoringCase(item.value, "x-gzip") || item.value == "*");
  });
}

bool HttplibWouldGzip(std::string_view type) {
  // httplib's own list (detail::can_compress_content_type), which compares
  // the whole Content-Type value.
  return (type.starts_with("text/") && type != "text/event-stream") || type == "image/svg+xml" ||
         type == "application/javascript" || type == "application/json" ||
         type == "application/xml" || type == "application/protobuf" ||
         type == "application/xhtml+xml";
}

std::string Gzip(std::string_view bytes, int level) {
  z_stream z{};
  // 15 window bits + 16: a gzip header and trailer.
  if (deflateInit2(&z, level, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  std::string out(deflateBound(&z, static_cast<uLong>(bytes.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return rc == Z_STREAM_END ? out : std::string();
}

}  // namespace surfdeform
