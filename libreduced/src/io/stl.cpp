// STUB: to be implemented.
#include <khz/reduced/io/stl.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

TriangleMesh parse_stl(std::string_view, const std::string&) { throw Error("not implemented"); }
std::string format_stl_binary(const TriangleMesh&) { throw Error("not implemented"); }
std::string format_stl_ascii(const TriangleMesh&) { throw Error("not implemented"); }

}  // namespace khz::reduced
