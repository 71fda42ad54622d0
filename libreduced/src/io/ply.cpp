// STUB: to be implemented.
#include <khz/reduced/io/ply.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

TriangleMesh parse_ply(std::string_view, const std::string&) { throw Error("not implemented"); }
std::string format_ply(const TriangleMesh&, PlyEncoding) { throw Error("not implemented"); }

}  // namespace khz::reduced
