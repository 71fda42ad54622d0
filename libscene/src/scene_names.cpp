#include "names.hpp"

#include <khz/scene/scene_names.hpp>

namespace khz::scene {

std::string_view basis_method_name(BasisMethod method) noexcept {
  return detail::name_of(method, detail::basis_methods);
}

std::string_view pointshell_method_name(PointshellMethod method) noexcept {
  return detail::name_of(method, detail::pointshell_methods);
}

std::string_view device_type_name(DeviceType type) noexcept {
  return detail::name_of(type, detail::device_types);
}

}  // namespace khz::scene
