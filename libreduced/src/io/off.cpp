// STUB: to be implemented.
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

TriangleMesh parse_off(std::string_view, const std::string&) { throw Error("not implemented"); }
std::string format_off(const TriangleMesh&) { throw Error("not implemented"); }

}  // namespace khz::reduced
