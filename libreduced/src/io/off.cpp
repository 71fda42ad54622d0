#include <khz/reduced/io/off.hpp>

#include "detail/text_scanner.hpp"
#include "io/surface_parsing.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

using detail::TextScanner;
using detail::UncommentedTokens;

/// What follows x y z on each vertex line, as announced by the header keyword.
struct OffLayout {
  bool normals = false;  // NOFF: nx ny nz
  bool colors = false;   // COFF: r g b [a]
};

OffLayout parse_keyword(const TextScanner& scanner, std::string_view keyword) {
  if (keyword == "OFF") return {};
  if (keyword == "COFF") return {.normals = false, .colors = true};
  if (keyword == "NOFF") return {.normals = true, .colors = false};
  if (keyword == "CNOFF") return {.normals = true, .colors = true};
  scanner.fail("expected the header keyword OFF, COFF, NOFF or CNOFF, found " +
               detail::quoted_token(keyword));
}

bool looks_fractional(std::string_view token) {
  return token.find_first_of(".eE") != std::string_view::npos;
}

/// A COFF vertex colour: the rest of the line, RGB or RGBA. Writers use either 0–255 integers
/// or [0, 1] floats; a line with any fractional-looking component is read as floats. Because
/// the colour has no fixed length, anything after it would be ambiguous, so extra values are
/// rejected.
std::array<float, 4> read_color(const TextScanner& scanner, UncommentedTokens& tokens) {
  std::array<std::string_view, 5> parts;
  std::size_t count = 0;
  for (std::string_view token = tokens.next(); !token.empty() && count < parts.size();
       token = tokens.next()) {
    parts[count++] = token;
  }
  if (count < 3 || count > 4) {
    scanner.fail("expected a vertex colour of 3 or 4 components after the coordinates, found " +
                 (count > 4 ? std::string("more than 4") : std::to_string(count)));
  }
  bool fractional = false;
  for (std::size_t i = 0; i < count; ++i) fractional = fractional || looks_fractional(parts[i]);

  std::array<float, 4> rgba = {1.0f, 1.0f, 1.0f, 1.0f};
  for (std::size_t i = 0; i < count; ++i) {
    if (fractional) {
      if (!detail::parse_float(parts[i], rgba[i]) || rgba[i] < 0.0f || rgba[i] > 1.0f) {
        scanner.fail("expected a colour component in [0, 1], found " +
                     detail::quoted_token(parts[i]));
      }
    } else {
      std::int64_t value = 0;
      if (!detail::parse_integer(parts[i], value) || value < 0 || value > 255) {
        scanner.fail("expected a colour component in [0, 255] (or a number in [0, 1]), found " +
                     detail::quoted_token(parts[i]));
      }
      rgba[i] = detail::channel_from_byte(value);
    }
  }
  return rgba;
}

void read_vertex(TextScanner& scanner, const OffLayout& layout, detail::SurfaceBuilder& builder) {
  UncommentedTokens tokens(scanner, '#');
  std::array<double, 3> position;
  for (double& coordinate : position) coordinate = tokens.require_double("vertex coordinate");
  if (layout.normals) {
    for (int i = 0; i < 3; ++i) tokens.require_double("vertex normal component");
  }
  if (layout.colors) {
    builder.add_vertex(position, read_color(scanner, tokens));
  } else {
    // Values after the declared fields (texture coordinates, or a colour under a plain OFF
    // keyword) are unambiguous to skip, and real files have them.
    builder.add_vertex(position);
  }
}

}  // namespace

TriangleMesh parse_off(std::string_view data, const std::string& source) {
  TextScanner scanner(data, source);
  scanner.require_content_line('#', "the header keyword OFF");
  UncommentedTokens header(scanner, '#');
  const OffLayout layout = parse_keyword(scanner, header.require("the header keyword OFF"));

  // Some writers put the counts on the keyword's line.
  if (header.exhausted()) scanner.require_content_line('#', "the vertex and face counts");
  UncommentedTokens counts(scanner, '#');
  const std::int64_t num_vertices = counts.require_integer("vertex count");
  const std::int64_t num_faces = counts.require_integer("face count");
  // The edge count that may follow is unused.

  // Shortest lines are "0 0 0" and "3 0 1 2"; line breaks are not counted because the last
  // line may lack one.
  detail::check_count_fits(scanner, num_vertices, 5, "vertices");
  detail::check_vertex_limit(scanner, num_vertices);
  detail::check_count_fits(scanner, num_faces, 7, "faces");

  detail::SurfaceBuilder builder;
  builder.reserve(num_vertices, num_faces, layout.colors);
  for (std::int64_t v = 0; v < num_vertices; ++v) {
    scanner.require_row('#', "vertex", v, num_vertices);
    read_vertex(scanner, layout, builder);
  }

  std::vector<int> corners;
  for (std::int64_t f = 0; f < num_faces; ++f) {
    scanner.require_row('#', "face", f, num_faces);
    UncommentedTokens tokens(scanner, '#');
    const std::int64_t num_corners = tokens.require_integer("face corner count");
    detail::check_corner_count(scanner, f, num_corners);
    corners.clear();
    for (std::int64_t c = 0; c < num_corners; ++c) {
      corners.push_back(
          detail::checked_corner(scanner, f, tokens.require_integer("vertex index"), num_vertices));
    }
    // Anything after the indices is a face colour, which a TriangleMesh does not hold.
    builder.add_polygon(corners);
  }
  return builder.finish();
}

std::string format_off(const TriangleMesh& mesh) {
  const bool colors = mesh.has_vertex_colors();
  std::string out = colors ? "COFF\n" : "OFF\n";
  detail::append_number(out, mesh.num_vertices());
  out += ' ';
  detail::append_number(out, mesh.num_triangles());
  out += " 0\n";
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) {
      if (c > 0) out += ' ';
      detail::append_number(out, mesh.vertices(v, c));
    }
    for (int c = 0; colors && c < 4; ++c) {
      out += ' ';
      detail::append_number(out, int{detail::byte_from_channel(mesh.vertex_colors(v, c))});
    }
    out += '\n';
  }
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    out += '3';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      detail::append_number(out, mesh.triangles(t, c));
    }
    out += '\n';
  }
  return out;
}

}  // namespace khz::reduced
