#include <khz/reduced/io/stl.hpp>

#include "detail/byte_reader.hpp"
#include "detail/text_scanner.hpp"
#include "io/surface_parsing.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

using detail::ByteReader;
using detail::Endian;
using detail::TextScanner;

constexpr std::size_t header_bytes = 80;
constexpr std::size_t count_bytes = 4;
constexpr std::size_t triangle_bytes = 50;  // normal, three corners (float32 ×12), attribute

/// Merges corners with bit-identical coordinates into one vertex: an open-addressing hash table
/// of vertex indices, keyed by the coordinates' bit patterns (so -0 and 0 stay distinct).
class CornerWelder {
 public:
  explicit CornerWelder(std::size_t expected_vertices) {
    m_slots.assign(std::bit_ceil(std::max<std::size_t>(16, 2 * expected_vertices)), -1);
  }

  template <typename Reporter>
  int vertex_for(const std::array<double, 3>& position, detail::SurfaceBuilder& builder,
                 const Reporter& at) {
    const std::array<std::uint64_t, 3> key = bits(position.data());
    std::size_t slot = hash(key) & (m_slots.size() - 1);
    while (m_slots[slot] >= 0) {
      if (bits(builder.position(m_slots[slot])) == key) return m_slots[slot];
      slot = (slot + 1) & (m_slots.size() - 1);
    }
    detail::check_vertex_limit(at, builder.num_vertices() + 1);
    const int vertex = static_cast<int>(builder.num_vertices());
    builder.add_vertex(position);
    m_slots[slot] = vertex;
    // Keep the table at most half full so probe sequences stay short.
    if (2 * builder.num_vertices() > static_cast<std::int64_t>(m_slots.size())) rehash(builder);
    return vertex;
  }

 private:
  static std::array<std::uint64_t, 3> bits(const double* p) {
    return {std::bit_cast<std::uint64_t>(p[0]), std::bit_cast<std::uint64_t>(p[1]),
            std::bit_cast<std::uint64_t>(p[2])};
  }

  /// Mixes all 64 bits of each coordinate into the low bits the table uses: "round" values such
  /// as 1.0 or 0.5 have all-zero low mantissa bits.
  static std::size_t hash(const std::array<std::uint64_t, 3>& key) {
    std::uint64_t h = 0;
    for (const std::uint64_t k : key) {
      h = (h ^ k ^ (k >> 32)) * 0x9E3779B97F4A7C15u;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }

  void rehash(const detail::SurfaceBuilder& builder) {
    m_slots.assign(2 * m_slots.size(), -1);
    for (int v = 0; v < builder.num_vertices(); ++v) {
      std::size_t slot = hash(bits(builder.position(v))) & (m_slots.size() - 1);
      while (m_slots[slot] >= 0) slot = (slot + 1) & (m_slots.size() - 1);
      m_slots[slot] = v;
    }
  }

  std::vector<int> m_slots;  // vertex index, or -1 for an empty slot
};

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](char x, char y) { return (x >= 'A' && x <= 'Z' ? x - 'A' + 'a' : x) == y; });
}

/// Whether the first word of the file is "solid", the start of ASCII STL.
bool starts_with_solid(std::string_view data) {
  const std::size_t start = data.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && equals_ignoring_case(data.substr(start, 5), "solid");
}

/// Whether the start of the file holds a byte no ASCII STL holds (NUL or a control character
/// other than white space): binary data, whatever its header says.
bool holds_binary_bytes(std::string_view data) {
  const std::string_view start = data.substr(0, 1024);
  return std::any_of(start.begin(), start.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return byte < 32 && byte != '\t' && byte != '\n' && byte != '\v' && byte != '\f' &&
           byte != '\r';
  });
}

/// Next token must be `keyword` (lower case; matched case-insensitively).
void expect_keyword(TextScanner& scanner, std::string_view keyword) {
  const std::string_view token = scanner.next_token();
  if (!equals_ignoring_case(token, keyword)) {
    scanner.fail("expected '" + std::string(keyword) + "', found " +
                 (token.empty() ? std::string("end of line") : detail::quoted_token(token)));
  }
}

/// Moves to the next line, which must start with `keyword`.
void expect_line(TextScanner& scanner, std::string_view keyword, std::string_view quoted) {
  scanner.require_content_line(detail::no_comment, quoted);
  expect_keyword(scanner, keyword);
}

TriangleMesh parse_ascii(std::string_view data, const std::string& source) {
  TextScanner scanner(data, source);
  detail::SurfaceBuilder builder;
  CornerWelder welder(0);
  expect_line(scanner, "solid", "'solid'");  // the solid's name, if any, is ignored
  while (true) {
    scanner.require_content_line(detail::no_comment, "'facet' or 'endsolid'");
    const std::string_view keyword = scanner.require_token("'facet' or 'endsolid'");
    if (equals_ignoring_case(keyword, "endsolid")) {
      if (!scanner.next_content_line(detail::no_comment)) break;
      expect_keyword(scanner, "solid");  // files may hold several solids
      continue;
    }
    if (!equals_ignoring_case(keyword, "facet")) {
      scanner.fail("expected 'facet' or 'endsolid', found " + detail::quoted_token(keyword));
    }
    // The normal follows from the winding; it is not even parsed, since some exporters write
    // "nan" for degenerate facets.
    expect_keyword(scanner, "normal");
    for (int i = 0; i < 3; ++i) scanner.require_token("facet normal component");
    expect_line(scanner, "outer", "'outer loop'");
    expect_keyword(scanner, "loop");
    std::array<int, 3> corners;
    for (int& corner : corners) {
      expect_line(scanner, "vertex", "'vertex'");
      std::array<double, 3> position;
      for (double& coordinate : position) coordinate = scanner.require_double("vertex coordinate");
      corner = welder.vertex_for(position, builder, scanner);
    }
    expect_line(scanner, "endloop", "'endloop'");
    expect_line(scanner, "endfacet", "'endfacet'");
    builder.add_polygon(corners);
  }
  return builder.finish();
}

