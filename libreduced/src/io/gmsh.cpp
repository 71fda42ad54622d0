// STUB: to be implemented.
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

VolumeMesh parse_gmsh(std::string_view, const std::string&) { throw Error("not implemented"); }
std::string format_gmsh(const VolumeMesh&) { throw Error("not implemented"); }

}  // namespace khz::reduced
