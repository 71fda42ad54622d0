#include <khz/haptic/device/trajectory_file.hpp>

#include "device/pose_math.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

namespace khz::haptic {
namespace {

constexpr std::array<std::string_view, 9> column_names = {"t",  "x",  "y",  "z",      "qw",
                                                          "qx", "qy", "qz", "buttons"};
constexpr std::size_t pose_columns = 8;
constexpr std::string_view utf8_bom = "\xEF\xBB\xBF";

std::string_view trim(std::string_view text) noexcept {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

/// `text` for an error message: quoted, at most 40 characters, control bytes shown as '?'.
std::string quoted(std::string_view text) {
  std::string out = "'";
  for (const char c : text.substr(0, 40)) out += (static_cast<unsigned char>(c) < 32) ? '?' : c;
  return out + (text.size() > 40 ? "...'" : "'");
}

/// Walks the content lines of a CSV text and splits them into trimmed fields.
class CsvLines {
 public:
  CsvLines(std::string_view data, std::string source) : m_data(data), m_source(std::move(source)) {
    if (m_data.starts_with(utf8_bom)) m_data.remove_prefix(utf8_bom.size());
  }

  /// Moves to the next line that is neither blank nor a '#' comment. False at the end.
  bool next() {
    while (m_next < m_data.size()) {
      const std::size_t end = std::min(m_data.find('\n', m_next), m_data.size());
      m_line = trim(m_data.substr(m_next, end - m_next));
      m_next = end + 1;
      ++m_line_number;
      if (!m_line.empty() && m_line.front() != '#') return true;
    }
    ++m_line_number;  // errors about a missing line point just past the last one
    return false;
  }

  /// Splits the current line at commas; returns the number of fields (only the first
  /// fields.size() are stored).
  template <std::size_t N>
  std::size_t split(std::array<std::string_view, N>& fields) const {
    std::string_view rest = m_line;
    std::size_t count = 0;
    for (;;) {
      const std::size_t comma = rest.find(',');
      if (count < N) fields[count] = trim(rest.substr(0, comma));
      ++count;
      if (comma == std::string_view::npos) return count;
      rest.remove_prefix(comma + 1);
    }
  }

  std::string_view line() const noexcept { return m_line; }

  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError::at_line(m_source, m_line_number, message);
  }

 private:
  std::string_view m_data;
  std::string m_source;
  std::size_t m_next = 0;
  std::int64_t m_line_number = 0;
  std::string_view m_line;
};

template <typename T>
bool parse_number(std::string_view field, T& value) noexcept {
  const char* end = field.data() + field.size();
  const auto result = std::from_chars(field.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

template <typename T>
void append_number(std::string& out, T value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
}

template <std::size_t N>
void append_row(std::string& out, const std::array<double, N>& values) {
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += ',';
    append_number(out, values[i]);
  }
}

std::size_t read_header(CsvLines& lines) {
  const std::string expected = "t,x,y,z,qw,qx,qy,qz[,buttons]";
  if (!lines.next()) lines.fail("file ends early: expected the header '" + expected + "'");
  std::array<std::string_view, column_names.size()> fields;
  const std::size_t count = lines.split(fields);
  const bool names_match =
      (count == pose_columns || count == column_names.size()) &&
      std::equal(fields.begin(), fields.begin() + static_cast<std::ptrdiff_t>(count),
                 column_names.begin());
  if (!names_match) {
    lines.fail("expected the header '" + expected + "', found " + quoted(lines.line()));
  }
  return count;
}

std::string read_whole_file(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw IoError("cannot open '" + file.string() + "' for reading");
  std::string bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
  if (stream.bad()) throw IoError("cannot read '" + file.string() + "'");
  return bytes;
}

void write_whole_file(const std::filesystem::path& file, std::string_view bytes) {
  std::ofstream stream(file, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  stream.close();
  if (!stream) throw IoError("cannot write '" + file.string() + "'");
}

}  // namespace

std::vector<TrajectorySample> parse_trajectory(std::string_view data, const std::string& source) {
  CsvLines lines(data, source);
  const std::size_t columns = read_header(lines);
  std::vector<TrajectorySample> samples;
  std::array<std::string_view, column_names.size()> fields;
  while (lines.next()) {
    const std::size_t count = lines.split(fields);
    if (count != columns) {
      lines.fail("expected " + std::to_string(columns) + " comma-separated fields, found " +
                 std::to_string(count));
    }
    std::array<double, pose_columns> values;
    for (std::size_t c = 0; c < pose_columns; ++c) {
      if (!parse_number(fields[c], values[c]) || !std::isfinite(values[c])) {
        lines.fail("expected " + std::string(column_names[c]) + " (a finite number), found " +
                   quoted(fields[c]));
      }
    }
    TrajectorySample sample;
    sample.time = values[0];
    if (!samples.empty() && !(sample.time > samples.back().time)) {
      lines.fail("time " + std::string(fields[0]) +
                 " does not increase (times must be strictly increasing)");
    }
    sample.pose.position = Eigen::Vector3d(values[1], values[2], values[3]);
    sample.pose.orientation = Eigen::Quaterniond(values[4], values[5], values[6], values[7]);
    if (!detail::is_valid_pose(sample.pose)) {
      lines.fail("the quaternion (qw,qx,qy,qz) has norm " +
                 std::to_string(sample.pose.orientation.norm()) + ", expected 1 (within 1e-3)");
    }
    sample.pose.orientation.normalize();
    if (columns == column_names.size()) {
      std::uint64_t buttons = 0;
      if (!parse_number(fields[pose_columns], buttons) ||
          buttons > std::numeric_limits<std::uint32_t>::max()) {
        lines.fail("expected buttons (an integer bitmask in [0, 4294967295]), found " +
                   quoted(fields[pose_columns]));
      }
      sample.buttons = static_cast<std::uint32_t>(buttons);
    }
    samples.push_back(sample);
  }
  if (samples.empty()) lines.fail("file ends early: expected at least one sample");
  return samples;
}

std::string format_trajectory(std::span<const TrajectorySample> samples, bool with_buttons) {
  std::string out = with_buttons ? "t,x,y,z,qw,qx,qy,qz,buttons\n" : "t,x,y,z,qw,qx,qy,qz\n";
  for (const TrajectorySample& s : samples) {
    const Eigen::Vector3d& p = s.pose.position;
    const Eigen::Quaterniond& q = s.pose.orientation;
    append_row(out, std::array{s.time, p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()});
    if (with_buttons) {
      out += ',';
      append_number(out, s.buttons);
    }
    out += '\n';
  }
  return out;
}

std::vector<TrajectorySample> read_trajectory(const std::filesystem::path& file) {
  return parse_trajectory(read_whole_file(file), file.string());
}

void write_trajectory(const std::filesystem::path& file, std::span<const TrajectorySample> samples,
                      bool with_buttons) {
  write_whole_file(file, format_trajectory(samples, with_buttons));
}

std::string format_wrench_record(std::span<const RecordedWrench> record) {
  std::string out = "t,fx,fy,fz,tx,ty,tz\n";
  for (const RecordedWrench& r : record) {
    const Eigen::Vector3d& f = r.wrench.force;
    const Eigen::Vector3d& t = r.wrench.torque;
    append_row(out, std::array{r.time, f.x(), f.y(), f.z(), t.x(), t.y(), t.z()});
    out += '\n';
  }
  return out;
}

void write_wrench_record(const std::filesystem::path& file,
                         std::span<const RecordedWrench> record) {
  write_whole_file(file, format_wrench_record(record));
}

}  // namespace khz::haptic
