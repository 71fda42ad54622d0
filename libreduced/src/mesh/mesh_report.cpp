// STUB: to be implemented.
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

MeshReport analyze_mesh(const TriangleMesh&) { throw Error("not implemented"); }
std::ostream& operator<<(std::ostream&, const MeshReport&) { throw Error("not implemented"); }

}  // namespace khz::reduced
