#pragma once
// Export of distance grids to VTK XML image data (".vti"), for ParaView and other VTK readers.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_grid.hpp>

#include <filesystem>
#include <string>

namespace khz::contact {

/// How the node values are written into the .vti file.
enum class VtiEncoding {
  /// Inline base64 of a UInt64 byte count followed by the raw Float32 values (VTK's "binary"
  /// format, uncompressed): about 5.3 bytes per node, bit-exact.
  base64,
  /// Decimal text, the shortest form that reads back as the same float: up to 16 bytes per
  /// node, readable with any text tool.
  ascii,
};

/// The grid as a VTK XML ImageData document (VTKFile version 1.0, header_type UInt64, the
/// host's byte order): WholeExtent 0 … cells on each axis, Origin and Spacing from the
/// geometry, and one point-data array of Float32 named "signed_distance" or "distance" (as
/// DistanceGrid::is_signed()) holding the node values, x fastest.
KHZ_CONTACT_API std::string format_distance_field_vti(const DistanceGrid& grid,
                                                      VtiEncoding encoding = VtiEncoding::base64);

/// Writes format_distance_field_vti() to `file` (by convention with the extension ".vti"),
/// streaming the values, through a temporary file in the same directory renamed over `file`,
/// so that a failure leaves the previous file, if any, untouched.
/// @throws IoError naming `file` and the reason if writing fails.
KHZ_CONTACT_API void write_distance_field_vti(const std::filesystem::path& file,
                                              const DistanceGrid& grid,
                                              VtiEncoding encoding = VtiEncoding::base64);

}  // namespace khz::contact
