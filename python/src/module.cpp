// The kilohertz._core extension module: one submodule per library.

#include <khz/contact/version.hpp>

#include "bindings.hpp"

PYBIND11_MODULE(_core, module) {
  namespace kp = khz::python;
  namespace py = pybind11;
  module.doc() = "Kilohertz's compiled core; import the package `kilohertz` instead.";
  module.attr("__version__") = khz::contact::library_version();
  kp::bind_errors(module);
  // Each submodule is named as users import it (kilohertz/__init__.py registers it under that
  // name) before its classes are made, so signatures and help() show kilohertz.reduced.X.
  const auto submodule = [&module](const char* name, const char* doc) {
    auto sub = module.def_submodule(name, doc);
    sub.attr("__name__") = std::string("kilohertz.") + name;
    return sub;
  };
  auto reduced = submodule(
      "reduced", "Meshes, mesh files, reports and repair (the C++ library khz::reduced).");
  kp::bind_reduced_meshes(reduced);
  kp::bind_reduced_fem(reduced);
  kp::bind_reduced_models(reduced);
  auto contact = submodule(
      "contact",
      "Distance fields, pointshells and the contact query (the C++ library khz::contact).");
  kp::bind_contact_fields(contact);
  kp::bind_contact_query(contact);
  auto haptic = submodule(
      "haptic",
      "Devices, virtual coupling and the multi-body World (the C++ library khz::haptic).");
  kp::bind_haptic_devices(haptic);
  kp::bind_haptic_coupling(haptic);
  auto scene = submodule(
      "scene", "Scene files, their preparation and their runtime (the C++ library khz::scene).");
  kp::bind_scene(scene, module.attr("Error"));
  kp::bind_scene_report(scene);
}
