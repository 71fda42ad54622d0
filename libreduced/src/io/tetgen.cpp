// STUB: to be implemented.
#include <khz/reduced/io/tetgen.hpp>
#include <khz/reduced/errors.hpp>
#include <ostream>

namespace khz::reduced {

VolumeMesh parse_tetgen(std::string_view, const std::string&, std::string_view, const std::string&) { throw Error("not implemented"); }
TetgenFiles format_tetgen(const VolumeMesh&) { throw Error("not implemented"); }

}  // namespace khz::reduced
