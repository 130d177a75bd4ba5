// The built-in fonts: files of Debian's font packages (scripts/setup.sh
// installs them; the Docker image too), named as requests name them.
#pragma once

#include <string>
#include <vector>

namespace surfdeform {

struct BuiltinFont {
  const char* name;     // as "text.font" names it
  const char* file;     // under the font directory (--font-dir, /usr/share/fonts)
  const char* package;  // the Debian package that has it
};

inline constexpr BuiltinFont kBuiltinFonts[] = {
    {"DejaVuSans", "truetype/dejavu/DejaVuSans.ttf", "fonts-dejavu-core"},
    {"DejaVuSans-Bold", "truetype/dejavu/DejaVuSans-Bold.ttf", "fonts-dejavu-core"},
    {"DejaVuSerif", "truetype/dejavu/DejaVuSerif.ttf", "fonts-dejavu-core"},
    {"DejaVuSansMono", "truetype/dejavu/DejaVuSansMono.ttf", "fonts-dejavu-core"},
    // OpenType with CFF outlines (cubic curves).
    {"Cantarell", "opentype/cantarell/Cantarell-Regular.otf", "fonts-cantarell"},
    {"Amiri", "opentype/fonts-hosny-amiri/Amiri-Regular.ttf", "fonts-hosny-amiri"},
    {"EzraSIL", "truetype/ezra/SILEOT.ttf", "fonts-sil-ezra"},
    {"LohitDevanagari", "truetype/lohit-devanagari/Lohit-Devanagari.ttf", "fonts-lohit-deva"},
};

inline constexpr const char* kDefaultFontDir = "/usr/share/fonts";

}  // namespace surfdeform
