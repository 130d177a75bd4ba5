// Text as a model: shaping equals HarfBuzz's own, every glyph a closed
// outward solid whose volume is its outline's area times its depth (the
// area from FreeType's curves by exact quadrature), holes kept, overlaps
// filled once, the refusals, and a name round a full cylinder with rigid
// glyphs.
#include "text/text_model.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include <gtest/gtest.h>
#include <hb.h>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "engine/deform/deform.hpp"
#include "service/builtin_fonts.hpp"
#include "support/test_meshes.hpp"
#include "support/test_surfaces.hpp"
#include "text/font_face_impl.hpp"
#include "text/glyph_mesh.hpp"
#include "text/glyph_outline.hpp"
#include "text/text_shaping.hpp"

namespace surfdeform {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Font {
  std::string name;
  std::string bytes;
  std::unique_ptr<FontFace> face;
};

const Font& FontNamed(const std::string& name) {
  static std::map<std::string, Font> fonts;
  auto it = fonts.find(name);
  if (it != fonts.end()) return it->second;
  Font f{name, {}, nullptr};
  for (const BuiltinFont& b : kBuiltinFonts) {
    if (name == b.name) f.bytes = ReadFile(std::string(kDefaultFontDir) + "/" + b.file);
  }
  EXPECT_FALSE(f.bytes.empty()) << name << ": install the font packages (scripts/setup.sh)";
  auto face = FontFace::Open(f.bytes, FontLimits{});
  EXPECT_TRUE(face.ok()) << face.status().ToString();
  if (face.ok()) f.face = std::move(*face);
  return fonts.emplace(name, std::move(f)).first->second;
}

// HarfBuzz's own shaping of `text` with its defaults (kern and liga on),
// straight from the file's bytes.
struct Reference {
  std::vector<uint32_t> glyphs;
  std::vector<int> advances;
};
Reference HarfBuzzShape(const std::string& bytes, const std::string& text) {
  hb_blob_t* blob = hb_blob_create(bytes.data(), static_cast<unsigned>(bytes.size()),
                                   HB_MEMORY_MODE_READONLY, nullptr, nullptr);
  hb_face_t* face = hb_face_create(blob, 0);
  hb_font_t* font = hb_font_create(face);
  hb_buffer_t* buf = hb_buffer_create();
  hb_buffer_add_utf8(buf, text.data(), static_cast<int>(text.size()), 0, -1);
  hb_buffer_guess_segment_properties(buf);
  hb_shape(font, buf, nullptr, 0);
  unsigned n = 0;
  const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(buf, &n);
  const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(buf, &n);
  Reference r;
  for (unsigned k = 0; k < n; ++k) {
    r.glyphs.push_back(info[k].codepoint);
    r.advances.push_back(pos[k].x_advance);
  }
  hb_buffer_destroy(buf);
  hb_font_destroy(font);
  hb_face_destroy(face);
  hb_blob_destroy(blob);
  return r;
}

bool Covers(const FontFace& face, const std::string& text) {
  auto cps = DecodeUtf8(text);
  return cps.ok() && MissingCodePoints(face, *cps).empty();
}

TextSettings Text(const std::string& s, const std::string& font = "DejaVuSans") {
  TextSettings t;
  t.string = s;
  t.font = font;
  return t;
}

TEST(TextShaping, EqualsHarfBuzzForEveryBuiltinFont) {
  const std::vector<std::string> samples = {"Hello", "AVATAR", "office", "سلام", "नमस्ते"};
  std::map<std::string, int> shaped_by;
  for (const BuiltinFont& b : kBuiltinFonts) {
    const Font& f = FontNamed(b.name);
    ASSERT_NE(f.face, nullptr);
    for (const std::string& s : samples) {
      if (!Covers(*f.face, s)) continue;
      ++shaped_by[s];
      auto lines = ShapeText(*f.face, Text(s, b.name));
      ASSERT_TRUE(lines.ok()) << lines.status().ToString();
      ASSERT_EQ(lines->size(), 1u);
      ASSERT_EQ((*lines)[0].runs.size(), 1u) << b.name << " " << s;
      const ShapedRun& run = (*lines)[0].runs[0];
      const Reference ref = HarfBuzzShape(f.bytes, s);
      ASSERT_EQ(run.glyphs.size(), ref.glyphs.size()) << b.name << " " << s;
      for (size_t k = 0; k < ref.glyphs.size(); ++k) {
        EXPECT_EQ(run.glyphs[k].glyph, ref.glyphs[k]) << b.name << " " << s << " " << k;
        EXPECT_EQ(run.glyphs[k].x_advance, ref.advances[k]) << b.name << " " << s << " " << k;
      }
      EXPECT_EQ(run.rtl, s == "سلام") << b.name;
    }
  }
  for (const std::string& s : samples)
    EXPECT_GE(shaped_by[s], 1) << s << ": no built-in font has it";
}

TEST(TextShaping, KerningLigaturesAndJoiningAreReal) {
  const FontFace& sans = *FontNamed("DejaVuSans").face;
  // AVATAR: kerning moves "AV" closer than the nominal advances.
  TextSettings plain = Text("AVATAR");
  plain.features = {};
  auto kerned = ShapeText(sans, Text("AVATAR"));
  auto unkerned = ShapeText(sans, plain);
  ASSERT_TRUE(kerned.ok() && unkerned.ok());
  double a = 0, b = 0;
  for (const auto& g : (*kerned)[0].runs[0].glyphs) a += g.x_advance;
  for (const auto& g : (*unkerned)[0].runs[0].glyphs) b += g.x_advance;
  EXPECT_LT(a, b - 50) << "kerning should tighten AVATAR";
  // office: the ffi ligature where the font has it (one glyph fewer or more).
  TextSettings no_liga = Text("office");
  no_liga.features = {"kern"};
  auto lig = ShapeText(sans, Text("office"));
  auto nolig = ShapeText(sans, no_liga);
  ASSERT_TRUE(lig.ok() && nolig.ok());
  EXPECT_EQ((*nolig)[0].runs[0].glyphs.size(), 6u);
  EXPECT_LT((*lig)[0].runs[0].glyphs.size(), 6u);
  // Arabic joins: the shaped glyphs are not the letters' isolated forms.
  const FontFace& amiri = *FontNamed("Amiri").face;
  auto salam = ShapeText(amiri, Text("سلام", "Amiri"));
  ASSERT_TRUE(salam.ok());
  const auto& glyphs = (*salam)[0].runs[0].glyphs;
  ASSERT_FALSE(glyphs.empty());
  // Visual order: the first letter (seen) is the rightmost glyph.
  EXPECT_EQ(glyphs.back().cluster, 0u);
  FT_Face face = amiri.impl().face;
  EXPECT_NE(glyphs.back().glyph, FT_Get_Char_Index(face, U'\u0633')) << "seen should be initial";
}

TEST(TextShaping, NumbersInRightToLeftTextStayLeftToRight) {
  const FontFace& sans = *FontNamed("DejaVuSans").face;
  auto lines = ShapeText(sans, Text("שלום 123"));
  ASSERT_TRUE(lines.ok());
  const ShapedLine& line = (*lines)[0];
  EXPECT_TRUE(line.rtl);
  ASSERT_EQ(line.runs.size(), 2u);
  // Visual order: the digits' run first (leftmost), its glyphs 1, 2, 3.
  EXPECT_FALSE(line.runs[0].rtl);
  const auto& d = line.runs[0].glyphs;
  ASSERT_EQ(d.size(), 3u);
  EXPECT_LT(d[0].cluster, d[1].cluster);
  EXPECT_LT(d[1].cluster, d[2].cluster);
  EXPECT_TRUE(line.runs[1].rtl);
}

// The signed area of FreeType's contours, by exact quadrature of x dy - y dx
// on each piece (Gauss-Legendre, 3 points: exact to degree 5, a cubic's
// integrand), at the font's own curves: no flattening.
struct AreaSum {
  double area = 0;
  Vec2 pen;
};
Vec2 V(const FT_Vector* v) { return {double(v->x), double(v->y)}; }
double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
template <class B, class D>
double Piece(B bezier, D derivative) {
  static const double x[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  static const double w[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double t = 0.5 * (x[k] + 1.0);
    s += 0.5 * w[k] * Cross(bezier(t), derivative(t));
  }
  return 0.5 * s;
}
double ExactOutlineArea(FT_Face face, uint32_t glyph) {
  EXPECT_EQ(FT_Load_Glyph(face, glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING), 0);
  AreaSum sum;
  FT_Outline_Funcs f{};
  f.move_to = [](const FT_Vector* to, void* u) {
    static_cast<AreaSum*>(u)->pen = V(to);
    return 0;
  };
  f.line_to = [](const FT_Vector* to, void* u) {
    auto* s = static_cast<AreaSum*>(u);
    s->area += 0.5 * Cross(s->pen, V(to));
    s->pen = V(to);
    return 0;
  };
  f.conic_to = [](const FT_Vector* c, const FT_Vector* to, void* u) {
    auto* s = static_cast<AreaSum*>(u);
    const Vec2 p0 = s->pen, p1 = V(c), p2 = V(to);
    s->area += Piece(
        [&](double t) { return Vec2((1 - t) * (1 - t) * p0 + 2 * t * (1 - t) * p1 + t * t * p2); },
        [&](double t) { return Vec2(2 * (1 - t) * (p1 - p0) + 2 * t * (p2 - p1)); });
    s->pen = p2;
    return 0;
  };
  f.cubic_to = [](const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* u) {
    auto* s = static_cast<AreaSum*>(u);
    const Vec2 p0 = s->pen, p1 = V(c1), p2 = V(c2), p3 = V(to);
    s->area += Piece(
        [&](double t) {
          const double r = 1 - t;
          return Vec2(r * r * r * p0 + 3 * r * r * t * p1 + 3 * r * t * t * p2 + t * t * t * p3);
        },
        [&](double t) {
          const double r = 1 - t;
          return Vec2(3 * r * r * (p1 - p0) + 6 * r * t * (p2 - p1) + 3 * t * t * (p3 - p2));
        });
    s->pen = p3;
    return 0;
  };
  // Contours close back to their start: FreeType's decomposition does.
  EXPECT_EQ(FT_Outline_Decompose(&face->glyph->outline, &f, &sum), 0);
  // TrueType outlines run clockwise around filled areas.
  return std::abs(sum.area);
}

// Closed and consistently oriented: every directed edge once, its reverse once.
void ExpectClosedOriented(const Mesh& m, const MeshGroup& g) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t) {
    const auto& tri = m.triangles[t];
    for (int i = 0; i < 3; ++i) ++edges[{tri[i], tri[(i + 1) % 3]}];
  }
  for (const auto& [e, n] : edges) {
    ASSERT_EQ(n, 1) << g.name << ": edge used twice the same way";
    ASSERT_EQ(edges.count({e.second, e.first}), 1u) << g.name << ": an open edge";
  }
}

