#pragma once
// Mesh fingerprints: a 64-bit hash that ties files computed for a mesh (bases, reduced models)
// to that exact mesh.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <cstdint>
#include <string>

namespace khz::reduced {

/// XXH3-64 (seed 0) of the mesh's discretization, as the little-endian byte sequence
///   int32 nodes per element (4 or 8), uint64 #V, uint64 #E,
///   #E×N int32 node indices (element by element), #V×3 float64 coordinates (vertex by vertex).
/// Coordinates are compared bitwise: moving a vertex by one ulp, or writing −0.0 for 0.0, gives
/// a different fingerprint; reordering vertices or elements does too. element_groups (material
/// regions) are not included. The definition is part of the basis file format and never changes;
/// the value is the same on every platform.
KHZ_REDUCED_API std::uint64_t mesh_fingerprint(const VolumeMesh& mesh);

/// A fingerprint as "0x" and 16 lowercase hex digits, the form messages and `khz info` use.
KHZ_REDUCED_API std::string fingerprint_text(std::uint64_t fingerprint);

}  // namespace khz::reduced
