#include "service/flat_sheet_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

}  // namespace

std::string FlatSheetSvg(const FlatSheet& sheet, const std::string& title, bool periodic_u,
                         bool periodic_v) {
  Eigen::AlignedBox2d box;
  for (const Vec2& p : sheet.flat) box.extend(p);
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

  // Log area ratio per cell, and the colour scale's range.
  const int cu = sheet.nu - 1;
  const int cv = sheet.nv - 1;
  std::vector<double> log_ratio(static_cast<size_t>(std::max(cu, 0)) * std::max(cv, 0), 0.0);
  double worst = 0.0;
  for (int j = 0; j < cv; ++j) {
    for (int i = 0; i < cu; ++i) {
      const int a = i + sheet.nu * j, b = a + 1, c = a + 1 + sheet.nu, d = a + sheet.nu;
      const double surface = TriangleArea(sheet.points[a], sheet.points[b], sheet.points[c]) +
                             TriangleArea(sheet.points[a], sheet.points[c], sheet.points[d]);
      const double flat = TriangleArea(sheet.flat[a], sheet.flat[b], sheet.flat[c]) +
                          TriangleArea(sheet.flat[a], sheet.flat[c], sheet.flat[d]);
      const double r = surface > 0 && flat > 0 ? std::log(flat / surface) : 0.0;
      log_ratio[i + cu * j] = r;
      worst = std::max(worst, std::abs(r));
    }
  }
  const double range = std::max(worst, 1e-3);  // never exaggerate round-off

  std::string svg;
  svg += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Fixed(width, 0) + "\" height=\"" +
         Fixed(height, 0) + "\" viewBox=\"0 0 " + Fixed(width) + " " + Fixed(height) + "\">\n";
  svg += "<title>" + title + "</title>\n";
  svg += "<g stroke=\"#333\" stroke-width=\"0.5\">\n";
  for (int j = 0; j < cv; ++j) {
    for (int i = 0; i < cu; ++i) {
      const int a = i + sheet.nu * j, b = a + 1, c = a + 1 + sheet.nu, d = a + sheet.nu;
      const double r = log_ratio[i + cu * j];
      svg += "<polygon points=\"" + map(sheet.flat[a]) + " " + map(sheet.flat[b]) + " " +
             map(sheet.flat[c]) + " " + map(sheet.flat[d]) + "\" fill=\"" + Colour(r / range) +
             "\"><title>cell (" + std::to_string(i) + ", " + std::to_string(j) + "): area ratio " +
             Fixed(std::exp(r), 5) + "</title></polygon>\n";
    }
  }
  svg += "</g>\n";
  if ((periodic_u || periodic_v) && cu > 0 && cv > 0) {
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
