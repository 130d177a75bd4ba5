#include "text/text_model.hpp"

#include <cmath>
#include <map>
#include <numbers>

#include "base/format.hpp"
#include "text/glyph_mesh.hpp"
#include "text/glyph_outline.hpp"
#include "text/text_shaping.hpp"

namespace surfdeform {
namespace {

Status Invalid(const std::string& message, const std::string& field) {
  return Status(ErrorCode::kInvalidArgument, message, field);
}

std::string CodePointName(char32_t c) {
  char hex[16];
  std::snprintf(hex, sizeof hex, "U+%04X", static_cast<unsigned>(c));
  return std::string(hex) + " \"" + EncodeUtf8(c) + "\"";
}

// A glyph before the path: on its line, in mm.
struct Laid {
  uint32_t glyph;
  uint32_t cluster;
  int line;
  double x;        // the pen's position at its start
  double advance;  // along the baseline
  Vec2 offset;     // HarfBuzz's offset from the pen
};

// The baseline's frame at arc length s: a point and its unit tangent.
struct Frame {
  Vec2 p, t;
};

class Path {
 public:
  explicit Path(const TextPath& path) : path_(path) {
    if (path.kind == TextPathKind::kSheetPoints) {
      cumulative_.push_back(0.0);
      for (size_t k = 1; k < path.sheet_points.size(); ++k) {
        cumulative_.push_back(cumulative_.back() +
                              (path.sheet_points[k] - path.sheet_points[k - 1]).norm());
      }
    }
  }
  double length() const {
    if (path_.kind == TextPathKind::kSheetPoints) return cumulative_.back();
    if (path_.kind == TextPathKind::kArc) return 2.0 * std::numbers::pi * std::abs(path_.arc_mm);
    return 0.0;
  }
  Frame At(double s) const {
    switch (path_.kind) {
      case TextPathKind::kStraight:
        return {{s, 0.0}, {1.0, 0.0}};
      case TextPathKind::kArc: {
        const double r = path_.arc_mm, a = s / r;
        return {{r * std::sin(a), r * std::cos(a) - r}, {std::cos(a), -std::sin(a)}};
      }
      case TextPathKind::kSheetPoints:
        break;
    }
    const auto& pts = path_.sheet_points;
    size_t k = 1;
    while (k + 1 < cumulative_.size() && cumulative_[k] < s) ++k;
    const double len = cumulative_[k] - cumulative_[k - 1];
    const Vec2 t = (pts[k] - pts[k - 1]) / len;
    return {pts[k - 1] + (s - cumulative_[k - 1]) * t, t};
  }

