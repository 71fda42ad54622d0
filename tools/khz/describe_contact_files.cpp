// `khz info` for libcontact's files: distance fields, pointshells and deformable point trees.
#include "describe_files.hpp"

#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>

#include <algorithm>
#include <iostream>

namespace khz::tool {
namespace {

/// Checks `file`'s envelope (magic, version, length, checksum) and prints what it is and its
/// format version, which the readers do not report; returns the file's size. The container is
/// released before the caller's reader reads the file again.
std::uintmax_t describe_container(const std::string& file, const reduced::ContainerFormat& format) {
  const reduced::ContainerReader reader = reduced::ContainerReader::open(file, format);
  info_line("kind") << format.description << ", format version " << reader.version() << "\n";
  return reader.file_bytes();
}

/// The levels with their point counts, the points and their bounding box.
void describe_levels(const contact::Pointshell& pointshell) {
  std::ostream& out = info_line("levels") << pointshell.num_levels() << " (";
  for (int level = 0; level < pointshell.num_levels(); ++level) {
    out << (level > 0 ? ", " : "") << pointshell.level_end(level) - pointshell.level_begin(level);
  }
  out << " points)\n";
  info_line("points") << pointshell.size() << "\n";
  info_line("bounds") << box_text(bounding_box(pointshell.points)) << " m\n";
}

}  // namespace

void describe_distance_field_file(const std::string& file) {
  const std::uintmax_t file_bytes = describe_container(file, contact::distance_field_file_format);
  const contact::DistanceGrid grid = contact::read_distance_field(file);
  const contact::GridGeometry& geometry = grid.geometry();
  const auto [lowest, highest] = std::ranges::minmax(grid.values());
  info_line("distances") << (grid.is_signed() ? "signed (negative inside)" : "unsigned") << "\n";
  info_line("cells") << geometry.cells << " per axis (" << geometry.nodes_per_axis()
                     << "^3 = " << geometry.node_count() << " nodes)\n";
  info_line("spacing") << geometry.spacing << " m\n";
  info_line("domain") << box_text(geometry.box()) << " m\n";
  info_line("values") << "min " << lowest << " m, max " << highest << " m\n";
  info_line("memory") << grid.values().size_bytes() << " bytes (a float per node)\n";
  describe_file_size(file_bytes);
}

void describe_pointshell_file(const std::string& file) {
  const std::uintmax_t file_bytes = describe_container(file, contact::pointshell_file_format);
  describe_levels(contact::read_pointshell(file));
  describe_file_size(file_bytes);
}

void describe_point_tree_file(const std::string& file) {
  const std::uintmax_t file_bytes = describe_container(file, contact::point_tree_file_format);
  const contact::DeformablePointTree deformable = contact::read_deformable_point_tree(file);
  const contact::PointTree& tree = deformable.tree();
  describe_levels(tree.pointshell());
  info_line("nodes") << tree.num_nodes() << " (" << tree.num_internal_nodes()
                     << " with children)\n";
  info_line("modes r") << deformable.dimension() << " (deformable: U_s, dN_s per point)\n";
  info_line("fingerprint") << reduced::fingerprint_text(contact::point_tree_fingerprint(tree))
                           << " (topology)\n";
  describe_file_size(file_bytes);
}

}  // namespace khz::tool
