#include <khz/reduced/io/ply.hpp>

#include "detail/byte_reader.hpp"
#include "detail/text_scanner.hpp"
#include "io/surface_parsing.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

using detail::ByteReader;
using detail::Endian;
using detail::TextScanner;

// ---- Header -------------------------------------------------------------------------------

enum class PlyType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct TypeName {
  std::string_view name;
  PlyType type;
};

constexpr std::array<TypeName, 16> type_names = {{
    {"char", PlyType::int8},
    {"uchar", PlyType::uint8},
    {"short", PlyType::int16},
    {"ushort", PlyType::uint16},
    {"int", PlyType::int32},
    {"uint", PlyType::uint32},
    {"float", PlyType::float32},
    {"double", PlyType::float64},
    {"int8", PlyType::int8},
    {"uint8", PlyType::uint8},
    {"int16", PlyType::int16},
    {"uint16", PlyType::uint16},
    {"int32", PlyType::int32},
    {"uint32", PlyType::uint32},
    {"float32", PlyType::float32},
    {"float64", PlyType::float64},
}};

bool is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

std::size_t size_of(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 8;
}

/// Range of an integer type, for checking ASCII values.
std::array<std::int64_t, 2> range_of(PlyType type) {
  switch (type) {
    case PlyType::int8:
      return {INT8_MIN, INT8_MAX};
    case PlyType::uint8:
      return {0, UINT8_MAX};
    case PlyType::int16:
      return {INT16_MIN, INT16_MAX};
    case PlyType::uint16:
      return {0, UINT16_MAX};
    case PlyType::int32:
      return {INT32_MIN, INT32_MAX};
    default:
      return {0, UINT32_MAX};
  }
}

/// What the parser does with a property's values.
enum class Role : std::uint8_t { skip, x, y, z, red, green, blue, alpha, corners };

struct Property {
  std::string name;
  std::string description;          // "'x' of element 'vertex'", for error messages
  PlyType type = PlyType::float32;  // item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::uint8;
  Role role = Role::skip;
};

enum class Kind : std::uint8_t { other, vertex, face };

struct Element {
  std::string name;
  Kind kind = Kind::other;
  std::int64_t count = 0;
  std::int64_t line = 0;
  std::vector<Property> properties;

  bool has(Role role) const {
    for (const Property& property : properties) {
      if (property.role == role) return true;
    }
    return false;
  }
};

struct Header {
  PlyEncoding encoding = PlyEncoding::ascii;
  std::vector<Element> elements;
  std::size_t vertex_element = 0;  // index into elements; finish_header() ensures it exists
  std::optional<std::size_t> face_element;

  const Element& vertices() const { return elements[vertex_element]; }
  std::int64_t num_faces() const { return face_element ? elements[*face_element].count : 0; }
};

PlyType parse_type(const TextScanner& scanner, std::string_view token) {
  for (const TypeName& entry : type_names) {
    if (entry.name == token) return entry.type;
  }
  scanner.fail("unknown property type " + detail::quoted_token(token) +
               "; expected char, uchar, short, ushort, int, uint, float, double or a sized name "
               "such as int32 or float64");
}

/// The rest of a `format NAME VERSION` line.
PlyEncoding parse_format(TextScanner& scanner) {
  const std::string_view name = scanner.require_token("the PLY format");
  scanner.require_token("the format version");  // always 1.0; not checked
  if (name == "ascii") return PlyEncoding::ascii;
  if (name == "binary_little_endian") return PlyEncoding::binary_little_endian;
  if (name == "binary_big_endian") return PlyEncoding::binary_big_endian;
  scanner.fail("unknown PLY format " + detail::quoted_token(name) +
               "; expected ascii, binary_little_endian or binary_big_endian");
}

/// The role of a property of a vertex or face element, checking the property's shape.
Role role_of(const TextScanner& scanner, const Element& element, const Property& property) {
  Role role = Role::skip;
  if (element.kind == Kind::vertex) {
    constexpr std::array<std::string_view, 7> names = {"x",     "y",    "z",    "red",
                                                       "green", "blue", "alpha"};
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (property.name == names[i])
        role = static_cast<Role>(static_cast<int>(Role::x) + static_cast<int>(i));
    }
    if (role != Role::skip && property.is_list) {
      scanner.fail("property " + property.description + " must be a scalar, not a list");
    }
  } else if (element.kind == Kind::face &&
             (property.name == "vertex_indices" || property.name == "vertex_index")) {
    if (!property.is_list || !is_integer(property.type)) {
      scanner.fail("property " + property.description + " must be a list of integers");
    }
    role = Role::corners;
  }
  if (role != Role::skip && element.has(role)) {
    scanner.fail("element '" + element.name + "' has a second " + property.description);
  }
  return role;
}

