#pragma once
// Line plots written as PNG files: force and torque over time, cost against error. A thin layer
// over PLplot (cairo driver) that checks its input and picks axis ranges.

#include <khz/render/color.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::plot {

/// One curve: points (x[i], y[i]) joined in order. Points with a non-finite coordinate (or, on a
/// logarithmic axis, a coordinate ≤ 0) are left out and break the line there.
struct Series {
  std::string label;  ///< Shown in the legend; empty for none.
  std::vector<double> x, y;
  render::Color color{0, 0, 0};
  bool markers = false;  ///< Also mark each point.
};

/// What the plot shows around its curves.
struct PlotOptions {
  std::string title, x_label, y_label;
  int width = 1000, height = 600;     ///< Pixels, each in [100, 8000].
  bool log_x = false, log_y = false;  ///< Logarithmic (decade) axes.
};

/// Writes the series as a PNG line plot to `file`, the axes fitted to every plotted point (with a
/// small margin; a flat or single-point range is widened so it is visible).
/// @throws khz::reduced::Error if a series' x and y differ in length, no series has a plottable
///         point, or a size is out of range (the message names the series or option);
///         khz::reduced::IoError naming the file if it cannot be written.
void write_line_plot(const std::filesystem::path& file, const PlotOptions& options,
                     const std::vector<Series>& series);

}  // namespace khz::plot
