// Font upload and shaping: hostile font bytes through FreeType (behind the
// font limits), HarfBuzz and the glyph mesher. An input is either a whole
// font file (mode byte 0), or patches to a real built-in font (mode 1..7:
// which font; then 5-byte records of a 32-bit offset and a byte to write),
// so that the fuzzer corrupts real tables rather than guessing their
// layout. The text shaped is a line in four scripts, plus the input's last
// 16 bytes as code points: those of them the font has (a missing one would
// end the work before shaping).
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "service/builtin_fonts.hpp"
#include "text/text_model.hpp"
#include "text/text_shaping.hpp"

namespace {

std::vector<std::string>& Fonts() {
  static std::vector<std::string> fonts = [] {
    std::vector<std::string> out;
    for (const auto& b : surfdeform::kBuiltinFonts) {
      std::ifstream in(std::string(surfdeform::kDefaultFontDir) + "/" + b.file, std::ios::binary);
      std::ostringstream s;
      s << in.rdbuf();
      out.push_back(s.str());
    }
    return out;
  }();
  return fonts;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace surfdeform;
  if (size < 1) return 0;
  std::string font;
  if (data[0] == 0) {
    font.assign(reinterpret_cast<const char*>(data + 1), size - 1);
  } else {
    const auto& fonts = Fonts();
    font = fonts[data[0] % fonts.size()];
    if (font.empty()) return 0;
    for (size_t k = 1; k + 5 <= size; k += 5) {
      const uint32_t at = (uint32_t(data[k]) | uint32_t(data[k + 1]) << 8 |
                           uint32_t(data[k + 2]) << 16 | uint32_t(data[k + 3]) << 24) %
                          static_cast<uint32_t>(font.size());
      font[at] = static_cast<char>(data[k + 4]);
    }
  }
  FontLimits limits;
  limits.max_font_memory = 64u << 20;
  limits.max_text_cost = 200000;
  auto face = FontFace::Open(font, limits);
  if (!face.ok()) return 0;
  // The sample's code points the font has (a missing one ends the work
  // before shaping), then the input's last bytes as more of them.
  std::string sample =
      "Ada fi AV 8 \u0633\u0644\u0627\u0645 \u05e9\u05dc\u05d5\u05dd "
      "\u0928\u092e\u0938\u094d\u0924\u0947\n";
  for (size_t k = size > 16 ? size - 16 : 0; k < size; ++k) {
    if (data[k] >= 0x20) sample += static_cast<char>(data[k] & 0x7F);
  }
  TextSettings t;
  auto cps = DecodeUtf8(sample);
  if (!cps.ok()) return 0;
  for (char32_t c : *cps) {
    if (c == U'\n' || (**face).HasCodePoint(c)) t.string += EncodeUtf8(c);
  }
  if (t.string.find_first_not_of(" \n") == std::string::npos) return 0;
  t.size_mm = 4;
  t.tolerance_mm = 0.05;
  (void)MakeTextModel(**face, t);
  t.direction = TextDirection::kRtl;
  t.depth_mm = 0;
  (void)MakeTextModel(**face, t);
  return 0;
}