double Volume(const Mesh& m, const MeshGroup& g) {
  double v = 0;
  for (uint32_t t = g.first_triangle; t < g.first_triangle + g.triangle_count; ++t) {
    const auto& tri = m.triangles[t];
    v += m.positions[tri[0]].dot(m.positions[tri[1]].cross(m.positions[tri[2]])) / 6.0;
  }
  return v;
}

// DejaVuSans (TrueType: quadratic pieces) and Cantarell (CFF: cubic ones).
TEST(TextModel, GlyphsAreClosedSolidsWithTheOutlinesVolume) {
  for (const char* font : {"DejaVuSans", "Cantarell"}) {
    const FontFace& sans = *FontNamed(font).face;
    FT_Face face = sans.impl().face;
    const double upem = sans.info().units_per_em;
    for (const double tolerance : {0.01, 1e-6}) {
      TextSettings t = Text("Ada Lovelace OB8", font);
      t.tolerance_mm = tolerance;
      auto model = MakeTextModel(sans, t);
      ASSERT_TRUE(model.ok()) << model.status().ToString();
      const Mesh& m = model->mesh;
      EXPECT_EQ(CheckMesh(m), "");
      ASSERT_EQ(m.groups.size(), 14u);  // the letters; the spaces have none
      double worst = 0;
      for (const TextGlyph& g : model->glyphs) {
        if (g.group == static_cast<size_t>(-1)) continue;
        const MeshGroup& group = m.groups[g.group];
        EXPECT_EQ(group.name, g.cluster);
        ExpectClosedOriented(m, group);
        const double scale = t.size_mm / upem;
        const double area = ExactOutlineArea(face, g.glyph) * scale * scale;
        const double volume = Volume(m, group);
        EXPECT_GT(volume, 0) << g.cluster << ": inward";
        const double rel = std::abs(volume / t.depth_mm - area) / area;
        worst = std::max(worst, rel);
        // Chords stay within the tolerance of the curves: the area within
        // tolerance x perimeter (the perimeter under 4 ems).
        EXPECT_LT(std::abs(volume / t.depth_mm - area), tolerance * 4 * t.size_mm) << g.cluster;
      }
      if (tolerance < 1e-5) {
        EXPECT_LT(worst, 1e-6) << font;
      }
    }
  }
}

