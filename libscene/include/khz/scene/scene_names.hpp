#pragma once
// The scene file's spelling of the choices it makes (docs/SCENES.md), for tools that describe a
// scene in the file's own words.

#include <khz/scene/basis_description.hpp>
#include <khz/scene/device_description.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/pointshell_description.hpp>

#include <string_view>

namespace khz::scene {

/// "modes", "sketch" or "simulation_data" (JSON model.basis.method).
KHZ_SCENE_API std::string_view basis_method_name(BasisMethod method) noexcept;
/// "repulsion", "vertices", "random" or "voxels" (JSON pointshell.method).
KHZ_SCENE_API std::string_view pointshell_method_name(PointshellMethod method) noexcept;
/// "null", "trajectory", "operator" or "hardware" (JSON device.type).
KHZ_SCENE_API std::string_view device_type_name(DeviceType type) noexcept;

}  // namespace khz::scene
