// Text as the model of a deformation or an animation: the request's text
// made into a mesh with its font from the font store (text/text_model.hpp),
// the placement a text on a sheet polyline takes, and the text's part of
// an answer's key.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "base/cancel_flag.hpp"
#include "base/status.hpp"
#include "engine/common/placement_settings.hpp"
#include "meshio/mesh_import.hpp"
#include "service/font_store.hpp"
#include "text/text_settings.hpp"

namespace surfdeform {

// A text is the whole model: a mesh in the body as well is a 400.
Status CheckTextAlone(const std::optional<TextSettings>& text, std::string_view body);

// A text on "sheet_points" is set where its points are: the placement's
// centre becomes the sheet's origin, and a centre, rotation or scale given
// as well is a 422 (they would move it off its path).
Status PlaceTextOnItsPath(const std::optional<TextSettings>& text, PlacementSettings* placement);

// The text's model id in answers' keys: its canonical settings and the
// font's content id.
std::string TextModelKey(const TextSettings& text, const std::string& font_id);

// A text's account in the reply's statistics ("text": font, glyphs, lines,
// width, runs, clusters), made once with its mesh (ImportedMesh::text_stats)
// and shared by each reply's stats.
struct TextStats {
  std::string font;  // its name, or a font uploaded by id
  std::string family;
  std::string style;
  size_t glyphs = 0;
  size_t solids = 0;  // the mesh's groups: a letter each
  int lines = 0;
  double width_mm = 0.0;
  size_t outline_points = 0;
  double area_mm2 = 0.0;
  std::vector<std::string> runs;
  // The first kMaxClusters glyphs: the text each stands for, and where.
  struct Cluster {
    std::string text;
    uint32_t glyph = 0;
    int line = 0;
    double s_mm = 0.0;
    double advance_mm = 0.0;
  };
  static constexpr size_t kMaxClusters = 1000;
  std::vector<Cluster> clusters;
  double path_length_mm = 0.0;  // along a path (0: straight, not written)
  nlohmann::json ToJson() const;
};

// The text's mesh (in mm; x along the baseline, z out of the surface), its
// origin the footprint's centre, its account in text_stats. A code
// point the font lacks is a 422 naming the built-in fonts that have them.
Result<ImportedMesh> MakeTextMesh(const TextSettings& text, const StoredFont& font,
                                  const FontStore& fonts, const FontLimits& limits,
                                  const CancelFlag* cancel);

// GET /v1/fonts: the built-in fonts, each with its family, style, format,
// glyphs and the scripts it covers.
nlohmann::json FontListJson(const FontStore& fonts);
nlohmann::json FontJson(const StoredFont& font);

}  // namespace surfdeform