// The filled area of a glyph by FreeType's own rasterizer (its fill rule,
// independent of the triangulation): 1-bit pixels at 2048 per em, in font
// units squared.
double RasterArea(const std::string& bytes, uint32_t glyph) {
  FT_Library lib = nullptr;
  FT_Face face = nullptr;
  EXPECT_EQ(FT_Init_FreeType(&lib), 0);
  EXPECT_EQ(FT_New_Memory_Face(lib, reinterpret_cast<const FT_Byte*>(bytes.data()),
                               static_cast<FT_Long>(bytes.size()), 0, &face),
            0);
  constexpr int kPixelsPerEm = 2048;
  EXPECT_EQ(FT_Set_Pixel_Sizes(face, 0, kPixelsPerEm), 0);
  EXPECT_EQ(FT_Load_Glyph(face, glyph, FT_LOAD_NO_HINTING | FT_LOAD_RENDER | FT_LOAD_TARGET_MONO),
            0);
  const FT_Bitmap& b = face->glyph->bitmap;
  size_t set = 0;
  for (unsigned row = 0; row < b.rows; ++row) {
    for (unsigned col = 0; col < b.width; ++col) {
      set += (b.buffer[row * static_cast<unsigned>(b.pitch) + col / 8] >> (7 - col % 8)) & 1;
    }
  }
  const double unit = static_cast<double>(face->units_per_EM) / kPixelsPerEm;
  FT_Done_Face(face);
  FT_Done_FreeType(lib);
  return static_cast<double>(set) * unit * unit;
}

