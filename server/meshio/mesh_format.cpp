#include "meshio/mesh_format.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <string>

namespace surfdeform {
namespace {

bool StartsWith(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

std::string_view SkipSpace(std::string_view s) {
  size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

bool LooksLikeText(std::string_view s) {
  const size_t n = std::min<size_t>(s.size(), 4096);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\f')) return false;
  }
  return true;
}

}  // namespace

const char* MeshFormatName(MeshFormat format) {
  switch (format) {
    case MeshFormat::kGlb:
      return "glb";
    case MeshFormat::kGltf:
      return "gltf";
    case MeshFormat::kDraco:
      return "drc";
    case MeshFormat::kObj:
      return "obj";
    case MeshFormat::kPly:
      return "ply";
    case MeshFormat::kStl:
      return "stl";
    case MeshFormat::kOff:
      return "off";
    case MeshFormat::k3mf:
      return "3mf";
    case MeshFormat::kUnknown:
      break;
  }
  return "unknown";
}

std::optional<MeshFormat> MeshFormatFromName(std::string_view name) {
  std::string n(name);
  if (!n.empty() && n.front() == '.') n.erase(0, 1);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  for (MeshFormat f : {MeshFormat::kGlb, MeshFormat::kGltf, MeshFormat::kDraco, MeshFormat::kObj,
                       MeshFormat::kPly, MeshFormat::kStl, MeshFormat::kOff}) {
    if (n == MeshFormatName(f)) return f;
  }
  if (n == "draco") return MeshFormat::kDraco;
  return std::nullopt;
}

MeshFormat DetectMeshFormat(std::string_view bytes) {
  if (StartsWith(bytes, "glTF")) return MeshFormat::kGlb;
  if (StartsWith(bytes, "DRACO")) return MeshFormat::kDraco;
  if (StartsWith(bytes, "ply\n") || StartsWith(bytes, "ply\r\n")) return MeshFormat::kPly;
  // Binary STL: an 80-byte header, a triangle count, 50 bytes per triangle.
  if (bytes.size() >= 84) {
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50ull * count) return MeshFormat::kStl;
  }
  if (!LooksLikeText(bytes)) return MeshFormat::kUnknown;
  const std::string_view text = SkipSpace(bytes);
  if (StartsWith(text, "{")) {
    return text.find("\"asset\"") != std::string_view::npos ? MeshFormat::kGltf
                                                            : MeshFormat::kUnknown;
  }
  if (StartsWith(text, "solid") && text.find("facet") != std::string_view::npos) {
    return MeshFormat::kStl;
  }
  for (std::string_view magic : {"OFF", "COFF", "NOFF", "CNOFF"}) {
    if (StartsWith(text, magic) && (text.size() == magic.size() ||
                                    std::isspace(static_cast<unsigned char>(text[magic.size()])))) {
      return MeshFormat::kOff;
    }
  }
  // OBJ: some line that starts with a vertex statement.
  size_t pos = 0;
  const size_t scan = std::min<size_t>(bytes.size(), 1 << 16);
  while (pos < scan) {
    const std::string_view line = SkipSpace(bytes.substr(pos, 3));
    if (StartsWith(line, "v ") || StartsWith(line, "v\t")) return MeshFormat::kObj;
    const size_t next = bytes.find('\n', pos);
    if (next == std::string_view::npos) break;
    pos = next + 1;
  }
  return MeshFormat::kUnknown;
}

}  // namespace surfdeform
