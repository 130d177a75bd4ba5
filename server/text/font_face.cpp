#include "text/font_face.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_FONT_FORMATS_H
#include FT_MODULE_H
#include FT_SYSTEM_H

#include <hb-ft.h>
#include <hb.h>

#include <cstdlib>
#include <cstring>

#include "text/font_face_impl.hpp"

namespace surfdeform {
namespace {

// FreeType's heap, bounded: an allocation past the budget fails, and
// FreeType reports an out-of-memory error for the font.
struct Header {
  size_t size;
  size_t pad;  // keeps the block 16-byte aligned
};

void* BudgetAlloc(FT_Memory memory, long size) {
  auto* budget = static_cast<FtBudget*>(memory->user);
  const auto n = static_cast<size_t>(size);
  if (size <= 0 || budget->used + n > budget->limit) {
    budget->exceeded = true;
    return nullptr;
  }
  auto* h = static_cast<Header*>(std::malloc(sizeof(Header) + n));
  if (h == nullptr) return nullptr;
  h->size = n;
  budget->used += n;
  budget->peak = std::max(budget->peak, budget->used);
  return h + 1;
}

void BudgetFree(FT_Memory memory, void* block) {
  if (block == nullptr) return;
  auto* budget = static_cast<FtBudget*>(memory->user);
  auto* h = static_cast<Header*>(block) - 1;
  budget->used -= h->size;
  std::free(h);
}

void* BudgetRealloc(FT_Memory memory, long /*cur_size*/, long new_size, void* block) {
  if (block == nullptr) return BudgetAlloc(memory, new_size);
  auto* budget = static_cast<FtBudget*>(memory->user);
  auto* h = static_cast<Header*>(block) - 1;
  const size_t old = h->size;
  const auto n = static_cast<size_t>(new_size);
  if (new_size <= 0 || budget->used - old + n > budget->limit) {
    budget->exceeded = true;
    return nullptr;
  }
  auto* moved = static_cast<Header*>(std::realloc(h, sizeof(Header) + n));
  if (moved == nullptr) return nullptr;
  moved->size = n;
  budget->used = budget->used - old + n;
  budget->peak = std::max(budget->peak, budget->used);
  return moved + 1;
}

// FreeType's own messages for its error codes (its documented table idiom).
#undef FTERRORS_H_
#define FT_ERRORDEF(e, v, s) {e, s},
#define FT_ERROR_START_LIST {
#define FT_ERROR_END_LIST \
  { 0, nullptr }          \
  }                       \
  ;
struct FtErrorMessage {
  int code;
  const char* message;
};
const FtErrorMessage kFtErrors[] =
#include FT_ERRORS_H

