// Text shaped and meshed (server/text): a 40-character line and a
// 200-character paragraph in DejaVuSans at 0.01 mm, 4 mm em, 0.6 mm deep.
// Prints, per text, the median time of shaping plus meshing (the font
// opened once, as the peer parses it once), the triangles, the outline
// points the tolerance needs (Wang's bound on every curve) and the fewest
// triangles a closed solid over those points can have: per glyph, its two
// faces of n - 2 chi triangles each (n boundary points, chi = pieces minus
// holes: a triangulation with no point added) and a wall of 2n.
// bench/text_vs_opentype.sh runs it beside opentype.js + earcut.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <map>
#include <string>

#include "harness.hpp"
#include "service/builtin_fonts.hpp"
#include "text/glyph_mesh.hpp"
#include "text/glyph_outline.hpp"
#include "text/text_model.hpp"
#include "text_samples.hpp"

namespace surfdeform::bench {
namespace {

// The fewest triangles of a closed solid over a glyph's outline at the
// tolerance: its n points (after flattening) and the Euler characteristic
// chi of its flat face (vertices - edges + faces), 2 (n - 2 chi) + 2 n.
long FewestTriangles(const FontFace& font, uint32_t glyph, double tolerance_units) {
  auto outline = LoadGlyphOutline(font, glyph, tolerance_units, 1u << 24);
  if (!outline.ok() || outline->contours.empty()) return 0;
  auto solid = MeshGlyph(outline->contours, outline->even_odd, 1.0, 0.0);
  if (!solid.ok()) return 0;
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : solid->triangles)
    for (int i = 0; i < 3; ++i) ++edges[std::minmax(t[i], t[(i + 1) % 3])];
  const long chi = static_cast<long>(solid->positions.size()) - static_cast<long>(edges.size()) +
                   static_cast<long>(solid->triangles.size());
  const auto n = static_cast<long>(outline->points());
  return 2 * (n - 2 * chi) + 2 * n;
}

}  // namespace
}  // namespace surfdeform::bench

int main(int argc, char** argv) {
  using namespace surfdeform;
  using namespace surfdeform::bench;
  CLI::App app{"text shaping and meshing, for bench/text_vs_opentype.sh"};
  std::string font_path = std::string(kDefaultFontDir) + "/" + kBuiltinFonts[0].file;
  int repeat = 50;
  double tolerance = 0.01, size = 4.0, depth = 0.6;
  app.add_option("--font", font_path, "Font file");
  app.add_option("--repeat", repeat, "Timed runs per text (the median is reported)");
  app.add_option("--tolerance-mm", tolerance);
  app.add_option("--size-mm", size);
  app.add_option("--depth-mm", depth);
  CLI11_PARSE(app, argc, argv);
  const std::string bytes = ReadFile(font_path);
  auto font = FontFace::Open(bytes, FontLimits{});
  if (!font.ok()) {
    std::fprintf(stderr, "%s\n", font.status().ToString().c_str());
    return 1;
  }
  const double open_ms = MedianMs(repeat, [&] { (void)FontFace::Open(bytes, FontLimits{}); });
  std::printf(
      "{\"font\": \"%s\", \"open_ms\": %.4f, \"tolerance_mm\": %g, \"size_mm\": %g, "
      "\"depth_mm\": %g, \"texts\": [\n",
      font_path.c_str(), open_ms, tolerance, size, depth);
  const char* texts[] = {kTextLine, kTextParagraph};
  for (int k = 0; k < 2; ++k) {
    TextSettings t;
    t.string = texts[k];
    t.size_mm = size;
    t.depth_mm = depth;
    t.tolerance_mm = tolerance;
    auto model = MakeTextModel(**font, t);
    if (!model.ok()) {
      std::fprintf(stderr, "%s\n", model.status().ToString().c_str());
      return 1;
    }
    const double ms = MedianMs(repeat, [&] { (void)MakeTextModel(**font, t); });
    // The fewest triangles over the points the tolerance needs.
    const double units = tolerance * (**font).info().units_per_em / size;
    long fewest = 0;
    std::map<uint32_t, long> each;
    for (const TextGlyph& g : model->glyphs) {
      if (g.group == static_cast<size_t>(-1)) continue;
      auto it = each.find(g.glyph);
      if (it == each.end())
        it = each.emplace(g.glyph, FewestTriangles(**font, g.glyph, units)).first;
      fewest += it->second;
    }
    std::printf(
        "  {\"chars\": %zu, \"text\": \"%s\", \"ms\": %.4f, \"triangles\": %zu, "
        "\"outline_points\": %zu, \"fewest_triangles\": %ld}%s\n",
        t.string.size(), t.string.c_str(), ms, model->mesh.triangles.size(), model->outline_points,
        fewest, k == 0 ? "," : "");
  }
  std::printf("]}\n");
  return 0;
}
