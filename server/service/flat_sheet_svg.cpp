#include "service/flat_sheet_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "engine/flatten/mesh_flatten.hpp"

namespace surfdeform {
namespace {

std::string Fixed(double x, int digits = 2) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

// Blue (t = -1) .. white (0) .. red (+1).
std::string Colour(double t) {
  t = std::clamp(t, -1.0, 1.0);
  const int fade = static_cast<int>(std::lround(255.0 * (1.0 - std::abs(t))));
  char buf[16];
  if (t >= 0) {
    std::snprintf(buf, sizeof buf, "#ff%02x%02x", fade, fade);
  } else {
    std::snprintf(buf, sizeof buf, "#%02x%02xff", fade, fade);
  }
  return buf;
}

double TriangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

double TriangleArea(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 e = b - a;
  const Vec2 f = c - a;
  return 0.5 * std::abs(e.x() * f.y() - e.y() * f.x());
}

// One coloured piece of the picture: a grid cell or a mesh triangle, in
// sheet coordinates, with its log area ratio.
struct Patch {
  std::vector<Vec2> corners;
  double log_ratio = 0.0;
  std::string title;
};

double LogRatio(double surface, double flat) {
  return surface > 0 && flat > 0 ? std::log(flat / surface) : 0.0;
}

// The patches of the sheet: its grid's cells, or a mesh surface's flat
// triangles (in the sheet's frame).
std::vector<Patch> PatchesOf(const FlatSheet& sheet, const FlatMesh* mesh) {
  std::vector<Patch> patches;
  if (mesh != nullptr) {
    const std::vector<Vec3>& x = mesh->mesh.positions;
    for (size_t f = 0; f < mesh->mesh.triangles.size(); ++f) {
      const auto& t = mesh->mesh.triangles[f];
      Patch p;
      for (int v : t) p.corners.push_back(sheet.frame_linear * mesh->flat[v] + sheet.frame_offset);
      p.log_ratio = LogRatio(TriangleArea(x[t[0]], x[t[1]], x[t[2]]),
                             TriangleArea(p.corners[0], p.corners[1], p.corners[2]));
      p.title = "triangle " + std::to_string(f);
      patches.push_back(std::move(p));
    }
    return patches;
  }
  for (int j = 0; j + 1 < sheet.nv; ++j) {
    for (int i = 0; i + 1 < sheet.nu; ++i) {
      const int a = i + sheet.nu * j, b = a + 1, c = a + 1 + sheet.nu, d = a + sheet.nu;
      const double surface = TriangleArea(sheet.points[a], sheet.points[b], sheet.points[c]) +
                             TriangleArea(sheet.points[a], sheet.points[c], sheet.points[d]);
      const double flat = TriangleArea(sheet.flat[a], sheet.flat[b], sheet.flat[c]) +
                          TriangleArea(sheet.flat[a], sheet.flat[c], sheet.flat[d]);
      Patch p;
      p.corners = {sheet.flat[a], sheet.flat[b], sheet.flat[c], sheet.flat[d]};
      p.log_ratio = LogRatio(surface, flat);
      p.title = "cell (" + std::to_string(i) + ", " + std::to_string(j) + ")";
      patches.push_back(std::move(p));
    }
  }
  return patches;
}

}  // namespace

std::string FlatSheetSvg(const FlatSheet& sheet, const std::string& title, bool periodic_u,
                         bool periodic_v, const FlatMesh* mesh) {
  const std::vector<Patch> patches = PatchesOf(sheet, mesh);
  Eigen::AlignedBox2d box;
  for (const Patch& p : patches) {
    for (const Vec2& c : p.corners) box.extend(c);
  }
  if (patches.empty()) box.extend(Vec2::Zero());
  const double extent = std::max(box.sizes().maxCoeff(), 1e-300);
  const double size = 800.0;  // drawing units for the longer side
  const double scale = size / extent;
  const double margin = 20.0;
  const double legend = 60.0;
  const double width = box.sizes().x() * scale + 2 * margin;
  const double height = box.sizes().y() * scale + 2 * margin + legend;
  // Sheet y up, SVG y down.
  auto map = [&](const Vec2& p) {
    return Fixed(margin + (p.x() - box.min().x()) * scale) + "," +
           Fixed(margin + (box.max().y() - p.y()) * scale);
  };
  double worst = 0.0;
  for (const Patch& p : patches) worst = std::max(worst, std::abs(p.log_ratio));
  const double range = std::max(worst, 1e-3);  // never exaggerate round-off

  std::string svg;
  svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Fixed(width, 0) + "\" height=\"" +
         Fixed(height, 0) + "\" viewBox=\"0 0 " + Fixed(width) + " " + Fixed(height) + "\">\n";
  svg += "<title>" + title + "</title>\n";
  svg +=
      "<g stroke=\"#333\" stroke-width=\"" + std::string(mesh != nullptr ? "0.2" : "0.5") + "\">\n";
  for (const Patch& p : patches) {
    svg += "<polygon points=\"";
    for (size_t k = 0; k < p.corners.size(); ++k) {
      if (k > 0) svg += ' ';
      svg += map(p.corners[k]);
    }
    svg += "\" fill=\"" + Colour(p.log_ratio / range) + "\"><title>" + p.title + ": area ratio " +
           Fixed(std::exp(p.log_ratio), 5) + "</title></polygon>\n";
  }
  svg += "</g>\n";
  const int cu = sheet.nu - 1;
  const int cv = sheet.nv - 1;
  if (mesh == nullptr && (periodic_u || periodic_v) && cu > 0 && cv > 0) {
    // The seams: the two sides of each are one line on the surface.
    svg +=
        "<g class=\"seam\" fill=\"none\" stroke=\"#c60\" stroke-width=\"2\" "
        "stroke-dasharray=\"6 4\"><title>the seam: a model may cross it</title>\n";
    auto line = [&](int start, int step, int count) {
      svg += "<polyline points=\"";
      for (int k = 0; k <= count; ++k) {
        if (k > 0) svg += ' ';
        svg += map(sheet.flat[start + step * k]);
      }
      svg += "\"/>\n";
    };
    if (periodic_u) {
      for (int i : {0, cu}) line(i, sheet.nu, cv);
    }
    if (periodic_v) {
      for (int j : {0, cv}) line(sheet.nu * j, 1, cu);
    }
    svg += "</g>\n";
  }
  // Legend: the colour scale and what its ends mean.
  const double y = height - legend + 15;
  svg += "<g font-family=\"sans-serif\" font-size=\"12\">\n";
  for (int k = 0; k <= 20; ++k) {
    const double t = -1.0 + 0.1 * k;
    svg += "<rect x=\"" + Fixed(margin + 12.0 * k) + "\" y=\"" + Fixed(y) +
           "\" width=\"12\" height=\"12\" fill=\"" + Colour(t) + "\"/>\n";
  }
  svg += "<text x=\"" + Fixed(margin) + "\" y=\"" + Fixed(y + 28) + "\">flat/surface area " +
         Fixed(std::exp(-range), 4) + "</text>\n";
  svg += "<text x=\"" + Fixed(margin + 252.0) + "\" y=\"" + Fixed(y + 10) + "\">" +
         Fixed(std::exp(range), 4) + " (stress " + Fixed(sheet.quality.stress, 6) +
         ", max edge error " + Fixed(sheet.quality.max_edge_error, 6) + ")</text>\n";
  svg += "</g>\n</svg>\n";
  return svg;
}

}  // namespace surfdeform
