#pragma once
// Pieces shared by the OBJ, OFF, STL and PLY readers and writers: comment-aware tokens,
// count and index checks with uniform messages, the growing mesh a parser fills, colour
// conversion and number output.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include "detail/byte_reader.hpp"
#include "detail/number_text.hpp"
#include "detail/text_scanner.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced::detail {

/// Parses all of `token` as a finite float. Colour channels are read this way because going
/// through double rounds twice, which is not always exact (e.g. "7.03853069e-26").
inline bool parse_float(std::string_view token, float& value) noexcept {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

/// An 8-bit colour channel in [0, 1]; the same expression writers invert, so k/255 round-trips.
inline float channel_from_byte(std::int64_t byte) { return static_cast<float>(byte) / 255.0f; }

/// A [0, 1] colour channel as 0–255 (NaN and out-of-range values clamp).
inline std::uint8_t byte_from_channel(float channel) {
  if (!(channel > 0.0f)) return 0;
  if (channel >= 1.0f) return 255;
  return static_cast<std::uint8_t>(std::lround(channel * 255.0f));
}

/// The tokens of a TextScanner's current line that precede a comment. The comment may start
/// anywhere, even inside a token: CGAL's mesh_with_colors.off has lines like "1 -1 0 0.9 0 0#red".
class UncommentedTokens {
 public:
  UncommentedTokens(TextScanner& scanner, char comment) : m_scanner(scanner), m_comment(comment) {}

  /// Next token, or an empty view at the end of the line or at the comment.
  std::string_view next() {
    if (m_in_comment) return {};
    std::string_view token = m_scanner.next_token();
    const std::size_t comment = token.find(m_comment);
    if (comment != std::string_view::npos) {
      m_in_comment = true;
      token = token.substr(0, comment);
    }
    return token;
  }

  /// True when no token precedes the comment or the end of the line.
  bool exhausted() {
    if (m_in_comment) return true;
    const std::string_view rest = m_scanner.rest_of_line();
    return rest.empty() || rest.front() == m_comment;
  }

  std::string_view require(std::string_view what) {
    const std::string_view token = next();
    if (token.empty()) m_scanner.fail("expected " + std::string(what) + ", found end of line");
    return token;
  }

  /// `token` (from next()) as a finite double.
  double to_double(std::string_view token, std::string_view what) const {
    double value = 0.0;
    if (!parse_double(token, value)) {
      m_scanner.fail("expected " + std::string(what) + " (a finite number), found " +
                     quoted_token(token));
    }
    return value;
  }

  double require_double(std::string_view what) { return to_double(require(what), what); }

  /// Next token as an integer; callers check its range with a message that names its role.
  std::int64_t require_integer(std::string_view what) {
    const std::string_view token = require(what);
    std::int64_t value = 0;
    if (!parse_integer(token, value)) {
      m_scanner.fail("expected " + std::string(what) + " (an integer), found " +
                     quoted_token(token));
    }
    return value;
  }

 private:
  TextScanner& m_scanner;
  char m_comment;
  bool m_in_comment = false;
};

// The checks below report through `at`, a TextScanner, ByteReader or any type with the same
// fail(), so the error carries the line or byte offset where the parser stands.

/// Rejects vertex counts that int indices cannot address.
template <typename Reporter>
void check_vertex_limit(const Reporter& at, std::int64_t count) {
  if (count > max_index) {
    at.fail(std::to_string(count) + " vertices exceed the supported maximum of " +
            std::to_string(max_index));
  }
}

/// Rejects faces with fewer than three corners. `face` is 0-based in file order.
template <typename Reporter>
void check_corner_count(const Reporter& at, std::int64_t face, std::int64_t corners) {
  if (corners < 3) {
    at.fail("face " + std::to_string(face) + " has " + std::to_string(corners) +
            " corners, but a face needs at least 3");
  }
}

/// A 0-based corner index checked against the file's vertex count.
template <typename Reporter>
int checked_corner(const Reporter& at, std::int64_t face, std::int64_t index,
                   std::int64_t num_vertices) {
  if (index < 0 || index >= num_vertices) {
    at.fail("face " + std::to_string(face) + " uses vertex " + std::to_string(index) +
            ", but the file has " + std::to_string(num_vertices) + " vertices");
  }
  return static_cast<int>(index);
}

/// The mesh a parser fills: flat buffers that become the TriangleMesh's matrices at the end.
class SurfaceBuilder {
 public:
  /// Call only with counts already checked against the file size.
  void reserve(std::int64_t vertices, std::int64_t triangles, bool colors) {
    m_positions.reserve(3 * static_cast<std::size_t>(vertices));
    m_triangles.reserve(3 * static_cast<std::size_t>(triangles));
    if (colors) m_colors.reserve(4 * static_cast<std::size_t>(vertices));
  }

  std::int64_t num_vertices() const noexcept {
    return static_cast<std::int64_t>(m_positions.size() / 3);
  }
  /// The three coordinates of vertex `v`.
  const double* position(int v) const noexcept { return m_positions.data() + 3 * std::size_t(v); }

  /// Adds an uncoloured vertex; it is white if other vertices have colours.
  void add_vertex(const std::array<double, 3>& position) {
    m_positions.insert(m_positions.end(), position.begin(), position.end());
    if (m_has_colors) m_colors.insert(m_colors.end(), 4, 1.0f);
  }

  /// Adds a coloured vertex; vertices added before without a colour become white.
  void add_vertex(const std::array<double, 3>& position, const std::array<float, 4>& rgba) {
    if (!m_has_colors) {
      m_colors.assign(4 * m_positions.size() / 3, 1.0f);
      m_has_colors = true;
    }
    m_positions.insert(m_positions.end(), position.begin(), position.end());
    m_colors.insert(m_colors.end(), rgba.begin(), rgba.end());
  }

  /// Adds a polygon of valid vertex indices as a triangle fan from its first corner.
  void add_polygon(std::span<const int> corners) {
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      m_triangles.insert(m_triangles.end(), {corners[0], corners[i], corners[i + 1]});
    }
  }

  TriangleMesh finish() const {
    const auto rows = static_cast<Eigen::Index>(num_vertices());
    TriangleMesh mesh;
    mesh.vertices = Eigen::Map<const VertexMatrix>(m_positions.data(), rows, 3);
    mesh.triangles = Eigen::Map<const TriangleMatrix>(
        m_triangles.data(), static_cast<Eigen::Index>(m_triangles.size() / 3), 3);
    if (m_has_colors) mesh.vertex_colors = Eigen::Map<const ColorMatrix>(m_colors.data(), rows, 4);
    return mesh;
  }

 private:
  std::vector<double> m_positions;  // x y z per vertex
  std::vector<int> m_triangles;     // three indices per triangle
  std::vector<float> m_colors;      // r g b a per vertex, once any vertex has a colour
  bool m_has_colors = false;
};

}  // namespace khz::reduced::detail