// Glyphs whose contours overlap (Lohit's "ø": the slash across the o;
// Amiri's "Ç": the cedilla into the C) are filled once: the area is what
// FreeType's rasterizer fills, well under the contours' areas summed.
TEST(TextModel, OverlappingContoursFillOnce) {
  for (const auto& [font, letter] : std::vector<std::pair<std::string, std::string>>{
           {"LohitDevanagari", "ø"}, {"Amiri", "Ç"}, {"DejaVuSans", "B"}}) {
    const Font& f = FontNamed(font);
    const FontFace& face = *f.face;
    auto cps = DecodeUtf8(letter);
    ASSERT_TRUE(cps.ok());
    const uint32_t glyph = FT_Get_Char_Index(face.impl().face, (*cps)[0]);
    ASSERT_NE(glyph, 0u) << font << " " << letter;
    auto outline = LoadGlyphOutline(face, glyph, 0.05, 1u << 20);
    ASSERT_TRUE(outline.ok());
    double summed = 0;
    for (const auto& c : outline->contours) {
      double a = 0;
      for (size_t i = 0; i < c.size(); ++i) {
        const Vec2 &p = c[i], &q = c[(i + 1) % c.size()];
        a += 0.5 * (p.x() * q.y() - q.x() * p.y());
      }
      summed += std::abs(a);
    }
    auto solid = MeshGlyph(outline->contours, outline->even_odd, 1.0, 1.0);
    ASSERT_TRUE(solid.ok());
    const double raster = RasterArea(f.bytes, glyph);
    EXPECT_NEAR(solid->area, raster, 5e-3 * raster) << font << " " << letter;
    Mesh m;
    m.positions = solid->positions;
    m.triangles = solid->triangles;
    ExpectClosedOriented(m, MeshGroup{letter, -1, 0, static_cast<uint32_t>(m.triangles.size())});
    if (letter == "ø") {
      EXPECT_GT(summed, 1.03 * solid->area) << "the slash overlaps the o: counted once";
    }
    if (letter == "Ç") {
      EXPECT_GT(summed, 1.0005 * solid->area) << "the cedilla overlaps the C";
    }
  }
}

