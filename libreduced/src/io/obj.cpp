// STUB: to be implemented.
#include <khz/reduced/io/obj.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

TriangleMesh parse_obj(std::string_view, const std::string&) { throw Error("not implemented"); }
std::string format_obj(const TriangleMesh&) { throw Error("not implemented"); }

}  // namespace khz::reduced
