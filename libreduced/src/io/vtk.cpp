// STUB: to be implemented.
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

std::string format_vtk_legacy(const TriangleMesh&, const VtkFields&) { throw Error("not implemented"); }
std::string format_vtk_legacy(const VolumeMesh&, const VtkFields&) { throw Error("not implemented"); }
std::string format_vtu(const TriangleMesh&, const VtkFields&) { throw Error("not implemented"); }
std::string format_vtu(const VolumeMesh&, const VtkFields&) { throw Error("not implemented"); }

}  // namespace khz::reduced