// Euler characteristic of the flat letters of one glyph: parts - holes.
int EulerCharacteristic(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : m.triangles)
    for (int i = 0; i < 3; ++i) ++edges[std::minmax(t[i], t[(i + 1) % 3])];
  return static_cast<int>(m.positions.size()) - static_cast<int>(edges.size()) +
         static_cast<int>(m.triangles.size());
}

TEST(TextModel, HolesStayAndOverlapsFillOnce) {
  const FontFace& sans = *FontNamed("DejaVuSerif").face;
  for (const auto& [letter, chi] :
       std::vector<std::pair<std::string, int>>{{"O", 0}, {"B", -1}, {"8", -1}, {"L", 1}}) {
    TextSettings t = Text(letter, "DejaVuSerif");
    t.depth_mm = 0;
    auto model = MakeTextModel(sans, t);
    ASSERT_TRUE(model.ok()) << model.status().ToString();
    EXPECT_EQ(EulerCharacteristic(model->mesh), chi) << letter;
    for (const Vec3& p : model->mesh.positions) EXPECT_EQ(p.z(), 0.0);
  }
  // Two overlapping squares, 2 x 2, 1 apart: non-zero fills the union
  // (6), even-odd leaves the overlap out (4).
  const std::vector<std::vector<Vec2>> squares = {{{0, 0}, {2, 0}, {2, 2}, {0, 2}},
                                                  {{1, 0.5}, {3, 0.5}, {3, 2.5}, {1, 2.5}}};
  auto nonzero = MeshGlyph(squares, false, 1.0, 1.0);
  auto evenodd = MeshGlyph(squares, true, 1.0, 1.0);
  ASSERT_TRUE(nonzero.ok() && evenodd.ok());
  EXPECT_NEAR(nonzero->area, 8.0 - 1.5, 1e-12);
  EXPECT_NEAR(evenodd->area, 8.0 - 3.0, 1e-12);
  Mesh m;
  m.positions = nonzero->positions;
  m.triangles = nonzero->triangles;
  MeshGroup all{"", -1, 0, static_cast<uint32_t>(m.triangles.size())};
  ExpectClosedOriented(m, all);
  EXPECT_NEAR(Volume(m, all), 6.5, 1e-12);
  // The same square twice, one reversed: a non-zero winding of 0 is empty.
  auto cancelled = MeshGlyph({squares[0], {{0, 0}, {0, 2}, {2, 2}, {2, 0}}}, false, 1.0, 1.0);
  ASSERT_TRUE(cancelled.ok());
  EXPECT_EQ(cancelled->area, 0.0);
}

