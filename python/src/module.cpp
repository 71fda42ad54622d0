// The kilohertz._core extension module: one submodule per library.

#include "bindings.hpp"

#include <khz/contact/version.hpp>

PYBIND11_MODULE(_core, module) {
  namespace kp = khz::python;
  module.doc() = "Kilohertz's compiled core; import the package `kilohertz` instead.";
  module.attr("__version__") = khz::contact::library_version();
  kp::bind_errors(module);
  auto reduced = module.def_submodule(
      "reduced", "Meshes, mesh files, reports and repair (the C++ library khz::reduced).");
  kp::bind_reduced_meshes(reduced);
  auto contact = module.def_submodule(
      "contact", "Distance fields and their point queries (the C++ library khz::contact).");
  kp::bind_contact_fields(contact);
}
