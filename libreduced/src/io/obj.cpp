#include <khz/reduced/io/obj.hpp>

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

/// `v x y z`, `v x y z w` (w ignored) or `v x y z r g b` (the common colour extension).
void read_vertex(TextScanner& scanner, UncommentedTokens& tokens, detail::SurfaceBuilder& builder) {
  detail::check_vertex_limit(scanner, builder.num_vertices() + 1);
  std::array<std::string_view, 7> fields;
  std::size_t count = 0;
  for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
    if (count == fields.size()) {
      scanner.fail("expected 'v x y z', 'v x y z w' or 'v x y z r g b', found more than 7 values");
    }
    fields[count++] = token;
  }
  if (count != 3 && count != 4 && count != 6) {
    scanner.fail("expected 'v x y z', 'v x y z w' or 'v x y z r g b', found " +
                 std::to_string(count) + " values");
  }
  std::array<double, 3> position;
  for (std::size_t c = 0; c < 3; ++c) {
    position[c] = tokens.to_double(fields[c], "vertex coordinate");
  }
  if (count == 4) tokens.to_double(fields[3], "vertex weight w");
  if (count != 6) {
    builder.add_vertex(position);
    return;
  }
  std::array<float, 4> rgba = {1.0f, 1.0f, 1.0f, 1.0f};
  for (std::size_t c = 0; c < 3; ++c) {
    if (!detail::parse_float(fields[3 + c], rgba[c]) || rgba[c] < 0.0f || rgba[c] > 1.0f) {
      scanner.fail("expected a vertex colour component in [0, 1], found " +
                   detail::quoted_token(fields[3 + c]));
    }
  }
  builder.add_vertex(position, rgba);
}

/// A face corner `i`, `i/t`, `i//n` or `i/t/n` as a 0-based vertex index. Only vertices defined
/// above the face count: negative indices are relative to them, and forward references (which
/// no writer produces) are rejected so the error can point at the face.
int read_corner(const TextScanner& scanner, std::string_view token, std::int64_t face,
                std::int64_t defined) {
  std::int64_t index = 0;
  if (!detail::parse_integer(token.substr(0, token.find('/')), index)) {
    scanner.fail(
        "expected a vertex index (an integer, optionally with /texture/normal indices), "
        "found " +
        detail::quoted_token(token));
  }
  if (index == 0) {
    scanner.fail("face " + std::to_string(face) +
                 " uses vertex index 0, but OBJ indices start at 1 (or count back from -1)");
  }
  const std::int64_t resolved = index > 0 ? index - 1 : defined + index;
  if (resolved < 0 || resolved >= defined) {
    scanner.fail("face " + std::to_string(face) + " uses vertex " + std::to_string(index) +
                 ", but only " + std::to_string(defined) + " vertices are defined before it");
  }
  return static_cast<int>(resolved);
}

}  // namespace

TriangleMesh parse_obj(std::string_view data, const std::string& source) {
  TextScanner scanner(data, source);
  detail::SurfaceBuilder builder;
  std::vector<int> corners;
  std::int64_t num_faces = 0;
  while (scanner.next_content_line('#')) {
    UncommentedTokens tokens(scanner, '#');
    const std::string_view keyword = tokens.next();
    if (keyword == "v") {
      read_vertex(scanner, tokens, builder);
    } else if (keyword == "f") {
      corners.clear();
      for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
        corners.push_back(read_corner(scanner, token, num_faces, builder.num_vertices()));
      }
      detail::check_corner_count(scanner, num_faces, static_cast<std::int64_t>(corners.size()));
      builder.add_polygon(corners);
      ++num_faces;
    }
    // Every other statement (vt, vn, g, o, s, usemtl, mtllib, l, p, ...) describes something a
    // TriangleMesh does not hold.
  }
  // An OBJ without vertices (empty, or only other statements) describes no surface at all.
  if (builder.num_vertices() == 0) {
    throw ParseError::at_line(source, scanner.line_number() + 1,
                              "file ends early: expected at least one vertex ('v' line)");
  }
  return builder.finish();
}

std::string format_obj(const TriangleMesh& mesh) {
  std::string out;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    out += 'v';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      detail::append_number(out, mesh.vertices(v, c));
    }
    // OBJ's colour extension has no alpha.
    for (int c = 0; mesh.has_vertex_colors() && c < 3; ++c) {
      out += ' ';
      detail::append_number(out, mesh.vertex_colors(v, c));
    }
    out += '\n';
  }
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      detail::append_number(out, mesh.triangles(t, c) + 1);
    }
    out += '\n';
  }
  return out;
}

}  // namespace khz::reduced
