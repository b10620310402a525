#pragma once
// Reading the report's SVG figures back (analysis/svg_plot.h writes them): the plotting area, the
// data group's circles, polylines, bars and paths, the texts; so a test checks what a reader sees.
#include <cmath>
#include <limits>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace glarelab::test {

struct SvgBox {
  double x = 0.0, y = 0.0, width = 0.0, height = 0.0;
  bool holds(double px, double py, double slack = 0.01) const {
    return px >= x - slack && px <= x + width + slack && py >= y - slack && py <= y + height + slack;
  }
};

struct SvgCircle {
  double cx = 0.0, cy = 0.0, r = 0.0;
  bool hollow = false;
  std::string colour;  // the fill, or the stroke of a hollow circle
};

struct SvgLine {
  std::string colour;
  std::vector<std::pair<double, double>> points;
};

// The data group (<g class="data">...</g>) of a figure.
inline std::string svg_data(const std::string& svg) {
  const std::size_t start = svg.find("<g class=\"data\">");
  const std::size_t end = svg.find("</g>", start);
  return start == std::string::npos ? std::string() : svg.substr(start, end - start);
}

inline SvgBox svg_plot_area(const std::string& svg) {
  static const std::regex pattern(
      R"re(<rect class="plot-area" x="([-0-9.e]+)" y="([-0-9.e]+)" width="([-0-9.e]+)" height="([-0-9.e]+)")re");
  std::smatch match;
  if (!std::regex_search(svg, match, pattern)) return {};
  return {std::stod(match[1]), std::stod(match[2]), std::stod(match[3]), std::stod(match[4])};
}

inline std::vector<SvgCircle> svg_circles(const std::string& svg) {
  static const std::regex pattern(
      R"re(<circle cx="([-0-9.]+)" cy="([-0-9.]+)" r="([0-9.]+)" (?:fill="white" stroke="(#[0-9a-f]+)"|fill="(#[0-9a-f]+)"))re");
  std::vector<SvgCircle> circles;
  const std::string data = svg_data(svg);
  for (auto it = std::sregex_iterator(data.begin(), data.end(), pattern); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    circles.push_back({std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), m[4].matched, m[4].matched ? m[4].str() : m[5].str()});
  }
  return circles;
}

inline std::vector<SvgLine> svg_polylines(const std::string& svg) {
  static const std::regex pattern(R"re(<polyline fill="none" stroke="(#[0-9a-f]+)"[^>]* points="([^"]*)")re");
  static const std::regex point(R"re(([-0-9.]+),([-0-9.]+))re");
  std::vector<SvgLine> lines;
  const std::string data = svg_data(svg);
  for (auto it = std::sregex_iterator(data.begin(), data.end(), pattern); it != std::sregex_iterator(); ++it) {
    SvgLine line{(*it)[1], {}};
    const std::string text = (*it)[2];
    for (auto p = std::sregex_iterator(text.begin(), text.end(), point); p != std::sregex_iterator(); ++p)
      line.points.emplace_back(std::stod((*p)[1]), std::stod((*p)[2]));
    lines.push_back(std::move(line));
  }
  return lines;
}

// Every coordinate pair of the data group's paths (error bars, arrowheads), by the path's stroke.
inline std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>> svg_paths(const std::string& svg) {
  static const std::regex pattern(R"re(<path fill="none" stroke="(#[0-9a-f]+)" stroke-width="[0-9.]+" d="([^"]*)")re");
  static const std::regex command(R"re(([MLHV])([-0-9.]+)(?:,([-0-9.]+))?)re");
  std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>> paths;
  const std::string data = svg_data(svg);
  for (auto it = std::sregex_iterator(data.begin(), data.end(), pattern); it != std::sregex_iterator(); ++it) {
    std::vector<std::pair<double, double>> points;
    double x = 0.0, y = 0.0;
    const std::string d = (*it)[2];
    for (auto c = std::sregex_iterator(d.begin(), d.end(), command); c != std::sregex_iterator(); ++c) {
      const std::string op = (*c)[1];
      if (op == "H") x = std::stod((*c)[2]);
      else if (op == "V") y = std::stod((*c)[2]);
      else x = std::stod((*c)[2]), y = std::stod((*c)[3]);
      points.emplace_back(x, y);
    }
    paths.emplace_back((*it)[1], std::move(points));
  }
  return paths;
}

// The data group's bars: x, y, width, height and fill.
struct SvgBar {
  double x = 0.0, y = 0.0, width = 0.0, height = 0.0;
  std::string colour;
};

inline std::vector<SvgBar> svg_bars(const std::string& svg) {
  static const std::regex pattern(
      R"re(<rect x="([-0-9.]+)" y="([-0-9.]+)" width="([-0-9.]+)" height="([-0-9.]+)" fill="(#[0-9a-f]+)"/>)re");
  std::vector<SvgBar> bars;
  const std::string data = svg_data(svg);
  for (auto it = std::sregex_iterator(data.begin(), data.end(), pattern); it != std::sregex_iterator(); ++it)
    bars.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]), std::stod((*it)[4]), (*it)[5]});
  return bars;
}

// The numeric x axis' ticks: (pixel x, value) from the tick labels 18 px below the plotting area.
inline std::vector<std::pair<double, double>> svg_x_ticks(const std::string& svg) {
  const SvgBox area = svg_plot_area(svg);
  static const std::regex pattern(R"re(<text x="([-0-9.]+)" y="([-0-9.]+)" text-anchor="middle">([-0-9.e+]+)</text>)re");
  std::vector<std::pair<double, double>> ticks;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), pattern); it != std::sregex_iterator(); ++it)
    if (std::abs(std::stod((*it)[2]) - (area.y + area.height + 18.0)) < 0.01)
      ticks.emplace_back(std::stod((*it)[1]), std::stod((*it)[3]));
  return ticks;
}

// The y value of a polyline at pixel x (linear between its points); NaN outside it.
inline double polyline_y_at(const SvgLine& line, double x) {
  for (std::size_t i = 1; i < line.points.size(); ++i) {
    const auto [x0, y0] = line.points[i - 1];
    const auto [x1, y1] = line.points[i];
    if (x >= x0 && x <= x1 && x1 > x0) return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace glarelab::test
