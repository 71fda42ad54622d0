#include <khz/plot/line_plot.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/render/png_file.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

namespace khz::plot {
namespace {

constexpr render::Color red{220, 30, 30}, blue{30, 60, 220}, white{255, 255, 255};

/// How many pixels of `image` have exactly `color`, and the bounding columns of those pixels.
struct ColorCount {
  long count = 0;
  int first_column = std::numeric_limits<int>::max(), last_column = -1;
};
ColorCount count_color(const render::Image& image, render::Color color) {
  ColorCount c;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      if (image.pixel(x, y) != color) continue;
      ++c.count;
      c.first_column = std::min(c.first_column, x);
      c.last_column = std::max(c.last_column, x);
    }
  }
  return c;
}

std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path directory = std::filesystem::current_path() / "scratch" / "plot";
  std::filesystem::create_directories(directory);
  return directory / name;
}

Series sine(double amplitude, render::Color color, const std::string& label) {
  Series s{label, {}, {}, color, false};
  for (int i = 0; i <= 200; ++i) {
    s.x.push_back(0.01 * i);
    s.y.push_back(amplitude * std::sin(2.0 * std::numbers::pi * s.x.back()));
  }
  return s;
}

TEST(LinePlot, DrawsEachSeriesInItsColourAcrossThePlotOnAWhitePage) {
  const std::filesystem::path file = scratch("two_sines.png");
  PlotOptions options{"force over time", "time (s)", "force (N)", 800, 500};
  write_line_plot(file, options, {sine(1.0, red, "x"), sine(0.5, blue, "y")});
  const render::Image image = render::read_png(file);
  ASSERT_EQ(image.width(), 800);
  ASSERT_EQ(image.height(), 500);
  EXPECT_EQ(image.pixel(2, 2), white);
  EXPECT_EQ(image.pixel(797, 497), white);
  // Both curves span most of the width (the x range is fitted to them).
  for (const render::Color color : {red, blue}) {
    const ColorCount c = count_color(image, color);
    EXPECT_GT(c.count, 400);
    EXPECT_GT(c.last_column - c.first_column, 500);
  }
}

TEST(LinePlot, LeavesOutNonFinitePointsAndNonPositiveOnesOnLogAxes) {
  Series s{"",
           {1.0, 10.0, std::nan(""), 100.0, -5.0, 1000.0},
           {1.0, 2.0, 3.0, 0.0, 5.0, 8.0},
           red,
           true};
  PlotOptions options;
  options.log_x = options.log_y = true;
  const std::filesystem::path file = scratch("log.png");
  write_line_plot(file, options, {s});
  EXPECT_GT(count_color(render::read_png(file), red).count, 50);
  // Nothing plottable at all is an error, not an empty picture.
  Series none{"empty", {-1.0, 0.0}, {1.0, 2.0}, red, false};
  EXPECT_THROW(write_line_plot(file, options, {none}), reduced::Error);
}

TEST(LinePlot, RejectsMismatchedSeriesBadSizesAndUnwritableFiles) {
  const auto message = [](auto&& call) {
    try {
      call();
    } catch (const reduced::Error& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  Series uneven{"torque", {0.0, 1.0, 2.0}, {0.0, 1.0}, red, false};
  EXPECT_NE(message([&] {
              write_line_plot(scratch("x.png"), {}, {uneven});
            }).find("'torque' has 3 x values and 2 y values"),
            std::string::npos);
  PlotOptions tiny;
  tiny.width = 10;
  EXPECT_NE(message([&] {
              write_line_plot(scratch("x.png"), tiny, {sine(1.0, red, "")});
            }).find("width 10"),
            std::string::npos);
  const std::filesystem::path nowhere = "/nonexistent-directory/plot.png";
  EXPECT_NE(
      message([&] { write_line_plot(nowhere, {}, {sine(1.0, red, "")}); }).find(nowhere.string()),
      std::string::npos);
}

TEST(LinePlot, AFlatSeriesIsStillVisible) {
  Series flat{"constant", {0.0, 1.0, 2.0}, {3.0, 3.0, 3.0}, blue, false};
  const std::filesystem::path file = scratch("flat.png");
  write_line_plot(file, {}, {flat});
  EXPECT_GT(count_color(render::read_png(file), blue).count, 300);
}

}  // namespace
}  // namespace khz::plot
