#include <khz/reduced/errors.hpp>
#include <khz/scene/cycle_log.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string_view>

namespace khz::scene {
namespace {

constexpr int column_count = 36;
/// Logs written before the sliding column have the first 35; before the penetration, residual
/// and energy columns, the first 31.
constexpr int metrics_column_count = 35;
constexpr int legacy_column_count = 31;

/// The values of a row in header order (booleans and counts as doubles: exact below 2⁵³).
std::array<double, column_count> columns(const CycleRow& row) {
  const auto d = [](auto v) { return static_cast<double>(v); };
  return {row.time,
          row.force.x(),
          row.force.y(),
          row.force.z(),
          row.torque.x(),
          row.torque.y(),
          row.torque.z(),
          row.rendered_force.x(),
          row.rendered_force.y(),
          row.rendered_force.z(),
          row.rendered_torque.x(),
          row.rendered_torque.y(),
          row.rendered_torque.z(),
          d(row.nodes),
          d(row.skipped),
          d(row.contacts),
          d(row.level),
          d(row.complete),
          row.query_us,
          row.cycle_us,
          row.manipulandum.x(),
          row.manipulandum.y(),
          row.manipulandum.z(),
          row.simulation.x(),
          row.simulation.y(),
          row.simulation.z(),
          row.orientation.w(),
          row.orientation.x(),
          row.orientation.y(),
          row.orientation.z(),
          d(row.ok),
          row.penetration,
          row.penetration_voxels,
          row.residual_force,
          row.energy,
          d(row.sliding)};
}

/// The columns holding counts and the level (nodes, skipped, contacts, level, sliding), and the
/// largest magnitude they may hold: the level is an int.
constexpr std::array<int, 5> integer_columns{13, 14, 15, 16, column_count - 1};
constexpr double largest_integer = 2147483647.0;

CycleRow from_columns(const std::array<double, column_count>& c) {
  const auto i64 = [](double v) { return static_cast<std::int64_t>(v); };
  CycleRow row;
  row.time = c[0];
  row.force = {c[1], c[2], c[3]};
  row.torque = {c[4], c[5], c[6]};
  row.rendered_force = {c[7], c[8], c[9]};
  row.rendered_torque = {c[10], c[11], c[12]};
  row.nodes = i64(c[13]);
  row.skipped = i64(c[14]);
  row.contacts = i64(c[15]);
  row.level = static_cast<int>(c[16]);
  row.complete = c[17] != 0.0;
  row.query_us = c[18];
  row.cycle_us = c[19];
  row.manipulandum = {c[20], c[21], c[22]};
  row.simulation = {c[23], c[24], c[25]};
  row.orientation = Eigen::Quaterniond(c[26], c[27], c[28], c[29]);
  row.ok = c[30] != 0.0;
  row.penetration = c[31];
  row.penetration_voxels = c[32];
  row.residual_force = c[33];
  row.energy = c[34];
  row.sliding = i64(c[35]);
  return row;
}

}  // namespace

CycleRow CycleRow::from(const haptic::CycleRecord& record, double cycle_us) noexcept {
  CycleRow row;
  row.time = record.time;
  row.force = record.contact.force;
  row.torque = record.contact.torque;
  row.rendered_force = record.rendered.force;
  row.rendered_torque = record.rendered.torque;
  const contact::ContactStatistics& s = record.contact.statistics;
  row.nodes = s.nodes_traversed;
  row.skipped = s.nodes_skipped;
  row.contacts = s.points_in_contact;
  row.level = s.deepest_level;
  row.complete = s.complete;
  row.query_us = s.microseconds;
  row.cycle_us = cycle_us;
  row.manipulandum = record.manipulandum.position;
  row.simulation = record.simulation.position;
  row.orientation = record.simulation.orientation;
  row.ok =
      record.device_valid && record.contact_valid && record.coupling_valid && record.integrators_ok;
  row.penetration = s.deepest_penetration;
  row.penetration_voxels = record.penetration_voxels;
  row.residual_force = record.residual.force.norm();
  row.energy = record.observed_energy;
  row.sliding = s.points_sliding;
  return row;
}

namespace {

std::string legacy_csv_header() {
  return "time,force_x,force_y,force_z,torque_x,torque_y,torque_z,rendered_force_x,"
         "rendered_force_y,rendered_force_z,rendered_torque_x,rendered_torque_y,rendered_torque_z,"
         "nodes,skipped,contacts,level,complete,query_us,cycle_us,manipulandum_x,manipulandum_y,"
         "manipulandum_z,simulation_x,simulation_y,simulation_z,orientation_w,orientation_x,"
         "orientation_y,orientation_z,ok";
}

std::string metrics_csv_header() {
  return legacy_csv_header() + ",penetration,penetration_voxels,residual_force,energy";
}

}  // namespace

std::string cycle_csv_header() { return metrics_csv_header() + ",sliding"; }

bool is_cycle_csv_header(const std::string& line) {
  return line == cycle_csv_header() || line == metrics_csv_header() || line == legacy_csv_header();
}

void write_cycle_csv(const std::vector<CycleRow>& rows, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw reduced::IoError("cannot write " + file.string());
  out << cycle_csv_header() << "\n";
  char buffer[32];
  for (const CycleRow& row : rows) {
    const auto values = columns(row);
    for (std::size_t c = 0; c < values.size(); ++c) {
      const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, values[c]);
      (void)error;
      out << (c > 0 ? "," : "") << std::string_view(buffer, static_cast<std::size_t>(end - buffer));
    }
    out << "\n";
  }
  out.flush();
  if (!out) throw reduced::IoError("cannot write " + file.string());
}

