// libFuzzer entry point for one reader of outside input other than the mesh formats, chosen at
// compile time by KHZ_FUZZ_READ: Kilohertz's binary files (cache files are outside input too),
// scene and device JSON, the trajectory, force-load and cycle-log CSV files.
//
// The contract under test: for any bytes, a reader either returns what it reads or throws a
// khz::reduced::ParseError (a khz::scene::SceneError for JSON). Anything else (crash, sanitizer
// report, another exception, a time-out or a memory blow-up from a hostile size field) is a bug.
//
// A binary file's checksum rejects almost every mutation at its envelope, so the file targets
// seal their input first: the first four bytes are the format version, the rest the payload,
// wrapped in the magic, the length and the checksum the reader expects. The mutations then reach
// the values behind the envelope; fuzz_container checks the envelope itself on raw bytes.
#include "io/basis_payload.hpp"

#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/haptic/device/trajectory_file.hpp>
#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_error.hpp>

#include <xxhash.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace {

using namespace khz;

void append_u64(std::string& bytes, std::uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes += static_cast<char>((value >> (8 * i)) & 0xff);
}

/// A container of `format` around the input: version (4 bytes, little-endian, missing bytes
/// zero), then the payload, then the length and checksum made to agree.
std::string sealed(std::string_view data, const reduced::ContainerFormat& format) {
  std::string version(4, '\0');
  data.copy(version.data(), 4);
  const std::string_view payload = data.size() > 4 ? data.substr(4) : std::string_view();
  std::string bytes(format.magic);
  bytes += version;
  const std::uint64_t length =
      reduced::container_header_bytes + payload.size() + reduced::container_checksum_bytes;
  append_u64(bytes, length);
  bytes += payload;
  append_u64(bytes, XXH3_64bits(bytes.data(), bytes.size()));
  return bytes;
}

[[maybe_unused]] void fuzz_read_container(std::string_view data) {
  constexpr reduced::ContainerFormat format{"KHZFUZZ!", "fuzzing container", 1};
  reduced::ContainerReader reader{std::string(data), "fuzz", format};
  // A word read before each value chooses its kind, so every value reader's size checks are
  // reached.
  while (reader.remaining_bytes() > 0) {
    switch (reader.read_u32("a kind") % 6) {
      case 0:
        reader.read_u64("a u64");
        break;
      case 1:
        reader.read_f64("an f64");
        break;
      case 2:
        reader.read_string("a string");
        break;
      case 3:
        reader.read_doubles("doubles");
        break;
      case 4:
        reader.read_ints("ints");
        break;
      default:
        reader.read_matrix("a matrix");
        break;
    }
  }
  reader.finish("the values");
}

[[maybe_unused]] void fuzz_read_basis(std::string_view data) {
  // read_basis() without the mesh whose fingerprint no fuzzer can match.
  reduced::ContainerReader reader{sealed(data, reduced::basis_file_format), "fuzz.khzbasis",
                                  reduced::basis_file_format};
  reduced::detail::BasisHeader header =
      reduced::detail::read_basis_header(reader, reduced::detail::max_basis_size);
  reduced::detail::read_basis_body(reader, std::move(header));
  reader.finish("the basis matrix U");
}

[[maybe_unused]] void fuzz_read_model(std::string_view data) {
  reduced::parse_reduced_model(sealed(data, reduced::reduced_model_file_format), "fuzz.khzmodel");
}

[[maybe_unused]] void fuzz_read_sdf(std::string_view data) {
  contact::parse_distance_field(sealed(data, contact::distance_field_file_format), "fuzz.khzsdf");
}

[[maybe_unused]] void fuzz_read_shell(std::string_view data) {
  contact::parse_pointshell(sealed(data, contact::pointshell_file_format), "fuzz.khzshell");
}

[[maybe_unused]] void fuzz_read_tree(std::string_view data) {
  contact::parse_deformable_point_tree(sealed(data, contact::point_tree_file_format),
                                       "fuzz.khztree");
}

/// Scenes and devices are checked without their files: whether a named mesh exists is not the
/// parser's question.
scene::SceneReadOptions without_files() {
  scene::SceneReadOptions options;
  options.check_files = false;
  return options;
}

[[maybe_unused]] void fuzz_read_scene(std::string_view data) {
  scene::parse_scene(data, "fuzz.json", without_files());
}

[[maybe_unused]] void fuzz_read_device(std::string_view data) {
  scene::parse_device(data, "fuzz.json", 1000.0, without_files());
}

[[maybe_unused]] void fuzz_read_cycles(std::string_view data) {
  scene::parse_cycle_csv(data, "fuzz.csv");
}
[[maybe_unused]] void fuzz_read_trajectory(std::string_view data) {
  haptic::parse_trajectory(data, "fuzz.csv");
}

[[maybe_unused]] void fuzz_read_loads(std::string_view data) {
  // Vertex indices are checked against a mesh of this many vertices.
  reduced::parse_force_loads(data, "fuzz.csv", 64);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    KHZ_FUZZ_READ(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const khz::reduced::ParseError&) {
    return 0;  // Rejecting malformed input is the expected outcome.
  } catch (const khz::scene::SceneError&) {
    return 0;
  }
  return 0;
}