void read_property(TextScanner& scanner, Element& element) {
  Property property;
  const std::string_view type = scanner.require_token("a property type or 'list'");
  if (type == "list") {
    property.is_list = true;
    property.count_type = parse_type(scanner, scanner.require_token("the list count type"));
    if (!is_integer(property.count_type)) scanner.fail("a list's count type must be an integer");
    property.type = parse_type(scanner, scanner.require_token("the list item type"));
  } else {
    property.type = parse_type(scanner, type);
  }
  property.name = scanner.require_token("a property name");
  property.description = "'" + property.name + "' of element '" + element.name + "'";
  property.role = role_of(scanner, element, property);
  element.properties.push_back(std::move(property));
}

void read_element(TextScanner& scanner, Header& header) {
  Element element;
  element.name = scanner.require_token("an element name");
  element.count = scanner.require_integer("element count", 0, INT64_MAX);
  element.line = scanner.line_number();
  const Kind kind = element.name == "vertex" ? Kind::vertex
                    : element.name == "face" ? Kind::face
                                             : Kind::other;
  for (const Element& earlier : header.elements) {
    if (kind != Kind::other && earlier.kind == kind) {
      scanner.fail("a second '" + element.name + "' element");
    }
  }
  element.kind = kind;
  header.elements.push_back(std::move(element));
}

/// Smallest number of bytes an instance of `element` can take in the body.
std::size_t min_instance_bytes(const Element& element, PlyEncoding encoding) {
  std::size_t bytes = 0;
  for (const Property& property : element.properties) {
    // A face's corner list holds at least three indices; other lists may be empty.
    const std::size_t items = property.role == Role::corners ? 3 : 0;
    if (encoding == PlyEncoding::ascii) {
      bytes += 2 * (1 + items);  // one digit and a separator per value
    } else {
      bytes += property.is_list ? size_of(property.count_type) + items * size_of(property.type)
                                : size_of(property.type);
    }
  }
  // The file's last value may lack a separator.
  return encoding == PlyEncoding::ascii ? bytes - 1 : bytes;
}

/// Checks, once the header is complete, what only the whole header can tell: required
/// properties and element counts the body can actually hold.
void finish_header(TextScanner& scanner, Header& header) {
  std::optional<std::size_t> vertex_element;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    if (header.elements[e].kind == Kind::vertex) vertex_element = e;
    if (header.elements[e].kind == Kind::face) header.face_element = e;
  }
  if (!vertex_element) scanner.fail("the header declares no 'vertex' element");
  header.vertex_element = *vertex_element;
  Element& vertices = header.elements[*vertex_element];
  for (const Role role : {Role::x, Role::y, Role::z}) {
    if (!vertices.has(role)) {
      const char* name = role == Role::x ? "x" : role == Role::y ? "y" : "z";
      throw ParseError::at_line(scanner.source(), vertices.line,
                                std::string("element 'vertex' has no property '") + name + "'");
    }
  }
  // Colours need all of red, green and blue; a lone channel is treated as any other property.
  if (!(vertices.has(Role::red) && vertices.has(Role::green) && vertices.has(Role::blue))) {
    for (Property& property : vertices.properties) {
      if (property.role >= Role::red && property.role <= Role::alpha) property.role = Role::skip;
    }
  }
  if (header.face_element && !header.elements[*header.face_element].has(Role::corners)) {
    throw ParseError::at_line(scanner.source(), header.elements[*header.face_element].line,
                              "element 'face' has no 'vertex_indices' list");
  }
  for (const Element& element : header.elements) {
    if (element.properties.empty()) continue;  // its instances take no bytes and are skipped
    detail::check_count_fits(scanner, element.count, min_instance_bytes(element, header.encoding),
                             "'" + element.name + "' elements");
  }
  detail::check_vertex_limit(scanner, vertices.count);
}

Header read_header(TextScanner& scanner) {
  scanner.require_content_line(detail::no_comment, "'ply'");
  const std::string_view magic = scanner.require_token("'ply'");
  if (magic != "ply") {
    scanner.fail("expected 'ply' (the PLY magic), found " + detail::quoted_token(magic));
  }
  Header header;
  std::optional<PlyEncoding> encoding;
  while (true) {
    scanner.require_content_line(detail::no_comment, "'end_header'");
    const std::string_view keyword = scanner.require_token("a header keyword");
    if (keyword == "end_header") break;
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (encoding) scanner.fail("a second 'format' line");
      encoding = parse_format(scanner);
    } else if (keyword == "element") {
      read_element(scanner, header);
    } else if (keyword == "property") {
      if (header.elements.empty()) scanner.fail("a property before any element");
      read_property(scanner, header.elements.back());
    } else {
      scanner.fail(
          "expected 'format', 'element', 'property', 'comment', 'obj_info' or 'end_header', "
          "found " +
          detail::quoted_token(keyword));
    }
  }
  if (!encoding) scanner.fail("the header has no 'format' line");
  header.encoding = *encoding;
  finish_header(scanner, header);
  return header;
}

