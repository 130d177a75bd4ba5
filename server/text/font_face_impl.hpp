// FontFace's FreeType and HarfBuzz handles, for the typesetter's own
// translation units (never included outside server/text).
#pragma once

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_SYSTEM_H

#include <hb.h>

#include "text/font_face.hpp"

namespace surfdeform {

struct FtBudget {
  size_t used = 0;
  size_t peak = 0;
  size_t limit = 0;
  bool exceeded = false;
};

struct FontFace::Impl {
  FtBudget budget;
  FT_MemoryRec_ memory{};
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  hb_font_t* hb_font = nullptr;
};

}  // namespace surfdeform
