#include <khz/plot/line_plot.hpp>

#include <khz/reduced/errors.hpp>

#include <plplot/plplot.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

namespace khz::plot {

namespace {

/// A series in plotting coordinates (log10 on logarithmic axes), split into runs of plottable
/// points.
struct Runs {
  std::vector<std::vector<PLFLT>> x, y;
};

Runs plottable_runs(const Series& series, const PlotOptions& options) {
  Runs runs;
  bool open = false;
  for (std::size_t i = 0; i < series.x.size(); ++i) {
    double x = series.x[i], y = series.y[i];
    const bool usable = std::isfinite(x) && std::isfinite(y) && (!options.log_x || x > 0.0) &&
                        (!options.log_y || y > 0.0);
    if (!usable) {
      open = false;
      continue;
    }
    if (options.log_x) x = std::log10(x);
    if (options.log_y) y = std::log10(y);
    if (!open) {
      runs.x.emplace_back();
      runs.y.emplace_back();
      open = true;
    }
    runs.x.back().push_back(x);
    runs.y.back().push_back(y);
  }
  return runs;
}

/// [low, high] widened by 4% on each side, or to a visible width when flat; whole decades on a
/// logarithmic axis.
std::pair<double, double> axis_range(double low, double high, bool logarithmic) {
  if (logarithmic) return {std::floor(low), std::max(std::ceil(high), std::floor(low) + 1.0)};
  if (high - low <= 1e-12 * std::max(std::abs(low), std::abs(high))) {
    const double half = low == 0.0 ? 1.0 : 0.1 * std::abs(low);
    return {low - half, high + half};
  }
  const double margin = 0.04 * (high - low);
  return {low - margin, high + margin};
}

void check_options(const PlotOptions& options) {
  for (const auto& [name, value] :
       {std::pair{"width", options.width}, {"height", options.height}}) {
    if (value < 100 || value > 8000) {
      throw reduced::Error(std::string("write_line_plot: ") + name + " " + std::to_string(value) +
                           " is not in [100, 8000] pixels");
    }
  }
}

}  // namespace

void write_line_plot(const std::filesystem::path& file, const PlotOptions& options,
                     const std::vector<Series>& series) {
  check_options(options);
  std::vector<Runs> runs;
  double x_low = std::numeric_limits<double>::infinity(), x_high = -x_low;
  double y_low = x_low, y_high = -x_low;
  for (const Series& s : series) {
    if (s.x.size() != s.y.size()) {
      throw reduced::Error("write_line_plot: series '" + s.label + "' has " +
                           std::to_string(s.x.size()) + " x values and " +
                           std::to_string(s.y.size()) + " y values");
    }
    runs.push_back(plottable_runs(s, options));
    for (std::size_t r = 0; r < runs.back().x.size(); ++r) {
      const auto [xa, xb] = std::minmax_element(runs.back().x[r].begin(), runs.back().x[r].end());
      const auto [ya, yb] = std::minmax_element(runs.back().y[r].begin(), runs.back().y[r].end());
      x_low = std::min(x_low, *xa), x_high = std::max(x_high, *xb);
      y_low = std::min(y_low, *ya), y_high = std::max(y_high, *yb);
    }
  }
  if (!(x_low <= x_high)) {
    throw reduced::Error("write_line_plot: no series has a plottable point (" + file.string() +
                         ")");
  }
  // PLplot ends the process when it cannot open its output, so the file is tried first.
  if (!std::ofstream(file, std::ios::binary)) {
    throw reduced::IoError("write_line_plot: cannot write " + file.string());
  }
  const auto [x_min, x_max] = axis_range(x_low, x_high, options.log_x);
  const auto [y_min, y_max] = axis_range(y_low, y_high, options.log_y);

  plsdev("pngcairo");
  plsfnam(file.c_str());
  plspage(0, 0, options.width, options.height, 0, 0);
  // Colour map 0: 0 background, 1 axes and text, then one entry per series.
  plscmap0n(static_cast<PLINT>(series.size()) + 2);
  plscol0(0, 255, 255, 255);
  plscol0(1, 0, 0, 0);
  for (std::size_t s = 0; s < series.size(); ++s) {
    const render::Color& c = series[s].color;
    plscol0(static_cast<PLINT>(s) + 2, c.r, c.g, c.b);
  }
  plinit();
  plcol0(1);
  const PLINT axis = (options.log_x ? 10 : 0) + (options.log_y ? 20 : 0) + 2;  // + grid
  plenv(x_min, x_max, y_min, y_max, 0, axis);
  pllab(options.x_label.c_str(), options.y_label.c_str(), options.title.c_str());
  plwidth(2.0);
  for (std::size_t s = 0; s < series.size(); ++s) {
    plcol0(static_cast<PLINT>(s) + 2);
    for (std::size_t r = 0; r < runs[s].x.size(); ++r) {
      const auto count = static_cast<PLINT>(runs[s].x[r].size());
      if (count > 1) plline(count, runs[s].x[r].data(), runs[s].y[r].data());
      if (series[s].markers || count == 1) {
        plpoin(count, runs[s].x[r].data(), runs[s].y[r].data(), 17);
      }
    }
  }
  // The legend, top right inside the box, for the labelled series.
  std::vector<PLINT> options_array, colours, text_colours, styles, symbol_numbers;
  std::vector<PLFLT> widths, scales;
  std::vector<const char*> labels, symbols;
  for (std::size_t s = 0; s < series.size(); ++s) {
    if (series[s].label.empty()) continue;
    options_array.push_back(PL_LEGEND_LINE | (series[s].markers ? PL_LEGEND_SYMBOL : 0));
    colours.push_back(static_cast<PLINT>(s) + 2);
    text_colours.push_back(1);
    styles.push_back(1);
    widths.push_back(2.0);
    scales.push_back(1.0);
    symbol_numbers.push_back(3);
    labels.push_back(series[s].label.c_str());
    symbols.push_back("#(728)");
  }
  if (!labels.empty()) {
    PLFLT legend_width = 0.0, legend_height = 0.0;
    pllegend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
             PL_POSITION_TOP | PL_POSITION_RIGHT | PL_POSITION_INSIDE, 0.01, 0.01, 0.08, 0, 1, 1, 0,
             0, static_cast<PLINT>(labels.size()), options_array.data(), 1.0, 1.0, 2.0, 1.0,
             text_colours.data(), labels.data(), nullptr, nullptr, nullptr, nullptr, colours.data(),
             styles.data(), widths.data(), colours.data(), scales.data(), symbol_numbers.data(),
             symbols.data());
  }
  plend();
}

}  // namespace khz::plot