TriangleMesh parse_binary(std::string_view data, const std::string& source,
                          std::int64_t num_triangles) {
  ByteReader reader(data, source, header_bytes + count_bytes);
  detail::SurfaceBuilder builder;
  // A closed mesh has about half as many vertices as triangles.
  builder.reserve(num_triangles / 2, num_triangles, false);
  CornerWelder welder(static_cast<std::size_t>(num_triangles / 2));
  for (std::int64_t t = 0; t < num_triangles; ++t) {
    reader.skip(12, "facet normal");
    std::array<int, 3> corners;
    for (int& corner : corners) {
      std::array<double, 3> position;
      for (double& coordinate : position) {
        const std::size_t offset = reader.offset();
        coordinate = reader.read<float>(Endian::little, "vertex coordinate");
        if (!std::isfinite(coordinate)) {
          throw ParseError::at_byte(
              source, static_cast<std::int64_t>(offset),
              "expected a finite vertex coordinate, found " + detail::number_text(coordinate));
        }
      }
      corner = welder.vertex_for(position, builder, reader);
    }
    reader.skip(2, "attribute byte count");
    builder.add_polygon(corners);
  }
  return builder.finish();
}

/// Unit normal of triangle t, or zero for a degenerate one.
Eigen::Vector3d facet_normal(const TriangleMesh& mesh, Eigen::Index t) {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0));
  const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1));
  const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2));
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double length = n.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Vector3d::Zero();
  return n / length;
}

template <typename Row>
void append_xyz(std::string& out, const Row& xyz) {
  for (int c = 0; c < 3; ++c) {
    out += ' ';
    detail::append_number(out, double{xyz(c)});
  }
}

}  // namespace

TriangleMesh parse_stl(std::string_view data, const std::string& source) {
  if (data.size() >= header_bytes + count_bytes) {
    ByteReader reader(data, source, header_bytes);
    const std::uint64_t count = reader.read<std::uint32_t>(Endian::little, "triangle count");
    const std::uint64_t binary_size = header_bytes + count_bytes + triangle_bytes * count;
    if (binary_size == data.size()) {
      return parse_binary(data, source, static_cast<std::int64_t>(count));
    }
    const std::string size_mismatch =
        "the header declares " + std::to_string(count) + " triangles, so the file should have " +
        std::to_string(binary_size) + " bytes, but it has " + std::to_string(data.size());
    if (!starts_with_solid(data)) {
      throw ParseError::at_byte(
          source, header_bytes,
          "not ASCII STL (no 'solid' at the start) and not binary STL: " + size_mismatch);
    }
    // Many binary writers start the header with "solid" too: the bytes after it tell.
    if (holds_binary_bytes(data)) {
      throw ParseError::at_byte(source, header_bytes,
                                "binary STL (its header starts with 'solid', but the file holds "
                                "non-text bytes) of the wrong size: " +
                                    size_mismatch);
    }
  }
  return parse_ascii(data, source);
}

std::string format_stl_binary(const TriangleMesh& mesh) {
  std::string out = "binary STL written by Kilohertz";
  out.resize(header_bytes, ' ');
  const auto count = static_cast<std::uint64_t>(mesh.num_triangles());
  if (count > UINT32_MAX) {
    throw Error("binary STL holds at most 4294967295 triangles; the mesh has " +
                std::to_string(count));
  }
  out.reserve(header_bytes + count_bytes + triangle_bytes * count);
  detail::append_binary(out, static_cast<std::uint32_t>(count), Endian::little);
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3f normal = facet_normal(mesh, t).cast<float>();
    for (int c = 0; c < 3; ++c) detail::append_binary(out, normal(c), Endian::little);
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) {
        const auto coordinate = static_cast<float>(mesh.vertices(mesh.triangles(t, k), c));
        detail::append_binary(out, coordinate, Endian::little);
      }
    }
    detail::append_binary(out, std::uint16_t{0}, Endian::little);
  }
  return out;
}

std::string format_stl_ascii(const TriangleMesh& mesh) {
  std::string out = "solid kilohertz\n";
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    out += "facet normal";
    append_xyz(out, facet_normal(mesh, t));
    out += "\n outer loop\n";
    for (int k = 0; k < 3; ++k) {
      out += "  vertex";
      append_xyz(out, mesh.vertices.row(mesh.triangles(t, k)));
      out += '\n';
    }
    out += " endloop\nendfacet\n";
  }
  out += "endsolid kilohertz\n";
  return out;
}

}  // namespace khz::reduced