TEST(TextModel, RefusalsSayHowToFix) {
  const FontFace& sans = *FontNamed("DejaVuSans").face;
  auto missing = MakeTextModel(sans, Text("नमस्ते"));
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(missing.status().field(), "text.string");
  EXPECT_NE(missing.status().message().find("U+0928"), std::string::npos)
      << missing.status().message();
  TextSettings small = Text("Ada");
  small.size_mm = 0.1;
  auto too_small = MakeTextModel(sans, small);
  ASSERT_FALSE(too_small.ok());
  EXPECT_EQ(too_small.status().field(), "text.size_mm");
  EXPECT_NE(too_small.status().message().find("0.32 mm"), std::string::npos)
      << too_small.status().message();
  TextSettings thin = Text("Ada");
  thin.depth_mm = 0.001;
  auto too_thin = MakeTextModel(sans, thin);
  ASSERT_FALSE(too_thin.ok());
  EXPECT_EQ(too_thin.status().field(), "text.depth_mm");
  TextSettings on_path = Text("Ada Lovelace");
  on_path.path.kind = TextPathKind::kSheetPoints;
  on_path.path.sheet_points = {{0, 0}, {5, 0}, {5, 5}};
  auto too_long = MakeTextModel(sans, on_path);
  ASSERT_FALSE(too_long.ok());
  EXPECT_EQ(too_long.status().field(), "text.path");
  EXPECT_TRUE(too_long.status().has_limit());
  EXPECT_EQ(too_long.status().limit(), 10.0);
  EXPECT_NEAR(too_long.status().actual(), 27.3, 1.0);
  // Not a font: a 400.
  for (const std::string& bytes :
       {std::string(100, 'x'), std::string("\0\1\0\0", 4) + std::string(64, '\0'),
        FontNamed("DejaVuSans").bytes.substr(0, 5000)}) {
    auto font = FontFace::Open(bytes, FontLimits{});
    if (font.ok()) {  // a truncated file FreeType opens lazily: its glyphs fail
      auto model = MakeTextModel(**font, Text("Ada"));
      ASSERT_FALSE(model.ok());
      EXPECT_EQ(model.status().code(), ErrorCode::kMalformed) << model.status().ToString();
    } else {
      EXPECT_EQ(font.status().code(), ErrorCode::kMalformed) << font.status().ToString();
    }
  }
  FontLimits tight;
  tight.max_glyphs = 100;
  auto many = FontFace::Open(FontNamed("DejaVuSans").bytes, tight);
  ASSERT_FALSE(many.ok());
  EXPECT_EQ(many.status().code(), ErrorCode::kLimitExceeded);
  EXPECT_EQ(many.status().limit(), 100);
}

TEST(TextModel, AlongAnArcAndAPolyline) {
  const FontFace& sans = *FontNamed("DejaVuSans").face;
  TextSettings t = Text("ABCDE");
  t.path.kind = TextPathKind::kArc;
  t.path.arc_mm = 10;
  auto arc = MakeTextModel(sans, t);
  ASSERT_TRUE(arc.ok()) << arc.status().ToString();
  for (const TextGlyph& g : arc->glyphs) {
    // The glyph's baseline centre is on the circle round (0, -10).
    const Vec2 centre =
        g.origin + 0.5 * g.advance_mm * Vec2(std::cos(g.rotation), std::sin(g.rotation));
    EXPECT_NEAR((centre - Vec2(0, -10)).norm(), 10.0, 1e-12);
    EXPECT_NEAR(g.rotation, -g.s_mm / 10.0, 1e-12);
  }
  t.path.kind = TextPathKind::kSheetPoints;
  t.path.sheet_points = {{0, 0}, {100, 0}};
  t.align = TextAlign::kLeft;
  auto line = MakeTextModel(sans, t);
  ASSERT_TRUE(line.ok());
  EXPECT_TRUE(line->in_sheet_units);
  EXPECT_NEAR(line->glyphs[0].origin.x(), 0.0, 1e-12);
  // Consecutive origins differ by the shaped advances.
  for (size_t k = 1; k < line->glyphs.size(); ++k) {
    EXPECT_NEAR(line->glyphs[k].origin.x() - line->glyphs[k - 1].origin.x(),
                line->glyphs[k - 1].advance_mm, 1e-12);
  }
}

