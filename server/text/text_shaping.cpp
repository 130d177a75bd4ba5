#include "text/text_shaping.hpp"

#include <hb.h>

#include <algorithm>

#include "text/font_face_impl.hpp"

namespace surfdeform {
namespace {

Status Invalid(const std::string& message, const std::string& field) {
  return Status(ErrorCode::kInvalidArgument, message, field);
}

// One run before shaping: bytes [begin, end) of the text.
struct Item {
  uint32_t begin = 0, end = 0;
  hb_script_t script = HB_SCRIPT_COMMON;
  bool rtl = false;
  bool number = false;  // digits set left to right inside right-to-left text
  int level = 0;        // the bidi embedding level (0 LTR base, 1 RTL, 2 LTR in RTL)
};

bool IsNeutralScript(hb_script_t s) {
  return s == HB_SCRIPT_COMMON || s == HB_SCRIPT_INHERITED || s == HB_SCRIPT_UNKNOWN;
}

bool IsJoining(hb_script_t s) {
  return s == HB_SCRIPT_ARABIC || s == HB_SCRIPT_SYRIAC || s == HB_SCRIPT_MONGOLIAN ||
         s == HB_SCRIPT_NKO || s == HB_SCRIPT_MANDAIC || s == HB_SCRIPT_DEVANAGARI ||
         s == HB_SCRIPT_BENGALI || s == HB_SCRIPT_GURMUKHI;
}

std::string ScriptTag(hb_script_t s) {
  char tag[5] = {};
  hb_tag_to_string(hb_script_to_iso15924_tag(s), tag);
  return tag;
}

struct CodePoint {
  char32_t c;
  uint32_t offset;  // byte offset in the text
};

// The line's runs, in logical order, each with its level; *rtl the line's
// base direction.
std::vector<Item> Itemize(const std::vector<CodePoint>& cps, uint32_t line_end,
                          const TextSettings& s, bool* rtl) {
  hb_unicode_funcs_t* uf = hb_unicode_funcs_get_default();
  std::vector<Item> items;
  if (cps.empty()) return items;
  if (s.direction != TextDirection::kAuto || s.script != "auto") {
    // One run: the direction and script given (the rest from HarfBuzz).
    Item it{cps.front().offset, line_end, HB_SCRIPT_INVALID};
    if (s.script != "auto") it.script = hb_script_from_string(s.script.c_str(), -1);
    for (const CodePoint& cp : cps) {
      if (it.script != HB_SCRIPT_INVALID) break;
      const hb_script_t sc = hb_unicode_script(uf, cp.c);
      if (!IsNeutralScript(sc)) it.script = sc;
    }
    if (it.script == HB_SCRIPT_INVALID) it.script = HB_SCRIPT_COMMON;
    it.rtl = s.direction == TextDirection::kRtl ||
             (s.direction == TextDirection::kAuto &&
              hb_script_get_horizontal_direction(it.script) == HB_DIRECTION_RTL);
    *rtl = it.rtl;
    it.level = it.rtl ? 1 : 0;
    items.push_back(it);
    return items;
  }
  // Runs of one script; neutrals join the run before them; digits after
  // right-to-left letters make a left-to-right run of their own.
  Item cur{cps.front().offset, cps.front().offset, HB_SCRIPT_INVALID};
  const auto flush = [&](uint32_t at) {
    cur.end = at;
    if (cur.end > cur.begin) items.push_back(cur);
    cur = Item{at, at, HB_SCRIPT_INVALID};
  };
  bool after_rtl = false;
  for (const CodePoint& cp : cps) {
    const hb_script_t sc = hb_unicode_script(uf, cp.c);
    const bool digit =
        hb_unicode_general_category(uf, cp.c) == HB_UNICODE_GENERAL_CATEGORY_DECIMAL_NUMBER;
    if (!IsNeutralScript(sc)) {
      const bool r = hb_script_get_horizontal_direction(sc) == HB_DIRECTION_RTL;
      if (cur.number || (cur.script != HB_SCRIPT_INVALID && cur.script != sc)) flush(cp.offset);
      cur.script = sc;
      cur.rtl = r;
      after_rtl = r;
    } else if (digit && after_rtl && !cur.number) {
      flush(cp.offset);
      cur.number = true;
      cur.script = HB_SCRIPT_COMMON;
    }
  }
  flush(line_end);
  for (Item& it : items) {
    if (it.script == HB_SCRIPT_INVALID) it.script = HB_SCRIPT_COMMON;
  }
  // The base direction: the first strong run's.
  *rtl = false;
  for (const Item& it : items) {
    if (!it.number && it.script != HB_SCRIPT_COMMON) {
      *rtl = it.rtl;
      break;
    }
  }
  for (Item& it : items) {
    if (it.number) {
      it.level = 2;
    } else if (it.rtl) {
      it.level = 1;
    } else {
      it.level = *rtl ? 2 : 0;
    }
  }
  return items;
}

// Unicode's rule L2: from the highest level down to the lowest odd one,
// reverse every stretch of runs at that level or above.
void ReorderRuns(std::vector<ShapedRun>* runs, const std::vector<int>& levels) {
  int top = 0, low_odd = 1 << 20;
  for (int l : levels) {
    top = std::max(top, l);
    if (l % 2 == 1) low_odd = std::min(low_odd, l);
  }
  std::vector<size_t> order(runs->size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  for (int l = top; l >= low_odd && l >= 1; --l) {
    size_t k = 0;
    while (k < order.size()) {
      if (levels[order[k]] < l) {
        ++k;
        continue;
      }
      size_t e = k;
      while (e < order.size() && levels[order[e]] >= l) ++e;
      std::reverse(order.begin() + static_cast<long>(k), order.begin() + static_cast<long>(e));
      k = e;
    }
  }
  std::vector<ShapedRun> out;
  out.reserve(runs->size());
  for (size_t k : order) out.push_back(std::move((*runs)[k]));
  *runs = std::move(out);
}

Result<std::vector<hb_feature_t>> Features(const TextSettings& s) {
  std::vector<hb_feature_t> out;
  bool kern = false, liga = false;
  for (size_t k = 0; k < s.features.size(); ++k) {
    hb_feature_t f;
    const std::string& text = s.features[k];
    if (text.empty() || text.size() > 64 ||
        !hb_feature_from_string(text.c_str(), static_cast<int>(text.size()), &f)) {
      return Invalid(
          "is not an OpenType feature as HarfBuzz spells them (\"kern\", \"-liga\", "
          "\"ss01=1\"), got \"" +
              text + "\"",
          "text.features[" + std::to_string(k) + "]");
    }
    kern = kern || (f.tag == HB_TAG('k', 'e', 'r', 'n') && f.value != 0);
    liga = liga || (f.tag == HB_TAG('l', 'i', 'g', 'a') && f.value != 0);
    out.push_back(f);
  }
  // Kerning and ligatures only when listed.
  if (!kern) out.push_back({HB_TAG('k', 'e', 'r', 'n'), 0, 0, static_cast<unsigned>(-1)});
  if (!liga) out.push_back({HB_TAG('l', 'i', 'g', 'a'), 0, 0, static_cast<unsigned>(-1)});
  return out;
}

}  // namespace

Result<std::u32string> DecodeUtf8(const std::string& text) {
  std::u32string out;
  out.reserve(text.size());
  size_t i = 0;
  const auto bad = [&] {
    return Status(ErrorCode::kMalformed, "is not UTF-8 at byte " + std::to_string(i),
                  "text.string");
  };
  while (i < text.size()) {
    const auto b = static_cast<unsigned char>(text[i]);
    int n = 0;
    char32_t c = 0;
    if (b < 0x80) {
      c = b;
    } else if ((b & 0xE0) == 0xC0) {
      n = 1;
      c = b & 0x1F;
    } else if ((b & 0xF0) == 0xE0) {
      n = 2;
      c = b & 0x0F;
    } else if ((b & 0xF8) == 0xF0) {
      n = 3;
      c = b & 0x07;
    } else {
      return bad();
    }
    if (n > 0 && i + static_cast<size_t>(n) >= text.size()) return bad();
    for (int k = 1; k <= n; ++k) {
      const auto cb = static_cast<unsigned char>(text[i + static_cast<size_t>(k)]);
      if ((cb & 0xC0) != 0x80) return bad();
      c = (c << 6) | (cb & 0x3F);
    }
    static constexpr char32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (c < kMin[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return bad();
    out.push_back(c);
    i += static_cast<size_t>(n) + 1;
  }
  return out;
}

std::string EncodeUtf8(char32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (c >> 18));
    s += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}

std::vector<char32_t> MissingCodePoints(const FontFace& font, const std::u32string& text) {
  hb_unicode_funcs_t* uf = hb_unicode_funcs_get_default();
  std::vector<char32_t> missing;
  for (char32_t c : text) {
    const auto cat = hb_unicode_general_category(uf, c);
    if (c == U'\n' || c == U'\r' || cat == HB_UNICODE_GENERAL_CATEGORY_CONTROL ||
        cat == HB_UNICODE_GENERAL_CATEGORY_FORMAT) {
      continue;  // line breaks, and joiners and marks of direction HarfBuzz hides
    }
    if (!font.HasCodePoint(c) && std::find(missing.begin(), missing.end(), c) == missing.end()) {
      missing.push_back(c);
    }
  }
  return missing;
}

Result<std::vector<ShapedLine>> ShapeText(const FontFace& font, const TextSettings& s) {
  SURFDEFORM_ASSIGN_OR_RETURN(const std::u32string cps32, DecodeUtf8(s.string));
  SURFDEFORM_ASSIGN_OR_RETURN(const std::vector<hb_feature_t> features, Features(s));
  hb_language_t language = nullptr;
  if (s.language != "auto") {
    language = hb_language_from_string(s.language.c_str(), static_cast<int>(s.language.size()));
  }
  // Code points with their byte offsets, line by line.
  std::vector<std::vector<CodePoint>> lines(1);
  std::vector<uint32_t> line_ends;
  uint32_t offset = 0;
  for (char32_t c : cps32) {
    const auto len = static_cast<uint32_t>(EncodeUtf8(c).size());
    if (c == U'\n') {
      line_ends.push_back(offset);
      lines.emplace_back();
    } else if (c != U'\r') {
      lines.back().push_back({c, offset});
    }
    offset += len;
  }
  line_ends.push_back(offset);
  std::vector<ShapedLine> out;
  out.reserve(lines.size());
  hb_buffer_t* buf = hb_buffer_create();
  for (size_t l = 0; l < lines.size(); ++l) {
    ShapedLine line;
    // A line's end before a "\r\n" is the "\r".
    uint32_t end = line_ends[l];
    if (!lines[l].empty()) {
      const CodePoint& last = lines[l].back();
      end = last.offset + static_cast<uint32_t>(EncodeUtf8(last.c).size());
    }
    const std::vector<Item> items = Itemize(lines[l], end, s, &line.rtl);
    std::vector<int> levels;
    for (const Item& it : items) {
      hb_buffer_clear_contents(buf);
      hb_buffer_set_flags(buf, HB_BUFFER_FLAG_REMOVE_DEFAULT_IGNORABLES);
      hb_buffer_add_utf8(buf, s.string.data(), static_cast<int>(s.string.size()), it.begin,
                         static_cast<int>(it.end - it.begin));
      hb_buffer_set_direction(buf, it.rtl ? HB_DIRECTION_RTL : HB_DIRECTION_LTR);
      hb_buffer_set_script(buf, it.script);
      if (language != nullptr) hb_buffer_set_language(buf, language);
      hb_buffer_guess_segment_properties(buf);
      hb_shape(font.impl().hb_font, buf, features.data(), static_cast<unsigned>(features.size()));
      unsigned n = 0;
      const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(buf, &n);
      const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(buf, &n);
      ShapedRun run;
      run.script = ScriptTag(hb_buffer_get_script(buf));
      run.rtl = it.rtl;
      run.joining = IsJoining(hb_buffer_get_script(buf));
      run.glyphs.resize(n);
      for (unsigned k = 0; k < n; ++k) {
        run.glyphs[k] = {info[k].codepoint,        info[k].cluster,
                         double(pos[k].x_advance), double(pos[k].y_advance),
                         double(pos[k].x_offset),  double(pos[k].y_offset)};
      }
      line.runs.push_back(std::move(run));
      levels.push_back(it.level);
    }
    ReorderRuns(&line.runs, levels);
    out.push_back(std::move(line));
  }
  hb_buffer_destroy(buf);
  return out;
}

}  // namespace surfdeform
