// STUB: to be implemented.
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

Eigen::Index weld_vertices(TriangleMesh&, double) { throw Error("not implemented"); }
Eigen::Index remove_degenerate_triangles(TriangleMesh&) { throw Error("not implemented"); }
bool orient_consistently(TriangleMesh&) { throw Error("not implemented"); }
RepairSummary repair_mesh(TriangleMesh&, const RepairOptions&) { throw Error("not implemented"); }

}  // namespace khz::reduced