std::vector<CycleRow> parse_cycle_csv(std::string_view data, const std::string& source) {
  // One line at a time, without its '\n' (and a '\r' before it is part of the line: a row with
  // one then fails as not a number, as it did when read with std::getline).
  std::size_t position = 0;
  const auto next_line = [&](std::string_view& line) {
    if (position >= data.size()) return false;
    const std::size_t end = std::min(data.find('\n', position), data.size());
    line = data.substr(position, end - position);
    position = end + 1;
    return true;
  };
  std::string_view line;
  if (!next_line(line) || !is_cycle_csv_header(std::string(line))) {
    throw reduced::ParseError::at_line(source, 1, "expected the header of a khz run cycle log");
  }
  const int columns_here = line == legacy_csv_header()    ? legacy_column_count
                           : line == metrics_csv_header() ? metrics_column_count
                                                          : column_count;
  std::vector<CycleRow> rows;
  std::int64_t line_number = 1;
  while (next_line(line)) {
    ++line_number;
    if (line.empty()) continue;
    std::array<double, column_count> values{};
    const char* p = line.data();
    const char* const end = line.data() + line.size();
    int count = 0;
    for (; count < columns_here; ++count) {
      const auto [next, error] = std::from_chars(p, end, values[static_cast<std::size_t>(count)]);
      if (error != std::errc()) break;
      p = next;
      if (count < columns_here - 1) {
        if (p == end || *p != ',') break;
        ++p;
      }
    }
    if (count != columns_here || p != end) {
      throw reduced::ParseError::at_line(
          source, line_number,
          "expected " + std::to_string(columns_here) + " comma-separated numbers (see the header)");
    }
    // Counts and the level are written as integers; anything else (a fraction, a value no
    // integer type holds) is not a log khz run wrote, and must not reach the conversion.
    for (const int column : integer_columns) {
      const double value = values[static_cast<std::size_t>(column)];
      if (column < columns_here &&
          !(std::trunc(value) == value && std::abs(value) <= largest_integer)) {
        throw reduced::ParseError::at_line(
            source, line_number,
            "column " + std::to_string(column + 1) + " must be an integer of at most 2^31");
      }
    }
    rows.push_back(from_columns(values));
  }
  return rows;
}

std::vector<CycleRow> read_cycle_csv(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw reduced::IoError("cannot read " + file.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return parse_cycle_csv(bytes.str(), file.string());
}

}  // namespace khz::scene
