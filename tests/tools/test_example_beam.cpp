// examples/beam_reduced_vs_full --small end to end, judged from its output files alone: the CSV
// is complete and finite, the full beam bends far into the nonlinear range, the reduced tip
// follows the full one about as closely as the thesis's modal-derivative bases do, a reduced
// step costs less, and every picture shows a beam in each half.
// KHZ_BEAM_EXAMPLE_PATH (the example's executable) comes from tests/CMakeLists.txt.
#include <khz/render/png_file.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace khz::test {
namespace {

constexpr double beam_length = 0.3;   // m, the example's cantilever
constexpr double release_time = 0.6;  // s, when the example lets go of the tip

// One line of beam.csv.
struct Row {
  double time = 0;
  Eigen::Vector3d tip_full, tip_reduced;
  double relative_error = 0, full_us = 0, reduced_us = 0;
};

// The rows of beam.csv, or none if the file is missing or its header is not the expected one; a
// cell that does not parse reads as NaN, which the finiteness check reports.
std::vector<Row> read_rows(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) ||
      line !=
          "time,tip_full_x,tip_full_y,tip_full_z,tip_reduced_x,tip_reduced_y,tip_reduced_z,"
          "relative_error,full_us,reduced_us") {
    return {};
  }
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<double> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) {
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);
      cells.push_back(end != cell.c_str() && *end == '\0' ? value : std::nan(""));
    }
    cells.resize(10, std::nan(""));
    rows.push_back({cells[0],
                    {cells[1], cells[2], cells[3]},
                    {cells[4], cells[5], cells[6]},
                    cells[7],
                    cells[8],
                    cells[9]});
  }
  return rows;
}

struct ExampleRun {
  std::filesystem::path out;
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
  std::vector<Row> rows;
};

ExampleRun run_small() {
  ExampleRun run;
  run.out = scratch_directory("beam_output");
  const std::filesystem::path log = scratch_file("beam_example.txt");
  const std::string command = std::string("\"") + KHZ_BEAM_EXAMPLE_PATH + "\" --small --out \"" +
                              run.out.string() + "\" > \"" + log.string() + "\" 2>&1";
  const int status = std::system(command.c_str());
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.output = read_bytes(log);
  run.rows = read_rows(run.out / "beam.csv");
  return run;
}

// Times at which the tip's vertical displacement changes sign after the release, interpolated.
std::vector<double> zero_crossings(const std::vector<Row>& rows, bool reduced) {
  std::vector<double> crossings;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i - 1].time <= release_time) continue;
    const double a = (reduced ? rows[i - 1].tip_reduced : rows[i - 1].tip_full).z();
    const double b = (reduced ? rows[i].tip_reduced : rows[i].tip_full).z();
    if ((a < 0) != (b < 0)) {
      crossings.push_back(rows[i - 1].time + (rows[i].time - rows[i - 1].time) * a / (a - b));
    }
  }
  return crossings;
}

// The free swing's period from its zero crossings (half a period apart).
std::optional<double> period(const std::vector<double>& crossings) {
  if (crossings.size() < 2) return std::nullopt;
  return 2 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

void expect_complete_and_finite(const std::vector<Row>& rows) {
  ASSERT_GE(rows.size(), 500u) << "beam.csv is missing, has another header or is short";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    ASSERT_TRUE(std::isfinite(r.time) && r.tip_full.allFinite() && r.tip_reduced.allFinite() &&
                std::isfinite(r.relative_error) && std::isfinite(r.full_us) &&
                std::isfinite(r.reduced_us))
        << "row " << i + 1;
    if (i > 0) {
      EXPECT_GT(r.time, rows[i - 1].time) << "row " << i + 1;
    }
  }
  EXPECT_GT(rows.back().time, release_time + 0.3) << "the run must include the free swing";
}

void expect_large_deformation(const std::vector<Row>& rows) {
  double largest = 0;
  for (const Row& r : rows) largest = std::max(largest, r.tip_full.norm());
  // Measured with --small: 154 mm, 51 % of the length.
  EXPECT_GE(largest, 0.2 * beam_length);
}

