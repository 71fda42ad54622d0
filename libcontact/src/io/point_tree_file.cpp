#include <khz/contact/io/point_tree_file.hpp>

#include <khz/contact/io/pointshell_file.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

/// FNV-1a over int32 values, byte by byte in little-endian order so the fingerprint does not
/// depend on the host.
class Fnv1a {
 public:
  void add(std::int64_t value) {
    const auto bits = static_cast<std::uint32_t>(static_cast<std::int32_t>(value));
    for (int shift = 0; shift < 32; shift += 8) {
      m_hash = (m_hash ^ ((bits >> shift) & 0xffu)) * 0x100000001b3ull;
    }
  }
  std::uint64_t digest() const noexcept { return m_hash; }

 private:
  std::uint64_t m_hash = 0xcbf29ce484222325ull;
};

std::string hex(std::uint64_t value) {
  char text[19];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

/// Reads one mode array and checks its size (3r per point) and that every entry is finite.
std::vector<double> take_modes(reduced::ContainerReader& reader, const char* what,
                               std::uint64_t expected, std::uint64_t per_point) {
  const std::size_t start = reader.offset();
  std::vector<double> modes = reader.read_doubles(what);
  if (modes.size() != expected) {
    reader.fail_at(start, std::string(what) + ": " + std::to_string(modes.size()) +
                              " entries, expected " + std::to_string(expected) + " (3r per point)");
  }
  for (std::size_t k = 0; k < modes.size(); ++k) {
    if (!std::isfinite(modes[k])) {
      reader.fail_at(reader.value_offset() + 8 * k,
                     std::string(what) + ": entry " + std::to_string(k % per_point) + " of point " +
                         std::to_string(k / per_point) + " is not finite");
    }
  }
  return modes;
}

DeformablePointTree read_payload(reduced::ContainerReader& reader,
                                 const ProgressCallback& progress) {
  Pointshell shell = take_pointshell(reader);
  const std::uint64_t fingerprint = reader.read_u64("the topology fingerprint");
  const std::size_t fingerprint_offset = reader.value_offset();
  const std::int32_t dimension = reader.read_i32("the reduced dimension");
  if (dimension < 1) {
    reader.fail_at(reader.value_offset(),
                   "the reduced dimension must be at least 1, got " + std::to_string(dimension));
  }
  // N < 2³¹ and r < 2³¹: 3rN < 2⁶⁴, no overflow. read_doubles() checks the count against the
  // bytes present before allocating.
  const std::uint64_t per_point = 3 * static_cast<std::uint64_t>(dimension);
  const std::uint64_t expected = per_point * static_cast<std::uint64_t>(shell.size());
  std::vector<double> displacement =
      take_modes(reader, "the displacement modes", expected, per_point);
  std::vector<double> normal = take_modes(reader, "the normal modes", expected, per_point);
  reader.finish("the normal modes");

  // Everything cheap is checked; now the rebuild, which the fingerprint must confirm.
  PointTree tree(shell, progress);
  const std::uint64_t rebuilt = point_tree_fingerprint(tree);
  if (rebuilt != fingerprint) {
    reader.fail_at(fingerprint_offset,
                   "the point tree rebuilt from the pointshell has topology "
                   "fingerprint " +
                       hex(rebuilt) + ", the file's tree had " + hex(fingerprint) +
                       " (written by a build that builds trees differently)");
  }
  return DeformablePointTree(std::move(tree), dimension, std::move(displacement), std::move(normal),
                             progress);
}

}  // namespace

Pointshell source_pointshell(const PointTree& tree) {
  const Pointshell& ordered = tree.pointshell();
  Pointshell shell;
  shell.points.resize(ordered.size(), 3);
  shell.normals.resize(ordered.size(), 3);
  for (Eigen::Index s = 0; s < ordered.size(); ++s) {
    shell.points.row(tree.source_index(s)) = ordered.points.row(s);
    shell.normals.row(tree.source_index(s)) = ordered.normals.row(s);
  }
  // The tree only permutes points within a level, so the level ends are the source's.
  shell.level_ends = ordered.level_ends;
  return shell;
}

std::uint64_t point_tree_fingerprint(const PointTree& tree) {
  Fnv1a hash;
  for (int level = 0; level <= tree.num_levels(); ++level) hash.add(tree.level_begin(level));
  for (const PointTreeNode& node : tree.nodes()) {
    hash.add(node.point);
    hash.add(node.parent);
    hash.add(node.first_child);
    hash.add(node.child_count);
  }
  for (Eigen::Index s = 0; s < tree.num_points(); ++s) hash.add(tree.source_index(s));
  return hash.digest();
}

void write_deformable_point_tree(const std::filesystem::path& file,
                                 const DeformablePointTree& tree) {
  reduced::ContainerWriter writer(point_tree_file_format);
  append_pointshell(writer, source_pointshell(tree.tree()));
  writer.write_u64(point_tree_fingerprint(tree.tree()));
  writer.write_i32(static_cast<std::int32_t>(tree.dimension()));
  const Eigen::Index n = tree.tree().num_points();
  const Eigen::Index per_point = 3 * tree.dimension();
  // The modes are contiguous in point order (row-major 3×r blocks); view them in place.
  writer.write_doubles(std::span<const double>(tree.displacement_modes(0).data(),
                                               static_cast<std::size_t>(per_point * n)));
  writer.write_doubles(std::span<const double>(tree.normal_modes(0).data(),
                                               static_cast<std::size_t>(per_point * n)));
  writer.write_file(file);
}

DeformablePointTree parse_deformable_point_tree(std::string bytes, std::string source,
                                                const ProgressCallback& progress) {
  reduced::ContainerReader reader(std::move(bytes), std::move(source), point_tree_file_format);
  return read_payload(reader, progress);
}

DeformablePointTree read_deformable_point_tree(const std::filesystem::path& file,
                                               const ProgressCallback& progress) {
  reduced::ContainerReader reader = reduced::ContainerReader::open(file, point_tree_file_format);
  return read_payload(reader, progress);
}

}  // namespace khz::contact
