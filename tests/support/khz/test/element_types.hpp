#pragma once
// Running one parameterized test over both element types.

#include <khz/reduced/mesh/volume_mesh.hpp>

#include <gtest/gtest.h>

#include <string>

namespace khz::test {

inline constexpr reduced::ElementType all_element_types[] = {reduced::ElementType::tetrahedron,
                                                             reduced::ElementType::hexahedron};

/// Test-name suffix for INSTANTIATE_TEST_SUITE_P: "Tetrahedra" or "Hexahedra".
inline std::string element_type_name(const ::testing::TestParamInfo<reduced::ElementType>& info) {
  return info.param == reduced::ElementType::tetrahedron ? "Tetrahedra" : "Hexahedra";
}

}  // namespace khz::test
