#include <khz/contact/io/pointshell_file.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

constexpr const char* axis_names[] = {"x", "y", "z"};

/// Reads an N×3 matrix and checks its shape and that every entry is finite; `rows` < 0 accepts
/// any row count, otherwise it must match. Entries are column-major, so entry (s, c) is at
/// value_offset() + 8·(c·N + s).
PointMatrix take_point_matrix(reduced::ContainerReader& reader, const char* what,
                              Eigen::Index rows) {
  const std::size_t start = reader.offset();
  const Eigen::MatrixXd matrix = reader.read_matrix(what);
  if (matrix.cols() != 3) {
    reader.fail_at(start, std::string(what) + " have " + std::to_string(matrix.cols()) +
                              " columns, expected 3");
  }
  if (rows >= 0 && matrix.rows() != rows) {
    reader.fail_at(start, std::string("there are ") + std::to_string(matrix.rows()) + " " + what +
                              " for " + std::to_string(rows) + " points");
  }
  const Eigen::Index n = matrix.rows();
  for (Eigen::Index c = 0; c < 3; ++c) {
    for (Eigen::Index s = 0; s < n; ++s) {
      if (!std::isfinite(matrix(s, c))) {
        reader.fail_at(reader.value_offset() + static_cast<std::size_t>(8 * (c * n + s)),
                       std::string(what) + ": " + axis_names[c] + " of point " + std::to_string(s) +
                           " is not finite");
      }
    }
  }
  return matrix;
}

}  // namespace

void append_pointshell(reduced::ContainerWriter& writer, const Pointshell& pointshell) {
  validate(pointshell);
  if (pointshell.size() > std::numeric_limits<std::int32_t>::max()) {
    throw Error("pointshell file: " + std::to_string(pointshell.size()) +
                " points, more than the format's 2147483647");
  }
  writer.write_matrix(pointshell.points);
  writer.write_matrix(pointshell.normals);
  // validate() guarantees 0 < ends ≤ N < 2³¹.
  const std::vector<int> ends(pointshell.level_ends.begin(), pointshell.level_ends.end());
  writer.write_ints(ends);
}

Pointshell take_pointshell(reduced::ContainerReader& reader) {
  Pointshell shell;
  shell.points = take_point_matrix(reader, "points", -1);
  const Eigen::Index n = shell.points.rows();
  shell.normals = take_point_matrix(reader, "normals", n);
  for (Eigen::Index s = 0; s < n; ++s) {
    const double length = shell.normals.row(s).norm();
    if (std::abs(length - 1.0) > 1e-6) {
      reader.fail_at(reader.value_offset() + static_cast<std::size_t>(8 * s),
                     "the normal of point " + std::to_string(s) + " has length " +
                         std::to_string(length) + ", not 1");
    }
  }
  const std::size_t ends_start = reader.offset();
  const std::vector<int> ends = reader.read_ints("the level ends");
  if (ends.empty()) reader.fail_at(ends_start, "no levels");
  Eigen::Index previous = 0;
  for (std::size_t level = 0; level < ends.size(); ++level) {
    if (ends[level] <= previous) {
      reader.fail_at(reader.value_offset() + 4 * level,
                     "level " + std::to_string(level) + " ends at point " +
                         std::to_string(ends[level]) + ", not after " + std::to_string(previous));
    }
    previous = ends[level];
  }
  if (previous != n) {
    reader.fail_at(reader.value_offset() + 4 * (ends.size() - 1),
                   "the levels end at point " + std::to_string(previous) + ", not at the " +
                       std::to_string(n) + " points");
  }
  shell.level_ends.assign(ends.begin(), ends.end());
  return shell;
}

void write_pointshell(const std::filesystem::path& file, const Pointshell& pointshell) {
  reduced::ContainerWriter writer(pointshell_file_format);
  append_pointshell(writer, pointshell);
  writer.write_file(file);
}

Pointshell parse_pointshell(std::string bytes, std::string source) {
  reduced::ContainerReader reader(std::move(bytes), std::move(source), pointshell_file_format);
  Pointshell shell = take_pointshell(reader);
  reader.finish("the level ends");
  return shell;
}

Pointshell read_pointshell(const std::filesystem::path& file) {
  reduced::ContainerReader reader = reduced::ContainerReader::open(file, pointshell_file_format);
  Pointshell shell = take_pointshell(reader);
  reader.finish("the level ends");
  return shell;
}

}  // namespace khz::contact
