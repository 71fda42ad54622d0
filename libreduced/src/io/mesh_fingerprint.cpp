#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>

#include <xxhash.h>

#include <bit>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>

namespace khz::reduced {
namespace {

/// A streaming XXH3-64 over little-endian values.
class Hasher {
 public:
  Hasher() : m_state(XXH3_createState(), &XXH3_freeState) {
    if (!m_state || XXH3_64bits_reset(m_state.get()) != XXH_OK) {
      throw Error("mesh fingerprint: cannot initialise the XXH3 hash state");
    }
  }

  template <typename T>
  void add(T value) {
    static_assert(std::is_arithmetic_v<T>);
    add_array(&value, 1);
  }

  template <typename T>
  void add_array(const T* values, std::size_t count) {
    if constexpr (std::endian::native == std::endian::little) {
      update(values, count * sizeof(T));
    } else {
      for (std::size_t i = 0; i < count; ++i) {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, values + i, sizeof(T));
        for (std::size_t b = 0; b < sizeof(T) / 2; ++b) {
          std::swap(bytes[b], bytes[sizeof(T) - 1 - b]);
        }
        update(bytes, sizeof(T));
      }
    }
  }

  std::uint64_t digest() const { return XXH3_64bits_digest(m_state.get()); }

 private:
  void update(const void* data, std::size_t size) {
    if (size > 0 && XXH3_64bits_update(m_state.get(), data, size) != XXH_OK) {
      throw Error("mesh fingerprint: XXH3 update failed");
    }
  }

  std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> m_state;
};

}  // namespace

std::uint64_t mesh_fingerprint(const VolumeMesh& mesh) {
  static_assert(sizeof(int) == 4 && std::numeric_limits<double>::is_iec559);
  Hasher hasher;
  hasher.add(static_cast<std::int32_t>(nodes_per_element(mesh.element_type)));
  hasher.add(static_cast<std::uint64_t>(mesh.num_vertices()));
  hasher.add(static_cast<std::uint64_t>(mesh.num_elements()));
  // Both matrices are row-major: element by element, vertex by vertex.
  hasher.add_array(mesh.elements.data(), static_cast<std::size_t>(mesh.elements.size()));
  hasher.add_array(mesh.vertices.data(), static_cast<std::size_t>(mesh.vertices.size()));
  return hasher.digest();
}

std::string fingerprint_text(std::uint64_t fingerprint) {
  char text[19];
  std::snprintf(text, sizeof(text), "0x%016llx", static_cast<unsigned long long>(fingerprint));
  return text;
}

}  // namespace khz::reduced