    std::string FtErrorText(FT_Error e) {
  for (const FtErrorMessage& m : kFtErrors) {
    if (m.message != nullptr && m.code == e) return m.message;
  }
  return "FreeType error " + std::to_string(e);
}

Status Refused(const std::string& why) {
  return Status(ErrorCode::kMalformed, "the font cannot be read: " + why, "font");
}

std::string FormatOf(std::string_view bytes, FT_Face face) {
  if (bytes.size() >= 4 && bytes.substr(0, 4) == "wOF2") return "woff2";
  if (bytes.size() >= 4 && bytes.substr(0, 4) == "wOFF") return "woff";
  const char* f = FT_Get_Font_Format(face);
  std::string s = f == nullptr ? "unknown" : f;
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

const std::vector<ScriptProbe>& ScriptProbes() {
  static const std::vector<ScriptProbe> probes = {
      {"Latn", "Latin", {U'A', U'z', U'\u00e9'}},
      {"Grek", "Greek", {U'\u0391', U'\u03a9', U'\u03c9'}},
      {"Cyrl", "Cyrillic", {U'\u0416', U'\u044f'}},
      {"Arab", "Arabic", {U'\u0628', U'\u0633', U'\u0644'}},
      {"Hebr", "Hebrew", {U'\u05d0', U'\u05e9'}},
      {"Deva", "Devanagari", {U'\u0915', U'\u0928', U'\u094d'}},
  };
  return probes;
}

FontFace::FontFace(const FontLimits& limits) : limits_(limits), impl_(std::make_unique<Impl>()) {}

FontFace::~FontFace() {
  if (impl_->hb_font != nullptr) hb_font_destroy(impl_->hb_font);
  if (impl_->face != nullptr) FT_Done_Face(impl_->face);
  if (impl_->library != nullptr) FT_Done_Library(impl_->library);
}

Result<std::unique_ptr<FontFace>> FontFace::Open(std::string_view bytes, const FontLimits& limits) {
  if (bytes.size() > limits.max_font_bytes) {
    return Status::LimitExceeded("the font file is larger than the limit", "font",
                                 static_cast<double>(limits.max_font_bytes),
                                 static_cast<double>(bytes.size()));
  }
  if (bytes.size() < 12) return Refused("it is " + std::to_string(bytes.size()) + " bytes long");
  std::unique_ptr<FontFace> font(new FontFace(limits));
  Impl& f = *font->impl_;
  f.budget.limit = limits.max_font_memory;
  f.memory.user = &f.budget;
  f.memory.alloc = BudgetAlloc;
  f.memory.free = BudgetFree;
  f.memory.realloc = BudgetRealloc;
  if (FT_New_Library(&f.memory, &f.library) != 0) {
    return Status(ErrorCode::kLimitExceeded, "no memory for the font reader", "font");
  }
  FT_Add_Default_Modules(f.library);
  const FT_Error opened =
      FT_New_Memory_Face(f.library, reinterpret_cast<const FT_Byte*>(bytes.data()),
                         static_cast<FT_Long>(bytes.size()), 0, &f.face);
  if (f.budget.exceeded) {
    return Status::LimitExceeded("reading the font takes more memory than the limit", "font",
                                 static_cast<double>(limits.max_font_memory),
                                 static_cast<double>(f.budget.peak));
  }
  if (opened != 0 || f.face == nullptr) {
    return Refused(FtErrorText(opened));
  }
  FT_Face face = f.face;
  if (!FT_IS_SCALABLE(face) || face->units_per_EM < 16 || face->units_per_EM > 16384) {
    return Refused("it has no scalable outlines (or units per em outside 16..16384)");
  }
  if (static_cast<size_t>(face->num_glyphs) > limits.max_glyphs) {
    return Status::LimitExceeded("the font has more glyphs than the limit", "font",
                                 static_cast<double>(limits.max_glyphs),
                                 static_cast<double>(face->num_glyphs));
  }
  if (FT_Select_Charmap(face, FT_ENCODING_UNICODE) != 0) {
    return Refused("it has no Unicode character map");
  }
  FontInfo& info = font->info_;
  info.family = face->family_name != nullptr ? face->family_name : "";
  info.style = face->style_name != nullptr ? face->style_name : "";
  info.format = FormatOf(bytes, face);
  info.glyphs = static_cast<size_t>(face->num_glyphs);
  info.units_per_em = face->units_per_EM;
  for (const ScriptProbe& p : ScriptProbes()) {
    bool all = true;
    for (char32_t c : p.letters) all = all && FT_Get_Char_Index(face, c) != 0;
    if (all) info.scripts.emplace_back(p.script);
  }
  // HarfBuzz reads the tables through FreeType (so WOFF2 works too) and
  // shapes in font units with its own OpenType functions: no hinting.
  hb_face_t* hb_face = hb_ft_face_create_referenced(face);
  f.hb_font = hb_font_create(hb_face);
  hb_face_destroy(hb_face);
  hb_font_set_scale(f.hb_font, face->units_per_EM, face->units_per_EM);
  if (f.budget.exceeded) {
    return Status::LimitExceeded("reading the font takes more memory than the limit", "font",
                                 static_cast<double>(limits.max_font_memory),
                                 static_cast<double>(f.budget.peak));
  }
  return font;
}

bool FontFace::HasCodePoint(char32_t c) const { return FT_Get_Char_Index(impl_->face, c) != 0; }

}  // namespace surfdeform
