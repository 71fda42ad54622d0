#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <gtest/gtest.h>

// xxHash compiled into this test, so the fingerprint's definition is checked independently.
#define XXH_INLINE_ALL
// Its portable scalar code (XXH_SCALAR), not the library's SIMD paths: independent, and free of
// GCC 12's false -Wuninitialized in the AVX-512 intrinsics under -march=native.
#define XXH_VECTOR 0
#include <xxhash.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace khz::reduced {
namespace {

VolumeMesh box() { return box_tet_mesh({0, 0, 0}, {1, 0.5, 0.25}, {2, 1, 1}); }

template <typename T>
void append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the test host is little-endian
  out.append(bytes, sizeof(T));
}

TEST(MeshFingerprint, HashesTheDocumentedByteSequence) {
  const VolumeMesh mesh = box();
  std::string bytes;
  append(bytes, std::int32_t{4});
  append(bytes, static_cast<std::uint64_t>(mesh.num_vertices()));
  append(bytes, static_cast<std::uint64_t>(mesh.num_elements()));
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (int c = 0; c < 4; ++c) append(bytes, static_cast<std::int32_t>(mesh.elements(e, c)));
  }
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) append(bytes, mesh.vertices(v, c));
  }
  EXPECT_EQ(mesh_fingerprint(mesh), XXH3_64bits(bytes.data(), bytes.size()));
}

TEST(MeshFingerprint, IsAFixedValueForAFixedMesh) {
  // Stored in basis files: must never change between versions or platforms.
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 0.5, 0, 0, 0, 0.25, 0, 0, 0, 2;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  EXPECT_EQ(fingerprint_text(mesh_fingerprint(mesh)), "0x98e7760db1f0ccd2");
}

TEST(MeshFingerprint, SeesEveryBitOfTheDiscretization) {
  const VolumeMesh mesh = box();
  const std::uint64_t reference = mesh_fingerprint(mesh);
  EXPECT_EQ(mesh_fingerprint(box()), reference);

  VolumeMesh moved = mesh;
  moved.vertices(3, 1) = std::nextafter(moved.vertices(3, 1), 2.0);
  EXPECT_NE(mesh_fingerprint(moved), reference);

  VolumeMesh signed_zero = mesh;
  ASSERT_EQ(signed_zero.vertices(0, 0), 0.0);
  signed_zero.vertices(0, 0) = -0.0;
  EXPECT_NE(mesh_fingerprint(signed_zero), reference);

  VolumeMesh renumbered = mesh;
  std::swap(renumbered.elements(0, 1), renumbered.elements(0, 2));
  EXPECT_NE(mesh_fingerprint(renumbered), reference);

  VolumeMesh fewer = mesh;
  fewer.elements.conservativeResize(mesh.num_elements() - 1, 4);
  EXPECT_NE(mesh_fingerprint(fewer), reference);

  const VolumeMesh hexes = box_hex_mesh({0, 0, 0}, {1, 0.5, 0.25}, {2, 1, 1});
  EXPECT_NE(mesh_fingerprint(hexes), reference);  // same vertices, other elements
}

TEST(MeshFingerprint, IgnoresMaterialGroups) {
  VolumeMesh grouped = box();
  grouped.element_groups = Eigen::VectorXi::Ones(grouped.num_elements());
  EXPECT_EQ(mesh_fingerprint(grouped), mesh_fingerprint(box()));
}

TEST(MeshFingerprint, PrintsAsSixteenHexDigits) {
  EXPECT_EQ(fingerprint_text(0), "0x0000000000000000");
  EXPECT_EQ(fingerprint_text(0x0123456789abcdefu), "0x0123456789abcdef");
  EXPECT_EQ(fingerprint_text(~std::uint64_t{0}), "0xffffffffffffffff");
}

}  // namespace
}  // namespace khz::reduced