// ---- Body ---------------------------------------------------------------------------------
// The body reader is written once against a value source; AsciiValues and BinaryValues supply
// read(), skip(), check_list_fits() and fail() at the current line or byte offset.

/// Values of an ASCII body: whitespace-separated tokens, across line breaks.
class AsciiValues {
 public:
  explicit AsciiValues(TextScanner& scanner) : m_scanner(scanner) {
    while (!m_scanner.next_token().empty()) {
    }  // anything after end_header on its line is ignored
  }

  double read(PlyType type, std::string_view what) {
    next_line_if_needed(what);
    if (!is_integer(type)) return m_scanner.require_double(what);
    const auto [min, max] = range_of(type);
    return static_cast<double>(m_scanner.require_integer(what, min, max));
  }

  void skip(PlyType, std::string_view what) {
    next_line_if_needed(what);
    m_scanner.require_token(what);  // skipped values are not parsed
  }

  /// Each item is a token, so an overlong list ends with "file ends early"; nothing to check.
  void check_list_fits(std::int64_t, PlyType) const {}

  [[noreturn]] void fail(const std::string& message) const { m_scanner.fail(message); }

 private:
  void next_line_if_needed(std::string_view what) {
    while (m_scanner.line_exhausted()) m_scanner.require_content_line(detail::no_comment, what);
  }

  TextScanner& m_scanner;
};

/// Values of a binary body; errors point at the first byte of the offending value.
class BinaryValues {
 public:
  BinaryValues(std::string_view data, const std::string& source, std::size_t offset, Endian endian)
      : m_reader(data, source, offset), m_endian(endian), m_value_start(offset) {}

  double read(PlyType type, std::string_view what) {
    m_value_start = m_reader.offset();
    switch (type) {
      case PlyType::int8:
        return m_reader.read<std::int8_t>(m_endian, what);
      case PlyType::uint8:
        return m_reader.read<std::uint8_t>(m_endian, what);
      case PlyType::int16:
        return m_reader.read<std::int16_t>(m_endian, what);
      case PlyType::uint16:
        return m_reader.read<std::uint16_t>(m_endian, what);
      case PlyType::int32:
        return m_reader.read<std::int32_t>(m_endian, what);
      case PlyType::uint32:
        return m_reader.read<std::uint32_t>(m_endian, what);
      case PlyType::float32:
        return finite(m_reader.read<float>(m_endian, what), what);
      case PlyType::float64:
        return finite(m_reader.read<double>(m_endian, what), what);
    }
    return 0.0;
  }

  void skip(PlyType type, std::string_view what) {
    m_value_start = m_reader.offset();
    m_reader.skip(size_of(type), what);
  }

  void check_list_fits(std::int64_t length, PlyType type) const {
    const std::uint64_t needed = static_cast<std::uint64_t>(length) * size_of(type);
    if (needed > m_reader.remaining_bytes()) {
      fail("list of " + std::to_string(length) + " items needs " + std::to_string(needed) +
           " bytes, but only " + std::to_string(m_reader.remaining_bytes()) + " remain");
    }
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError::at_byte(m_reader.source(), static_cast<std::int64_t>(m_value_start), message);
  }

 private:
  double finite(double value, std::string_view what) const {
    if (!std::isfinite(value)) {
      fail("expected " + std::string(what) + " (a finite number), found " +
           detail::number_text(value));
    }
    return value;
  }

  ByteReader m_reader;
  Endian m_endian;
  std::size_t m_value_start;
};

/// A list's length, checked against what the rest of the file can hold.
template <typename Values>
std::int64_t read_list_length(Values& values, const Property& property) {
  const auto length =
      static_cast<std::int64_t>(values.read(property.count_type, property.description));
  if (length < 0) {
    values.fail("negative list length " + std::to_string(length) + " for " + property.description);
  }
  values.check_list_fits(length, property.type);
  return length;
}

template <typename Values>
void skip_property(Values& values, const Property& property) {
  const std::int64_t items = property.is_list ? read_list_length(values, property) : 1;
  for (std::int64_t i = 0; i < items; ++i) values.skip(property.type, property.description);
}

/// A colour channel: integer types hold 0–255, floating-point types [0, 1].
template <typename Values>
float read_channel(Values& values, const Property& property) {
  const double value = values.read(property.type, property.description);
  const double max = is_integer(property.type) ? 255.0 : 1.0;
  if (value < 0.0 || value > max) {
    values.fail("expected " + property.description + " in [0, " + detail::number_text(max) +
                "], found " + detail::number_text(value));
  }
  return is_integer(property.type) ? detail::channel_from_byte(static_cast<std::int64_t>(value))
                                   : static_cast<float>(value);
}

