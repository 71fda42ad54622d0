#include <khz/contact/io/distance_field_file.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

constexpr std::uint32_t signed_flag = 1;
static_assert(sizeof(float) == sizeof(std::int32_t) && std::numeric_limits<float>::is_iec559,
              "node values are stored as IEEE 754 binary32 bit patterns");

std::string node_text(int i, int j, int k) {
  return "node (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")";
}

DistanceGrid read_payload(reduced::ContainerReader& reader) {
  const std::uint32_t flags = reader.read_u32("the flags");
  if ((flags & ~signed_flag) != 0) {
    reader.fail_at(reader.value_offset(),
                   "unknown flags " + std::to_string(flags) + " (only bit 0, signed, is defined)");
  }
  GridGeometry geometry;
  const char* axes[] = {"the origin's x", "the origin's y", "the origin's z"};
  for (int axis = 0; axis < 3; ++axis) {
    geometry.origin[axis] = reader.read_f64(axes[axis]);
    if (!std::isfinite(geometry.origin[axis])) {
      reader.fail_at(reader.value_offset(), std::string(axes[axis]) + " is not finite");
    }
  }
  geometry.spacing = reader.read_f64("the spacing");
  if (!(geometry.spacing > 0.0) || !std::isfinite(geometry.spacing)) {
    reader.fail_at(reader.value_offset(), "the spacing must be positive and finite, got " +
                                              std::to_string(geometry.spacing));
  }
  geometry.cells = reader.read_i32("the cell count");
  const std::size_t cells_offset = reader.value_offset();
  if (geometry.cells < 1 || geometry.cells == std::numeric_limits<std::int32_t>::max()) {
    reader.fail_at(cells_offset, "invalid cell count " + std::to_string(geometry.cells));
  }
  // n planes of an 8-byte count and n² values: checked before the grid is allocated.
  const auto n = static_cast<std::uint64_t>(geometry.cells) + 1;
  const std::uint64_t per_plane = 8 + 4 * n * n;  // n ≤ 2³¹: no overflow
  if (per_plane > reader.remaining_bytes() / n) {
    reader.fail_at(cells_offset,
                   std::to_string(geometry.cells) + "³ cells need " + std::to_string(n) +
                       " planes of " + std::to_string(per_plane) + " bytes, more than the " +
                       std::to_string(reader.remaining_bytes()) + " bytes that remain");
  }
  const bool is_signed = (flags & signed_flag) != 0;
  std::vector<float> values(static_cast<std::size_t>(n * n * n));
  for (std::uint64_t k = 0; k < n; ++k) {
    const std::size_t count_offset = reader.offset();
    const std::vector<int> plane = reader.read_ints("plane " + std::to_string(k));
    if (plane.size() != n * n) {
      reader.fail_at(count_offset, "plane " + std::to_string(k) + " has " +
                                       std::to_string(plane.size()) + " values, expected " +
                                       std::to_string(n * n) + " (nodes per axis squared)");
    }
    for (std::size_t index = 0; index < plane.size(); ++index) {
      const float value = std::bit_cast<float>(plane[index]);
      if (!std::isfinite(value) || (!is_signed && value < 0.0f)) {
        const auto i = static_cast<int>(index % n), j = static_cast<int>(index / n);
        reader.fail_at(
            reader.value_offset() + 4 * index,
            node_text(i, j, static_cast<int>(k)) + " = " + std::to_string(value) +
                (std::isfinite(value) ? " is negative in an unsigned field" : " is not finite"));
      }
      values[static_cast<std::size_t>(k * n * n + index)] = value;
    }
  }
  reader.finish("the node values");
  return DistanceGrid(geometry, std::move(values), is_signed);
}

}  // namespace

void write_distance_field(const std::filesystem::path& file, const DistanceGrid& grid) {
  const GridGeometry& g = grid.geometry();
  reduced::ContainerWriter writer(distance_field_file_format);
  writer.write_u32(grid.is_signed() ? signed_flag : 0);
  for (int axis = 0; axis < 3; ++axis) writer.write_f64(g.origin[axis]);
  writer.write_f64(g.spacing);
  writer.write_i32(g.cells);
  const auto plane_size = static_cast<std::size_t>(g.nodes_per_axis()) * g.nodes_per_axis();
  std::vector<int> plane(plane_size);
  const auto values = grid.values();
  for (int k = 0; k < g.nodes_per_axis(); ++k) {
    for (std::size_t index = 0; index < plane_size; ++index) {
      plane[index] = std::bit_cast<int>(values[k * plane_size + index]);
    }
    writer.write_ints(plane);
  }
  writer.write_file(file);
}

DistanceGrid parse_distance_field(std::string bytes, std::string source) {
  reduced::ContainerReader reader(std::move(bytes), std::move(source), distance_field_file_format);
  return read_payload(reader);
}

DistanceGrid read_distance_field(const std::filesystem::path& file) {
  reduced::ContainerReader reader =
      reduced::ContainerReader::open(file, distance_field_file_format);
  return read_payload(reader);
}

}  // namespace khz::contact