// A name round a full cylinder with rigid components: each glyph keeps its
// distances, and the glyphs' gaps along the surface are their gaps on the
// page.
TEST(TextModel, ANameRoundAFullCylinderKeepsEachGlyph) {
  const FontFace& sans = *FontNamed("DejaVuSans").face;
  auto model = MakeTextModel(sans, Text("Ada Lovelace"));
  ASSERT_TRUE(model.ok());
  const Mesh& word = model->mesh;
  const double radius = 8.0;  // 50 mm round: the 27 mm name covers half
  const testing::Target t = testing::Flattened(CylinderSpec{radius, 10.0, 360.0, {}}, 24);
  ASSERT_FALSE(t.sheet.points.empty());
  const SheetMap map(*t.surface, t.sheet);
  const Vec2 at(std::numbers::pi * radius, 5.0);
  PlacementOptions o = testing::KeepCoordinates(word, at);
  o.rigid = RigidMode::kComponents;
  auto r = Deform(map, word, {.placement = o});
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const Mesh& out = r->mesh;
  // The glyphs' reference points: each group's footprint centre, mapped by
  // its rigid motion (Kabsch on the glyph's vertices).
  std::vector<Vec3> flat_refs, surface_refs;
  for (const MeshGroup& g : word.groups) {
    std::vector<uint32_t> vs;
    for (uint32_t k = g.first_triangle; k < g.first_triangle + g.triangle_count; ++k)
      for (uint32_t v : word.triangles[k]) vs.push_back(v);
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    double worst = 0;
    for (size_t i = 0; i < vs.size(); i += 3)
      for (size_t j = i + 1; j < vs.size(); j += 5) {
        const double before = (word.positions[vs[i]] - word.positions[vs[j]]).norm();
        const double after = (out.positions[vs[i]] - out.positions[vs[j]]).norm();
        worst = std::max(worst, std::abs(after - before) / before);
      }
    EXPECT_LT(worst, 1e-9) << g.name;
    Eigen::AlignedBox2d box;
    Vec3 ca = Vec3::Zero(), cb = Vec3::Zero();
    for (uint32_t v : vs) {
      box.extend(word.positions[v].head<2>());
      ca += word.positions[v] / vs.size();
      cb += out.positions[v] / vs.size();
    }
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (uint32_t v : vs) h += (word.positions[v] - ca) * (out.positions[v] - cb).transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d rot = svd.matrixV() * svd.matrixU().transpose();
    if (rot.determinant() < 0) {
      Eigen::Matrix3d v = svd.matrixV();
      v.col(2) *= -1;
      rot = v * svd.matrixU().transpose();
    }
    const Vec3 ref(box.center().x(), box.center().y(), 0.0);
    flat_refs.push_back(ref);
    surface_refs.push_back(cb + rot * (ref - ca));
  }
  for (size_t k = 1; k < flat_refs.size(); ++k) {
    const Vec3 &p = surface_refs[k - 1], &q = surface_refs[k];
    EXPECT_NEAR(std::hypot(p.x(), p.y()), radius, 1e-9);
    const double turn =
        std::remainder(std::atan2(q.y(), q.x()) - std::atan2(p.y(), p.x()), 2 * std::numbers::pi);
    const double along = std::hypot(radius * turn, q.z() - p.z());
    const double flat = (flat_refs[k] - flat_refs[k - 1]).norm();
    EXPECT_NEAR(along, flat, 1e-6 * flat) << word.groups[k].name;
  }
}

}  // namespace
}  // namespace surfdeform