template <typename Values>
void read_vertex(Values& values, const Element& element, detail::SurfaceBuilder& builder,
                 bool colors) {
  std::array<double, 3> position = {};
  std::array<float, 4> rgba = {1.0f, 1.0f, 1.0f, 1.0f};
  for (const Property& property : element.properties) {
    if (property.role >= Role::x && property.role <= Role::z) {
      position[static_cast<int>(property.role) - static_cast<int>(Role::x)] =
          values.read(property.type, property.description);
    } else if (property.role >= Role::red && property.role <= Role::alpha) {
      rgba[static_cast<int>(property.role) - static_cast<int>(Role::red)] =
          read_channel(values, property);
    } else {
      skip_property(values, property);
    }
  }
  if (colors) {
    builder.add_vertex(position, rgba);
  } else {
    builder.add_vertex(position);
  }
}

template <typename Values>
void read_face(Values& values, const Element& element, std::int64_t face, std::int64_t num_vertices,
               std::vector<int>& corners, detail::SurfaceBuilder& builder) {
  for (const Property& property : element.properties) {
    if (property.role != Role::corners) {
      skip_property(values, property);
      continue;
    }
    const std::int64_t length = read_list_length(values, property);
    detail::check_corner_count(values, face, length);
    corners.clear();
    for (std::int64_t c = 0; c < length; ++c) {
      const auto index =
          static_cast<std::int64_t>(values.read(property.type, property.description));
      corners.push_back(detail::checked_corner(values, face, index, num_vertices));
    }
  }
  builder.add_polygon(corners);
}

template <typename Values>
TriangleMesh read_body(const Header& header, Values& values) {
  const bool colors = header.vertices().has(Role::red);
  detail::SurfaceBuilder builder;
  builder.reserve(header.vertices().count, header.num_faces(), colors);
  std::vector<int> corners;
  for (const Element& element : header.elements) {
    if (element.properties.empty()) continue;
    for (std::int64_t i = 0; i < element.count; ++i) {
      if (element.kind == Kind::vertex) {
        read_vertex(values, element, builder, colors);
      } else if (element.kind == Kind::face) {
        read_face(values, element, i, header.vertices().count, corners, builder);
      } else {
        for (const Property& property : element.properties) skip_property(values, property);
      }
    }
  }
  return builder.finish();
}

// ---- Writing ------------------------------------------------------------------------------

void append_value(std::string& out, PlyEncoding encoding, auto value) {
  if (encoding == PlyEncoding::ascii) {
    detail::append_number(out, value);
    out += ' ';
  } else {
    detail::append_binary(
        out, value, encoding == PlyEncoding::binary_little_endian ? Endian::little : Endian::big);
  }
}

/// Ends an ASCII line: replaces the separator after its last value by a line break.
void end_line(std::string& out, PlyEncoding encoding) {
  if (encoding == PlyEncoding::ascii) out.back() = '\n';
}

}  // namespace

TriangleMesh parse_ply(std::string_view data, const std::string& source) {
  TextScanner scanner(data, source);
  const Header header = read_header(scanner);
  if (header.encoding == PlyEncoding::ascii) {
    AsciiValues values(scanner);
    return read_body(header, values);
  }
  const std::size_t body = data.size() - scanner.remaining_bytes();
  BinaryValues values(
      data, source, body,
      header.encoding == PlyEncoding::binary_little_endian ? Endian::little : Endian::big);
  return read_body(header, values);
}

std::string format_ply(const TriangleMesh& mesh, PlyEncoding encoding) {
  const bool colors = mesh.has_vertex_colors();
  std::string out = "ply\nformat ";
  out += encoding == PlyEncoding::ascii                  ? "ascii"
         : encoding == PlyEncoding::binary_little_endian ? "binary_little_endian"
                                                         : "binary_big_endian";
  out += " 1.0\ncomment written by Kilohertz\nelement vertex ";
  detail::append_number(out, mesh.num_vertices());
  out += "\nproperty double x\nproperty double y\nproperty double z\n";
  if (colors) {
    out += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
  }
  out += "element face ";
  detail::append_number(out, mesh.num_triangles());
  out += "\nproperty list uchar int vertex_indices\nend_header\n";

  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) append_value(out, encoding, mesh.vertices(v, c));
    for (int c = 0; colors && c < 4; ++c) {
      append_value(out, encoding, detail::byte_from_channel(mesh.vertex_colors(v, c)));
    }
    end_line(out, encoding);
  }
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    append_value(out, encoding, std::uint8_t{3});
    for (int c = 0; c < 3; ++c) append_value(out, encoding, mesh.triangles(t, c));
    end_line(out, encoding);
  }
  return out;
}

}  // namespace khz::reduced