// Thresholds from the thesis's modal-derivative spoon (§2.13.1, r = 12): "almost correct
// amplitudes" and a 4.6 % error in the nonlinear frequency. A reduced run with exact amplitudes
// and that frequency error would score 11 % on the tip trajectory below (computed from this run's
// full trajectory, its free swing time-scaled by 4.6 %). Measured with --small, r = 18: loaded
// error 0.8 %, trajectory 1.8 %, frequency 0.3 %.
void expect_reduced_tip_follows(const std::vector<Row>& rows) {
  double loaded_error = 0, error_squares = 0, squares = 0;
  for (const Row& r : rows) {
    if (r.time <= release_time) loaded_error = std::max(loaded_error, r.relative_error);
    error_squares += (r.tip_reduced - r.tip_full).squaredNorm();
    squares += r.tip_full.squaredNorm();
  }
  // While loaded: the whole volume's mass-weighted error, relative to the largest displacement.
  EXPECT_LT(loaded_error, 0.05);
  EXPECT_LT(std::sqrt(error_squares / squares), 0.10);

  const std::optional<double> full = period(zero_crossings(rows, false));
  const std::optional<double> reduced = period(zero_crossings(rows, true));
  ASSERT_TRUE(full && reduced) << "the free swing must cross the rest position twice";
  EXPECT_LT(std::abs(*full / *reduced - 1.0), 0.046);
}

void expect_reduced_steps_cheaper(const std::vector<Row>& rows) {
  double full = 0, reduced = 0;
  for (const Row& r : rows) {
    full += r.full_us;
    reduced += r.reduced_us;
  }
  EXPECT_LT(reduced, full);
}

// Pixels clearly blue (the full model's colour) or orange (the reduced one's) in columns
// [begin, end): the grey clamp plate and white background count for neither.
struct ColouredPixels {
  int blue = 0, orange = 0;
};

ColouredPixels coloured_pixels(const render::Image& image, int begin, int end) {
  ColouredPixels count;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = begin; x < end; ++x) {
      const render::Color c = image.pixel(x, y);
      count.blue += c.b > c.r + 40;
      count.orange += c.r > c.b + 40;
    }
  }
  return count;
}

// Every frame: the full beam on the left, the reduced one on the right.
void expect_frames(const std::filesystem::path& out) {
  int frames = 0;
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("frame_") || entry.path().extension() != ".png") continue;
    SCOPED_TRACE(name);
    ++frames;
    const render::Image image = render::read_png(entry.path());
    const int half = image.width() / 2;
    const ColouredPixels left = coloured_pixels(image, 0, half);
    const ColouredPixels right = coloured_pixels(image, half, image.width());
    EXPECT_GT(left.blue, 500);
    EXPECT_EQ(left.orange, 0);
    EXPECT_GT(right.orange, 500);
    EXPECT_EQ(right.blue, 0);
  }
  // Rest, deepest, highest after the release, end.
  EXPECT_EQ(frames, 4);
}

void expect_plot(const std::filesystem::path& out) {
  const render::Image plot = render::read_png(out / "tip.png");
  const ColouredPixels lines = coloured_pixels(plot, 0, plot.width());
  EXPECT_GT(lines.blue, 200);
  EXPECT_GT(lines.orange, 200);
}

// One test, one run of the example (a few seconds): CTest runs every test in its own process.
// The suite is named after the target, so `ctest -R example_beam` selects it.
TEST(example_beam, SmallRunAgainstTheFullModel) {
  const ExampleRun run = run_small();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("speed-up"), std::string::npos) << run.output;
  {
    SCOPED_TRACE("beam.csv");
    ASSERT_NO_FATAL_FAILURE(expect_complete_and_finite(run.rows));
    expect_large_deformation(run.rows);
    expect_reduced_tip_follows(run.rows);
    expect_reduced_steps_cheaper(run.rows);
  }
  expect_frames(run.out);
  expect_plot(run.out);
}

}  // namespace
}  // namespace khz::test
