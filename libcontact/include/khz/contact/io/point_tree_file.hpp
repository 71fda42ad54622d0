#pragma once
// Deformable point tree files (".khztree"): a DeformablePointTree in Kilohertz's checked binary
// container (khz/reduced/io/binary_container.hpp).
//
// A PointTree cannot be given its arrays back (its only constructor builds it), so the file
// stores what the tree is built from — the pointshell it was built from, in that pointshell's
// own order — and the reader rebuilds the tree (deterministic; 0.09 s for 256k points). A
// topology fingerprint guards that the rebuilt tree is the one written: the modes are stored
// in the tree's point order, and a build that numbered the points differently would attach them
// to the wrong points. The per-point modes U_s and ΔN_s are stored as they are (recomputing them
// needs the volume mesh and basis); the BD-tree coefficients a_ij and the rest radii are
// recomputed from them by the plain-modes constructor, bit for bit what this build computed
// before writing.
//
// A rigid PointTree has no file type of its own: it is its source pointshell, so
//   write_pointshell(file, source_pointshell(tree));  PointTree(read_pointshell(file));
// round-trips it exactly (source_index() included).
//
// Format version 1. Container magic "KHZPTREE"; the payload, in order:
//
//   pointshell  the source pointshell, as the payload of a pointshell file (pointshell_file.hpp:
//               points, normals, level ends)
//   u64     topology fingerprint, point_tree_fingerprint() of the tree built from it
//   i32     r, the reduced dimension, ≥ 1
//   doubles displacement modes, 3r·N items: U_s for each point s in tree().pointshell() order,
//           a row-major 3×r block each (m per unit q); every entry finite
//   doubles normal modes, 3r·N items: ΔN_s, laid out as the displacement modes; every entry
//           finite
//
// Everything is little-endian and the whole file is covered by an XXH3-64 checksum.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/pointshell/pointshell.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/io/binary_container.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace khz::contact {

/// The extension deformable point tree files use (the reader does not insist on it).
inline constexpr std::string_view point_tree_file_extension = ".khztree";

/// The container format of deformable point tree files; version is the newest this build writes
/// and reads.
inline constexpr reduced::ContainerFormat point_tree_file_format{
    "KHZPTREE", "Kilohertz deformable point tree file", 1};

/// The pointshell `tree` was built from, in its original order: row tree.source_index(s) is
/// tree point s. PointTree(source_pointshell(tree)) rebuilds `tree` exactly.
KHZ_CONTACT_API Pointshell source_pointshell(const PointTree& tree);

/// A 64-bit FNV-1a hash of the tree's integer structure: the level begins, every node's point,
/// parent, first child and child count, and source_index(), as little-endian int32 in that
/// order. Floating-point data (radii) is left out: it is either stored or recomputed, and its
/// last bit could differ between compilers without the tree being a different one.
KHZ_CONTACT_API std::uint64_t point_tree_fingerprint(const PointTree& tree);

/// Writes `tree` to `file` atomically: a crash or a failure leaves the previous file, if any,
/// untouched. Size: 48 bytes per point for the pointshell plus 48r for the modes.
/// @throws IoError naming `file` and the system's reason if writing fails.
KHZ_CONTACT_API void write_deformable_point_tree(const std::filesystem::path& file,
                                                 const DeformablePointTree& tree);

/// Reads a deformable point tree file and rebuilds the tree: nodes, rest radii, points,
/// normals, modes and BD-tree coefficients are bit for bit those of the tree written (when
/// written and read by the same build).
/// @param progress Passed to the PointTree and DeformablePointTree constructors.
/// @throws IoError if the file cannot be read.
/// @throws ParseError "<file>: byte <offset>: <message>" if it is not a deformable point tree
///         file, was written by a newer format version, is truncated or corrupted (checksum),
///         holds a wrong pointshell (as read_pointshell()), r < 1, a mode array whose size is
///         not 3r per point or a non-finite mode, at the offending value's first byte; or if
///         the rebuilt tree's fingerprint differs from the stored one (at the fingerprint).
///         Sizes are checked against the bytes present before anything is allocated from them.
/// @throws Cancelled if `progress` cancels.
KHZ_CONTACT_API DeformablePointTree read_deformable_point_tree(
    const std::filesystem::path& file, const ProgressCallback& progress = {});

/// read_deformable_point_tree() on bytes in memory; `source` names them in messages (for
/// fuzzers and tests).
KHZ_CONTACT_API DeformablePointTree parse_deformable_point_tree(
    std::string bytes, std::string source, const ProgressCallback& progress = {});

}  // namespace khz::contact
