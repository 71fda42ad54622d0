#pragma once
// Pointshell files (".khzshell"): a Pointshell in Kilohertz's checked binary container
// (khz/reduced/io/binary_container.hpp).
//
// Format version 1. Container magic "KHZSHELL"; the payload, in order:
//
//   matrix  points, N×3 (m), column-major (all x, then all y, then all z); every entry finite
//   matrix  normals, N×3, column-major; every entry finite, each row a unit vector (length
//           within 1e-6 of 1, as validate(const Pointshell&) demands)
//   ints    level ends, L ≥ 1 items: strictly increasing, the first > 0, the last = N
//           (N < 2³¹, so int32 holds every end)
//
// Everything is little-endian and the whole file is covered by an XXH3-64 checksum, so a
// pointshell read back is bit for bit the pointshell written. The same payload is embedded in
// deformable point tree files (point_tree_file.hpp) through append_pointshell() and
// take_pointshell().

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/pointshell/pointshell.hpp>
#include <khz/reduced/io/binary_container.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::contact {

/// The extension pointshell files use (the reader does not insist on it).
inline constexpr std::string_view pointshell_file_extension = ".khzshell";

/// The container format of pointshell files; version is the newest this build writes and reads.
inline constexpr reduced::ContainerFormat pointshell_file_format{"KHZSHELL",
                                                                 "Kilohertz pointshell file", 1};

/// Writes `pointshell` to `file` atomically: a crash or a failure leaves the previous file, if
/// any, untouched. Size: 48 bytes per point plus 4 per level and 64 of framing.
/// @throws Error if `pointshell` fails validate() or has 2³¹ points or more (nothing is
///         written).
/// @throws IoError naming `file` and the system's reason if writing fails.
KHZ_CONTACT_API void write_pointshell(const std::filesystem::path& file,
                                      const Pointshell& pointshell);

/// Reads a pointshell file; the result is bit for bit the pointshell written and passes
/// validate().
/// @throws IoError if the file cannot be read.
/// @throws ParseError "<file>: byte <offset>: <message>" if it is not a pointshell file, was
///         written by a newer format version, is truncated or corrupted (checksum), or holds a
///         value that is wrong (a matrix without 3 columns, normals not matching the points in
///         number, a non-finite entry, a normal that is not a unit vector, no levels, level
///         ends not increasing or not ending at N), at the offending value's first byte. Sizes
///         are checked against the bytes present before anything is allocated from them.
KHZ_CONTACT_API Pointshell read_pointshell(const std::filesystem::path& file);

/// read_pointshell() on bytes in memory; `source` names them in messages (for fuzzers and
/// tests).
KHZ_CONTACT_API Pointshell parse_pointshell(std::string bytes, std::string source);

/// Appends the pointshell payload described above to `writer` (for file types that embed a
/// pointshell). @throws Error as write_pointshell().
KHZ_CONTACT_API void append_pointshell(reduced::ContainerWriter& writer,
                                       const Pointshell& pointshell);

/// Reads a payload written by append_pointshell() from `reader`'s current position, with the
/// checks of read_pointshell(). @throws ParseError as read_pointshell().
KHZ_CONTACT_API Pointshell take_pointshell(reduced::ContainerReader& reader);

}  // namespace khz::contact
