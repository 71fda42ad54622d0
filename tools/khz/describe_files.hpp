#pragma once
// What `khz info` prints for each kind of file (command_info.cpp picks the describer by the
// file's extension), and the line layout the describers share. Every describer throws
// reduced::Error (or a type derived from it) for a file it cannot read, which the tool reports
// with exit status 1.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <iosfwd>
#include <string>
#include <string_view>

namespace khz::tool {

/// Starts a line of `khz info` output on stdout: `indent` spaces, then "label:" padded so that
/// the values line up; the caller writes the value and the newline to the returned stream.
std::ostream& info_line(std::string_view label, int indent = 2);
/// Prints the "on disk" line: the file's size in bytes.
void describe_file_size(std::uintmax_t bytes);
/// "(x, y, z)", as reduced::MeshReport prints points.
std::string point_text(const Eigen::Vector3d& point);
/// "min (x, y, z), max (x, y, z), size (x, y, z)", as reduced::MeshReport prints bounding boxes;
/// "empty" for an empty box.
std::string box_text(const Eigen::AlignedBox3d& box);
/// The bounding box of N×3 points, one per row (empty when there are none).
Eigen::AlignedBox3d bounding_box(const reduced::VertexMatrix& points);

// libcontact's files (describe_contact_files.cpp).

/// `.khzsdf`: format version, signedness, cells per axis, spacing, domain, value range, memory
/// and file size (contact::read_distance_field()).
void describe_distance_field_file(const std::string& file);
/// `.khzshell`: format version, levels with their point counts, points, bounding box and file
/// size (contact::read_pointshell()).
void describe_pointshell_file(const std::string& file);
/// `.khztree`: format version, levels, points, nodes, the reduced dimension r, the topology
/// fingerprint and file size (contact::read_deformable_point_tree(), which rebuilds the tree).
void describe_point_tree_file(const std::string& file);

/// A scene file (`.json`, docs/SCENES.md), validated by scene::read_scene(): its objects (mesh,
/// roles, model, field, pointshell and the cached products each needs), the haptic object and
/// grasp, the device and the loop (describe_scene_file.cpp).
void describe_scene_file(const std::string& file);

/// A device trajectory (`.csv`, haptic::read_trajectory()): samples, time span, position range
/// (describe_trajectory_file.cpp).
/// @throws reduced::Error saying the file is not a trajectory, with the reader's message, if
///         the CSV is something else.
void describe_trajectory_file(const std::string& file);
/// A `.csv`: a `khz run` cycle log (scene::is_cycle_csv_header()): cycles, rate, µs
/// per cycle and query, contact and force maxima, failed cycles; otherwise a device trajectory
/// (describe_trajectory_file()) (describe_csv_file.cpp).
void describe_csv_file(const std::string& file);

// Files khz writes for other programs (describe_output_files.cpp).

/// A PNG image (render::read_png()): width, height and file size.
void describe_png_file(const std::string& file);
/// A file khz writes but has no reader for (ParaView and NumPy/MATLAB exports): says so, with
/// `what` the file is, and prints its size.
void describe_unread_file(const std::string& file, std::string_view what);

}  // namespace khz::tool
