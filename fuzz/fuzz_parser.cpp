// libFuzzer entry point for one mesh parser, chosen at compile time by KHZ_FUZZ_PARSE.
//
// The contract under test: for any bytes, a parser either returns a mesh that passes
// validate() or throws ParseError. Anything else (crash, sanitizer report, another exception,
// an invalid mesh, a time-out or memory blow-up from a hostile header) is a bug.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/io/obj.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/io/ply.hpp>
#include <khz/reduced/io/stl.hpp>
#include <khz/reduced/io/tetgen.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace {

using namespace khz::reduced;

[[maybe_unused]] TriangleMesh fuzz_parse_obj(std::string_view data) {
  return parse_obj(data, "fuzz.obj");
}
[[maybe_unused]] TriangleMesh fuzz_parse_off(std::string_view data) {
  return parse_off(data, "fuzz.off");
}
[[maybe_unused]] TriangleMesh fuzz_parse_stl(std::string_view data) {
  return parse_stl(data, "fuzz.stl");
}
[[maybe_unused]] TriangleMesh fuzz_parse_ply(std::string_view data) {
  return parse_ply(data, "fuzz.ply");
}
[[maybe_unused]] VolumeMesh fuzz_parse_gmsh(std::string_view data) {
  return parse_gmsh(data, "fuzz.msh");
}

/// A TetGen mesh is two files: the input is split at its first NUL byte into .node and .ele.
[[maybe_unused]] VolumeMesh fuzz_parse_tetgen(std::string_view data) {
  const std::size_t split = data.find('\0');
  const std::string_view node = data.substr(0, split);
  const std::string_view ele =
      split == std::string_view::npos ? std::string_view() : data.substr(split + 1);
  return parse_tetgen(node, "fuzz.node", ele, "fuzz.ele");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::optional<decltype(KHZ_FUZZ_PARSE(bytes))> mesh;
  try {
    mesh = KHZ_FUZZ_PARSE(bytes);
  } catch (const ParseError&) {
    return 0;  // Rejecting malformed input is the expected outcome.
  }
  validate(*mesh);  // A MeshError escaping here is a parser bug: libFuzzer reports it.
  return 0;
}
