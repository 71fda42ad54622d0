#pragma once
// Frames of a ParaView time series as VTK XML PolyData files (.vtp): a triangle surface or a
// point cloud, with named point-data arrays.
//
// Encoding: VTKFile version 1.0, byte_order LittleEndian, header_type UInt64, every array in
// one "appended raw" block at the end of the file (each array a UInt64 byte count followed by
// its values, little-endian on any host). That is 8 bytes per double, bit-exact, with no
// encoding or decoding work; inline base64 would be 4/3 as large. The part before the block
// is plain XML, but the block itself is binary, so the file as a whole is not an XML
// document: read it with VTK/ParaView (or skip the bytes from the '_' after
// <AppendedData encoding="raw"> as the VTK format describes).

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/series/point_array.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <vector>

namespace khz::series {

/// Writes a triangle surface as VTK XML PolyData (one VTK polygon cell per triangle).
/// The first scalar array of `point_data` becomes the active scalars, the first 3-vector array
/// the active vectors (ParaView's defaults for colouring and for the Glyph filter).
/// The file is written through a temporary file in the same directory renamed over `file`,
/// so a reader never sees part of it and a failure leaves an earlier file untouched.
/// @param file Output path (by convention with the extension ".vtp").
/// @param vertices #V×3 positions in the units of the caller (written as Float64 as they are,
///        non-finite values included).
/// @param triangles #F×3 zero-based indices into `vertices` (written as Int32).
/// @param point_data Arrays with #V rows each.
/// @throws reduced::MeshError naming the triangle if an index is outside [0, #V);
///         reduced::Error if an array has the wrong number of rows, an empty or duplicate name
///         or a control character in its name, or if 3·#F exceeds the Int32 range (all
///         checked before anything is written); reduced::IoError naming `file` and the
///         system's reason if it cannot be written.
void write_surface_vtp(const std::filesystem::path& file,
                       const Eigen::Ref<const reduced::VertexMatrix>& vertices,
                       const Eigen::Ref<const reduced::TriangleMatrix>& triangles,
                       const std::vector<PointArray>& point_data = {});

/// Writes a point cloud as VTK XML PolyData: one VTK vertex cell per point, so ParaView draws
/// every point. A set of arrows (e.g. contact forces) is a point cloud of their start points
/// with the arrow vectors as a 3-vector array: ParaView's Glyph filter (glyph type Arrow)
/// draws them, oriented and scaled by the active vectors. Active arrays, writing and failures
/// as write_surface_vtp().
/// @param file Output path (by convention with the extension ".vtp").
/// @param points #P×3 positions in the units of the caller.
/// @param point_data Arrays with #P rows each.
/// @throws reduced::Error for inconsistent arrays (as write_surface_vtp()) or more than
///         2³¹ − 1 points; reduced::IoError naming `file` if it cannot be written.
void write_point_cloud_vtp(const std::filesystem::path& file,
                           const Eigen::Ref<const reduced::VertexMatrix>& points,
                           const std::vector<PointArray>& point_data = {});

}  // namespace khz::series
