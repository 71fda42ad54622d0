#pragma once
// Recorded manipulandum trajectories and rendered wrenches as CSV text (thesis §4.5: the
// simulation takes the manipulandum trajectory one data point at a time, from a device or a
// file).

#include <khz/haptic/common.hpp>
#include <khz/haptic/export.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::haptic {

/// One recorded device reading: time (s), pose (m, unit quaternion) and buttons.
struct TrajectorySample {
  double time = 0.0;
  Pose pose;
  std::uint32_t buttons = 0;
};

/// One wrench a device was asked to render, with the device time of the cycle (s).
struct RecordedWrench {
  double time = 0.0;
  Wrench wrench;
};

/// Parses a trajectory from CSV text:
///
///     t,x,y,z,qw,qx,qy,qz,buttons
///     0,0,0,0,1,0,0,0,0
///     0.001,0.0001,0,0,1,0,0,0,1
///
/// The first content line is the header: exactly these names, the `buttons` column optional.
/// Every other content line is one sample: time (s, strictly increasing), position (m), the
/// orientation as a quaternion (w first; its norm must be 1 within 10⁻³, it is normalized), and
/// with the buttons column a bitmask in [0, 2³²). Fields may be padded with spaces or tabs;
/// blank lines and lines starting with '#' are skipped; '\r\n' line ends and a UTF-8 byte-order
/// mark are accepted; numbers use '.' as the decimal point.
///
/// @param data   the file's bytes.
/// @param source name used in error messages (usually the path).
/// @throws ParseError "<source>:<line>: <message>" for a missing or wrong header, a row with the
///         wrong number of fields, a field that is not a finite number (or, for buttons, an
///         integer in range), a time that does not increase, a non-unit quaternion, or a file
///         without samples.
KHZ_HAPTIC_API std::vector<TrajectorySample> parse_trajectory(std::string_view data,
                                                              const std::string& source);

/// The CSV text parse_trajectory() reads, numbers printed to round-trip exactly; the buttons
/// column is written when `with_buttons`.
KHZ_HAPTIC_API std::string format_trajectory(std::span<const TrajectorySample> samples,
                                             bool with_buttons = true);

/// Reads a trajectory file. @throws IoError if it cannot be read; ParseError as parse_trajectory().
KHZ_HAPTIC_API std::vector<TrajectorySample> read_trajectory(const std::filesystem::path& file);

/// Writes a trajectory file. @throws IoError if it cannot be written.
KHZ_HAPTIC_API void write_trajectory(const std::filesystem::path& file,
                                     std::span<const TrajectorySample> samples,
                                     bool with_buttons = true);

/// Rendered wrenches as CSV text: header `t,fx,fy,fz,tx,ty,tz`, one row per wrench (s, N, N·m).
KHZ_HAPTIC_API std::string format_wrench_record(std::span<const RecordedWrench> record);

/// Writes format_wrench_record() to a file. @throws IoError if it cannot be written.
KHZ_HAPTIC_API void write_wrench_record(const std::filesystem::path& file,
                                        std::span<const RecordedWrench> record);

}  // namespace khz::haptic