 private:
  const TextPath& path_;
  std::vector<double> cumulative_;
};

size_t ClusterEnd(const std::string& text, uint32_t begin, const std::vector<uint32_t>& starts) {
  size_t end = text.size();
  const auto it = std::upper_bound(starts.begin(), starts.end(), begin);
  if (it != starts.end()) end = *it;
  const size_t nl = text.find_first_of("\r\n", begin);
  return std::min(end, nl == std::string::npos ? text.size() : nl);
}

}  // namespace

double MinTextSize(double tolerance_mm) { return kMinSizeInTolerances * tolerance_mm; }
double MinTextDepth(double tolerance_mm) { return tolerance_mm; }

Result<TextModel> MakeTextModel(const FontFace& font, const TextSettings& s,
                                const CancelFlag* cancel) {
  SURFDEFORM_RETURN_IF_ERROR(ValidateTextSettings(s));
  if (s.size_mm < MinTextSize(s.tolerance_mm)) {
    return Invalid("is below what text.tolerance_mm = " + Num(s.tolerance_mm) +
                       " can represent: the smallest size that works is " +
                       Num(MinTextSize(s.tolerance_mm)) + " mm (" + Num(kMinSizeInTolerances) +
                       " tolerances; or make the tolerance at most " +
                       Num(s.size_mm / kMinSizeInTolerances) + " mm), got " + Num(s.size_mm),
                   "text.size_mm");
  }
  if (s.depth_mm > 0.0 && s.depth_mm < MinTextDepth(s.tolerance_mm)) {
    return Invalid("is below what text.tolerance_mm = " + Num(s.tolerance_mm) +
                       " can represent: the smallest depth that works is " +
                       Num(MinTextDepth(s.tolerance_mm)) + " mm (or 0 for flat letters), got " +
                       Num(s.depth_mm),
                   "text.depth_mm");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(const std::u32string code_points, DecodeUtf8(s.string));
  const FontLimits& limits = font.limits();
  if (code_points.size() > limits.max_text_code_points) {
    return Status::LimitExceeded("the text has more code points than the limit", "text.string",
                                 static_cast<double>(limits.max_text_code_points),
                                 static_cast<double>(code_points.size()));
  }
  if (const auto missing = MissingCodePoints(font, code_points); !missing.empty()) {
    std::string list;
    for (char32_t c : missing) list += (list.empty() ? "" : ", ") + CodePointName(c);
    return Invalid(
        "the font " + font.info().family + " " + font.info().style + " has no glyph for " + list,
        "text.string");
  }
  SURFDEFORM_ASSIGN_OR_RETURN(const std::vector<ShapedLine> lines, ShapeText(font, s));
  const double scale = s.size_mm / font.info().units_per_em;  // font units to mm
  const double tolerance = s.tolerance_mm / scale;            // in font units

  TextModel model;
  model.lines = static_cast<int>(lines.size());
  std::vector<Laid> laid;
  std::vector<double> widths;
  for (size_t l = 0; l < lines.size(); ++l) {
    double pen = 0.0;
    const size_t first = laid.size();
    for (const ShapedRun& run : lines[l].runs) {
      model.runs.push_back(run.script + (run.rtl ? " rtl" : " ltr"));
      for (size_t k = 0; k < run.glyphs.size(); ++k) {
        const ShapedGlyph& g = run.glyphs[k];
        Laid d{g.glyph, g.cluster,           static_cast<int>(l),
               pen,     g.x_advance * scale, Vec2(g.x_offset * scale, g.y_offset * scale)};
        // Letter spacing after each cluster, where letters do not join.
        const bool cluster_end =
            k + 1 == run.glyphs.size() || run.glyphs[k + 1].cluster != g.cluster;
        if (cluster_end && !run.joining) d.advance += s.letter_spacing_mm;
        pen += d.advance;
        laid.push_back(d);
      }
    }
    if (laid.size() > first && s.letter_spacing_mm != 0.0) pen -= s.letter_spacing_mm;
    widths.push_back(pen);
    model.width_mm = std::max(model.width_mm, pen);
  }

  // Each distinct glyph's outline once: the text's cost first, from the
  // curves alone, then the outlines and their solids.
  std::map<uint32_t, size_t> points;
  size_t cost = 0;
  for (const Laid& d : laid) {
    auto it = points.find(d.glyph);
    if (it == points.end()) {
      SURFDEFORM_ASSIGN_OR_RETURN(size_t n, CountGlyphPoints(font, d.glyph, tolerance));
      it = points.emplace(d.glyph, n).first;
    }
    cost += it->second;
  }
  if (cost > limits.max_text_cost) {
    return Status::LimitExceeded(
        "the text's outlines at this tolerance have more points than the limit (the glyphs "
        "times their points); raise text.tolerance_mm or shorten the text",
        "text.string", static_cast<double>(limits.max_text_cost), static_cast<double>(cost));
  }
  model.outline_points = cost;
  std::map<uint32_t, GlyphSolid> solids;
  for (const auto& [glyph, n] : points) {
    if (Cancelled(cancel)) {
      return Status(ErrorCode::kDeadlineExceeded, "stopped: nobody waits for the answer", "text");
    }
    SURFDEFORM_ASSIGN_OR_RETURN(GlyphOutline outline,
                                LoadGlyphOutline(font, glyph, tolerance, n + 1));
    SURFDEFORM_ASSIGN_OR_RETURN(GlyphSolid solid,
                                MeshGlyph(outline.contours, outline.even_odd, scale, s.depth_mm));
    solids.emplace(glyph, std::move(solid));
  }

  // Lines: baselines centred on the origin's, each aligned on its path.
  const Path path(s.path);
  model.path_length_mm = path.length();
  const double spacing = s.line_spacing * s.size_mm;
  const double middle = 0.5 * static_cast<double>(lines.size() - 1);
  std::vector<uint32_t> starts;
  for (const Laid& d : laid) starts.push_back(d.cluster);
  std::sort(starts.begin(), starts.end());
  Mesh& mesh = model.mesh;
  for (const Laid& d : laid) {
    const double w = widths[static_cast<size_t>(d.line)];
    double start = 0.0;  // the line's start along the path
    if (s.path.kind == TextPathKind::kSheetPoints) {
      const double room = path.length();
      if (w > room) {
        return Status(ErrorCode::kInvalidArgument,
                      "the text's line " + std::to_string(d.line + 1) + " needs " + Num(w) +
                          " mm and the path is " + Num(room) +
                          " mm long: lengthen text.path, or make the text smaller",
                      "text.path")
            .WithLimit(room, w);
      }
      start = s.align == TextAlign::kLeft    ? 0.0
              : s.align == TextAlign::kRight ? room - w
                                             : 0.5 * (room - w);
    } else {
      start = s.align == TextAlign::kLeft ? 0.0 : s.align == TextAlign::kRight ? -w : -0.5 * w;
      if (s.path.kind == TextPathKind::kArc && w > path.length()) {
        return Status(ErrorCode::kInvalidArgument,
                      "the text's line " + std::to_string(d.line + 1) + " needs " + Num(w) +
                          " mm and a circle of radius " + Num(std::abs(s.path.arc_mm)) + " mm is " +
                          Num(path.length()) +
                          " mm round: make text.path.arc_mm larger, or the text smaller",
                      "text.path.arc_mm")
            .WithLimit(path.length(), w);
      }
    }
    const double centre = start + d.x + 0.5 * d.advance;
    const double y = (middle - d.line) * spacing;
    const Frame f = path.At(centre);
    const Vec2 n(-f.t.y(), f.t.x());
    TextGlyph g;
    g.glyph = d.glyph;
    const size_t end = ClusterEnd(s.string, d.cluster, starts);
    g.cluster = s.string.substr(d.cluster, end - d.cluster);
    g.line = d.line;
    g.s_mm = centre;
    g.advance_mm = d.advance;
    // The glyph's origin: half an advance back from its centre on the baseline.
    const Vec2 local_origin(-0.5 * d.advance + d.offset.x(), y + d.offset.y());
    g.origin = f.p + local_origin.x() * f.t + local_origin.y() * n;
    g.rotation = std::atan2(f.t.y(), f.t.x());
    const GlyphSolid& solid = solids.at(d.glyph);
    if (!solid.triangles.empty()) {
      g.group = mesh.groups.size();
      const auto base = static_cast<uint32_t>(mesh.positions.size());
      MeshGroup group;
      group.name = g.cluster;
      group.first_triangle = static_cast<uint32_t>(mesh.triangles.size());
      group.triangle_count = static_cast<uint32_t>(solid.triangles.size());
      mesh.groups.push_back(group);
      for (const Vec3& p : solid.positions) {
        const Vec2 q = g.origin + p.x() * f.t + p.y() * n;
        mesh.positions.emplace_back(q.x(), q.y(), p.z());
      }
      for (const auto& t : solid.triangles) {
        mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      }
      model.area_mm2 += solid.area * scale * scale;
    }
    model.glyphs.push_back(std::move(g));
  }
  model.in_sheet_units = s.path.kind == TextPathKind::kSheetPoints;
  if (mesh.triangles.empty()) {
    return Invalid("has no visible letter (only spaces or marks without outlines)", "text.string");
  }
  return model;
}

}  // namespace surfdeform
