#pragma once
// Distance field files (".khzsdf"): a DistanceGrid in Kilohertz's checked binary container
// (khz/reduced/io/binary_container.hpp).
//
// Format version 1. Container magic "KHZFIELD"; the payload, in order:
//
//   u32     flags: bit 0 set when the values are signed distances (DistanceGrid::is_signed());
//           every other bit zero
//   f64     origin x (m)
//   f64     origin y (m)
//   f64     origin z (m)
//   f64     spacing h (m), finite and > 0
//   i32     cells per axis, ≥ 1; the grid has n = cells + 1 nodes per axis
//   n × ints  one array per plane k = 0 … n − 1, each of n² items: the node values of that
//           plane, x fastest (GridGeometry::node_index()), each stored as the bit pattern of
//           its IEEE 754 binary32 value in an int32 (the container has no float arrays; this
//           keeps files at 4 bytes per node and bit-exact); every value finite, and ≥ 0 in an
//           unsigned field
//
// Everything is little-endian and the whole file is covered by an XXH3-64 checksum, so a grid
// read back is bit for bit the grid written.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/reduced/io/binary_container.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::contact {

/// The extension distance field files use (the reader does not insist on it).
inline constexpr std::string_view distance_field_file_extension = ".khzsdf";

/// The container format of distance field files; version is the newest this build writes and
/// reads.
inline constexpr reduced::ContainerFormat distance_field_file_format{
    "KHZFIELD", "Kilohertz distance field file", 1};

/// Writes `grid` to `file` atomically: a crash or a failure leaves the previous file, if any,
/// untouched. Memory: the file's bytes are assembled in memory first (twice the grid's
/// size at the peak, 1.1 GB for 512³ cells).
/// @throws IoError naming `file` and the system's reason if writing fails.
KHZ_CONTACT_API void write_distance_field(const std::filesystem::path& file,
                                          const DistanceGrid& grid);

/// Reads a distance field file; the result is bit for bit the grid written.
/// @throws IoError if the file cannot be read.
/// @throws ParseError "<file>: byte <offset>: <message>" if it is not a distance field file, was
///         written by a newer format version, is truncated or corrupted (checksum), or holds a
///         value that is wrong (unknown flags, non-finite origin, spacing ≤ 0, cells < 1, a
///         plane of the wrong size, a non-finite value, a negative value in an unsigned field),
///         at the offending value's first byte. Sizes are checked against the bytes present
///         before anything is allocated from them.
KHZ_CONTACT_API DistanceGrid read_distance_field(const std::filesystem::path& file);

/// read_distance_field() on bytes in memory; `source` names them in messages (for fuzzers and
/// tests).
KHZ_CONTACT_API DistanceGrid parse_distance_field(std::string bytes, std::string source);

}  // namespace khz::contact
