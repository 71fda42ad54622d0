// ParaView time series (khz_series): .vtp frames and the .pvd collection, checked by reading the
// written files back with the test's own XML parser and appended-data decoder (independent of
// the writer's code), bit for bit.
#include <khz/reduced/errors.hpp>
#include <khz/series/point_array.hpp>
#include <khz/series/pvd_collection.hpp>
#include <khz/series/vtp_file.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace khz::series {
namespace {

using reduced::TriangleMatrix;
using reduced::VertexMatrix;

// ---- A small XML parser: well-formedness of the subset VTK files use ----

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::vector<XmlElement> children;

  /// The attribute's (unescaped) value; throws if it is missing.
  const std::string& attribute(std::string_view key) const {
    for (const auto& [k, v] : attributes) {
      if (k == key) return v;
    }
    throw std::runtime_error("<" + name + "> has no attribute " + std::string(key));
  }
  bool has_attribute(std::string_view key) const {
    return std::any_of(attributes.begin(), attributes.end(),
                       [&](const auto& a) { return a.first == key; });
  }
  std::vector<const XmlElement*> all(std::string_view child_name) const {
    std::vector<const XmlElement*> found;
    for (const XmlElement& child : children) {
      if (child.name == child_name) found.push_back(&child);
    }
    return found;
  }
  /// The only child of that name; throws unless there is exactly one.
  const XmlElement& only(std::string_view child_name) const {
    const auto found = all(child_name);
    if (found.size() != 1) {
      throw std::runtime_error("<" + name + "> has " + std::to_string(found.size()) + " <" +
                               std::string(child_name) + ">");
    }
    return *found.front();
  }
};

/// Parses a whole document: an optional declaration, one root element, whitespace around it.
/// Elements must nest and close by name, attributes be double-quoted, unique and free of '<',
/// '&' start one of the five predefined entities; text may hold only whitespace (VTK's).
/// Throws std::runtime_error naming the byte offset of the first violation.
class XmlParser {
 public:
  explicit XmlParser(std::string_view text) : m_text(text) {}

  XmlElement document() {
    if (m_text.substr(0, 5) == "<?xml") {
      const std::size_t end = m_text.find("?>");
      if (end == std::string_view::npos) fail("unterminated declaration");
      m_at = end + 2;
    }
    skip_whitespace();
    XmlElement root = element();
    skip_whitespace();
    if (m_at != m_text.size()) fail("content after the root element");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("XML byte " + std::to_string(m_at) + ": " + what);
  }
  char peek() const { return m_at < m_text.size() ? m_text[m_at] : '\0'; }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++m_at;
  }
  void skip_whitespace() {
    while (m_at < m_text.size() &&
           std::string_view(" \t\r\n").find(peek()) != std::string_view::npos) {
      ++m_at;
    }
  }
  std::string name() {
    const std::size_t start = m_at;
    const auto name_char = [](char c, bool first) {
      return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':' ||
             (!first && (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.'));
    };
    while (m_at < m_text.size() && name_char(peek(), m_at == start)) ++m_at;
    if (m_at == start) fail("expected a name");
    return std::string(m_text.substr(start, m_at - start));
  }
  /// Appends the character an entity reference at m_at stands for.
  void entity(std::string& out) {
    static const std::pair<const char*, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    for (const auto& [spelling, c] : entities) {
      if (m_text.substr(m_at).starts_with(spelling)) {
        out += c;
        m_at += std::strlen(spelling);
        return;
      }
    }
    fail("bad entity reference");
  }
  XmlElement element() {
    expect('<');
    XmlElement result;
    result.name = name();
    while (true) {
      const std::size_t before = m_at;
      skip_whitespace();
      if (peek() == '/' || peek() == '>') break;
      if (m_at == before) fail("expected whitespace before an attribute");
      std::string key = name();
      if (result.has_attribute(key)) fail("duplicate attribute " + key);
      skip_whitespace();
      expect('=');
      skip_whitespace();
      expect('"');
      std::string value;
      while (peek() != '"') {
        if (m_at >= m_text.size() || peek() == '<') fail("unterminated attribute value");
        if (peek() == '&') {
          entity(value);
        } else {
          value += m_text[m_at++];
        }
      }
      ++m_at;
      result.attributes.emplace_back(std::move(key), std::move(value));
    }
    if (peek() == '/') {
      ++m_at;
      expect('>');
      return result;
    }
    expect('>');
    while (true) {
      skip_whitespace();
      if (m_at >= m_text.size()) fail("<" + result.name + "> is not closed");
      if (m_text.substr(m_at).starts_with("</")) break;
      if (peek() != '<') fail("unexpected text in <" + result.name + ">");
      result.children.push_back(element());
    }
    m_at += 2;
    if (name() != result.name) fail("closing tag does not match <" + result.name + ">");
    skip_whitespace();
    expect('>');
    return result;
  }

  std::string_view m_text;
  std::size_t m_at = 0;
};

XmlElement parse_xml(std::string_view text) { return XmlParser(text).document(); }

// ---- VTK XML PolyData with a raw appended block, decoded independently ----

/// The little-endian value of type T (1, 4 or 8 bytes) at `bytes`.
template <typename T>
T little_endian(const char* bytes) {
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    bits |= std::uint64_t{static_cast<unsigned char>(bytes[i])} << (8 * i);
  }
  if constexpr (sizeof(T) == 8) {
    return std::bit_cast<T>(bits);
  } else if constexpr (sizeof(T) == 4) {
    return std::bit_cast<T>(static_cast<std::uint32_t>(bits));
  } else {
    return std::bit_cast<T>(static_cast<std::uint8_t>(bits));
  }
}

/// A .vtp file: its XML (the raw block cut out) and the raw block.
struct VtpFile {
  XmlElement root;
  std::string raw;

  /// The Piece element.
  const XmlElement& piece() const { return root.only("PolyData").only("Piece"); }

  /// The values of an appended DataArray of VTK type `type`: a UInt64 byte count at its offset
  /// into the raw block, then the values.
  template <typename T>
  std::vector<T> values(const XmlElement& array, std::string_view type) const {
    EXPECT_EQ(array.attribute("type"), type);
    EXPECT_EQ(array.attribute("format"), "appended");
    const std::size_t offset = std::stoull(array.attribute("offset"));
    if (offset + 8 > raw.size()) throw std::runtime_error("offset past the appended block");
    const auto bytes = little_endian<std::uint64_t>(raw.data() + offset);
    if (bytes % sizeof(T) != 0 || offset + 8 + bytes > raw.size()) {
      throw std::runtime_error("bad byte count " + std::to_string(bytes));
    }
    std::vector<T> result(bytes / sizeof(T));
    for (std::size_t i = 0; i < result.size(); ++i) {
      result[i] = little_endian<T>(raw.data() + offset + 8 + i * sizeof(T));
    }
    return result;
  }

  /// The point-data array of that name.
  const XmlElement& point_array(std::string_view name) const {
    for (const XmlElement* array : piece().only("PointData").all("DataArray")) {
      if (array->attribute("Name") == name) return *array;
    }
    throw std::runtime_error("no point array " + std::string(name));
  }
};

/// Reads a .vtp file: finds the raw block after '_', walks its arrays by their byte counts
/// (as many as the XML declares appended arrays), parses the rest as XML and checks that the
/// declared offsets are exactly the arrays' positions in the block, which they fill.
VtpFile read_vtp(const std::filesystem::path& file) {
  const std::string bytes = test::read_bytes(file);
  const std::string open = "<AppendedData encoding=\"raw\">";
  const std::size_t tag = bytes.find(open);
  if (tag == std::string::npos) throw std::runtime_error("no raw appended data");
  std::size_t underscore = tag + open.size();
  while (underscore < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[underscore]))) {
    ++underscore;
  }
  if (underscore >= bytes.size() || bytes[underscore] != '_') {
    throw std::runtime_error("no '_' before the appended data");
  }
  const std::string_view header(bytes.data(), tag);
  std::size_t arrays = 0;
  for (std::size_t at = header.find("format=\"appended\""); at != std::string_view::npos;
       at = header.find("format=\"appended\"", at + 1)) {
    ++arrays;
  }
  const std::size_t start = underscore + 1;
  std::vector<std::size_t> offsets;
  std::size_t end = start;
  for (std::size_t i = 0; i < arrays; ++i) {
    if (end + 8 > bytes.size()) throw std::runtime_error("appended data cut short");
    offsets.push_back(end - start);
    end += 8 + little_endian<std::uint64_t>(bytes.data() + end);
  }
  if (end > bytes.size()) throw std::runtime_error("appended data cut short");
  VtpFile result{parse_xml(bytes.substr(0, underscore) + bytes.substr(end)),
                 bytes.substr(start, end - start)};

  std::vector<std::size_t> declared;
  const auto collect = [&](const XmlElement& parent) {
    for (const XmlElement* array : parent.all("DataArray")) {
      declared.push_back(std::stoull(array->attribute("offset")));
    }
  };
  const XmlElement& piece = result.piece();
  for (const char* section : {"PointData", "Points", "Verts", "Polys"}) {
    for (const XmlElement* element : piece.all(section)) collect(*element);
  }
  std::sort(declared.begin(), declared.end());
  EXPECT_EQ(declared, offsets) << file;
  return result;
}

/// Row after row, as VTK stores tuples.
template <typename Scalar, typename Derived>
std::vector<Scalar> rows_of(const Eigen::MatrixBase<Derived>& values) {
  std::vector<Scalar> result;
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) result.push_back(values(r, c));
  }
  return result;
}

/// Bitwise equality, so that NaN, −0 and denormals count.
::testing::AssertionResult same_bits(const std::vector<double>& actual,
                                     const std::vector<double>& expected) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure()
           << actual.size() << " values, expected " << expected.size();
  }
  for (std::size_t i = 0; i < actual.size(); ++i) {
    if (std::bit_cast<std::uint64_t>(actual[i]) != std::bit_cast<std::uint64_t>(expected[i])) {
      return ::testing::AssertionFailure()
             << "value " << i << " is " << actual[i] << ", expected " << expected[i];
    }
  }
  return ::testing::AssertionSuccess();
}

/// `rows`×3 doubles from a fixed seed, with the awkward values up front: ±0, a denormal, the
/// extremes, ±∞ and NaN.
VertexMatrix awkward_doubles(Eigen::Index rows, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  VertexMatrix values(rows, 3);
  for (Eigen::Index i = 0; i < values.size(); ++i) values.data()[i] = uniform(random);
  const double specials[] = {-0.0,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max(),
                             std::numeric_limits<double>::lowest(),
                             std::numeric_limits<double>::infinity(),
                             std::numeric_limits<double>::quiet_NaN()};
  for (std::size_t i = 0; i < std::size(specials) && static_cast<Eigen::Index>(i) < values.size();
       ++i) {
    values.data()[i] = specials[i];
  }
  return values;
}

/// A closed octahedron: 6 vertices, 8 triangles.
struct Surface {
  VertexMatrix vertices;
  TriangleMatrix triangles;
};

Surface octahedron() {
  Surface s;
  s.vertices.resize(6, 3);
  s.vertices << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  s.triangles.resize(8, 3);
  s.triangles << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
  return s;
}

// ---- .vtp ----

TEST(VtpFile, SurfaceRoundTripsPointsTrianglesAndEveryArrayKindBitForBit) {
  Surface s = octahedron();
  s.vertices = awkward_doubles(6, 1);
  const VertexMatrix displacement = awkward_doubles(6, 2);
  const Eigen::VectorXd temperature = awkward_doubles(2, 3).reshaped<Eigen::RowMajor>();
  Eigen::VectorXi label(6);
  label << -7, 0, 1, std::numeric_limits<int>::max(), std::numeric_limits<int>::min(), 42;
  ByteVector state(6);
  state << 0, 1, 2, 255, 2, 1;
  const auto file = test::scratch_file("surface.vtp");
  write_surface_vtp(file, s.vertices, s.triangles,
                    {{"temperature", temperature},
                     {"displacement", displacement},
                     {"label", label},
                     {"state", state}});

  const VtpFile vtp = read_vtp(file);
  EXPECT_EQ(vtp.root.name, "VTKFile");
  EXPECT_EQ(vtp.root.attribute("type"), "PolyData");
  EXPECT_EQ(vtp.root.attribute("byte_order"), "LittleEndian");
  EXPECT_EQ(vtp.root.attribute("header_type"), "UInt64");
  const XmlElement& piece = vtp.piece();
  EXPECT_EQ(piece.attribute("NumberOfPoints"), "6");
  EXPECT_EQ(piece.attribute("NumberOfPolys"), "8");
  EXPECT_EQ(piece.attribute("NumberOfVerts"), "0");
  EXPECT_TRUE(piece.all("Verts").empty());

  const XmlElement& points = piece.only("Points").only("DataArray");
  EXPECT_EQ(points.attribute("NumberOfComponents"), "3");
  EXPECT_TRUE(same_bits(vtp.values<double>(points, "Float64"), rows_of<double>(s.vertices)));
  const XmlElement& polys = piece.only("Polys");
  ASSERT_EQ(polys.all("DataArray").size(), 2U);
  const XmlElement& connectivity = *polys.all("DataArray")[0];
  const XmlElement& offsets = *polys.all("DataArray")[1];
  EXPECT_EQ(connectivity.attribute("Name"), "connectivity");
  EXPECT_EQ(offsets.attribute("Name"), "offsets");
  EXPECT_EQ(vtp.values<std::int32_t>(connectivity, "Int32"), rows_of<std::int32_t>(s.triangles));
  EXPECT_EQ(vtp.values<std::int32_t>(offsets, "Int32"),
            (std::vector<std::int32_t>{3, 6, 9, 12, 15, 18, 21, 24}));

  // Active arrays: the first of each width.
  const XmlElement& point_data = piece.only("PointData");
  EXPECT_EQ(point_data.attribute("Scalars"), "temperature");
  EXPECT_EQ(point_data.attribute("Vectors"), "displacement");
  ASSERT_EQ(point_data.all("DataArray").size(), 4U);
  const XmlElement& t = vtp.point_array("temperature");
  EXPECT_EQ(t.attribute("NumberOfComponents"), "1");
  EXPECT_TRUE(same_bits(vtp.values<double>(t, "Float64"), rows_of<double>(temperature)));
  const XmlElement& u = vtp.point_array("displacement");
  EXPECT_EQ(u.attribute("NumberOfComponents"), "3");
  EXPECT_TRUE(same_bits(vtp.values<double>(u, "Float64"), rows_of<double>(displacement)));
  EXPECT_EQ(vtp.values<std::int32_t>(vtp.point_array("label"), "Int32"),
            rows_of<std::int32_t>(label));
  EXPECT_EQ(vtp.values<std::uint8_t>(vtp.point_array("state"), "UInt8"),
            rows_of<std::uint8_t>(state));
}

TEST(VtpFile, PointCloudHasOneVertexCellPerPointAndItsArrays) {
  const Eigen::Index n = 1000;
  const VertexMatrix points = awkward_doubles(n, 4);
  const VertexMatrix normals = awkward_doubles(n, 5);
  const VertexMatrix forces = awkward_doubles(n, 6);
  ByteVector state(n);
  for (Eigen::Index i = 0; i < n; ++i) state(i) = static_cast<std::uint8_t>(i % 3);
  const auto file = test::scratch_file("cloud.vtp");
  write_point_cloud_vtp(file, points, {{"state", state}, {"normal", normals}, {"force", forces}});

  const VtpFile vtp = read_vtp(file);
  const XmlElement& piece = vtp.piece();
  EXPECT_EQ(piece.attribute("NumberOfPoints"), "1000");
  EXPECT_EQ(piece.attribute("NumberOfVerts"), "1000");
  EXPECT_EQ(piece.attribute("NumberOfPolys"), "0");
  EXPECT_TRUE(piece.all("Polys").empty());
  EXPECT_TRUE(same_bits(vtp.values<double>(piece.only("Points").only("DataArray"), "Float64"),
                        rows_of<double>(points)));
  const auto verts = piece.only("Verts").all("DataArray");
  ASSERT_EQ(verts.size(), 2U);
  std::vector<std::int32_t> expected_connectivity(n), expected_offsets(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    expected_connectivity[i] = static_cast<std::int32_t>(i);
    expected_offsets[i] = static_cast<std::int32_t>(i + 1);
  }
  EXPECT_EQ(vtp.values<std::int32_t>(*verts[0], "Int32"), expected_connectivity);
  EXPECT_EQ(vtp.values<std::int32_t>(*verts[1], "Int32"), expected_offsets);

  const XmlElement& point_data = piece.only("PointData");
  EXPECT_EQ(point_data.attribute("Scalars"), "state");
  EXPECT_EQ(point_data.attribute("Vectors"), "normal");
  EXPECT_EQ(vtp.values<std::uint8_t>(vtp.point_array("state"), "UInt8"),
            rows_of<std::uint8_t>(state));
  EXPECT_TRUE(same_bits(vtp.values<double>(vtp.point_array("normal"), "Float64"),
                        rows_of<double>(normals)));
  EXPECT_TRUE(
      same_bits(vtp.values<double>(vtp.point_array("force"), "Float64"), rows_of<double>(forces)));
}

TEST(VtpFile, ArrayNamesWithXmlCharactersReadBack) {
  const VertexMatrix points = awkward_doubles(3, 7);
  const std::string name = "contact \"force\" <N> & more";
  const auto file = test::scratch_file("escaped.vtp");
  write_point_cloud_vtp(file, points, {{name, points}});
  const VtpFile vtp = read_vtp(file);
  EXPECT_EQ(vtp.piece().only("PointData").attribute("Vectors"), name);
  EXPECT_TRUE(
      same_bits(vtp.values<double>(vtp.point_array(name), "Float64"), rows_of<double>(points)));
  EXPECT_FALSE(vtp.piece().only("PointData").has_attribute("Scalars"));
}

TEST(VtpFile, EmptyGeometryIsAValidFile) {
  const auto file = test::scratch_file("empty.vtp");
  write_surface_vtp(file, VertexMatrix(0, 3), TriangleMatrix(0, 3));
  const VtpFile vtp = read_vtp(file);
  EXPECT_EQ(vtp.piece().attribute("NumberOfPoints"), "0");
  EXPECT_EQ(vtp.piece().attribute("NumberOfPolys"), "0");
  EXPECT_TRUE(vtp.piece().all("PointData").empty());
  EXPECT_TRUE(vtp.values<double>(vtp.piece().only("Points").only("DataArray"), "Float64").empty());
}

TEST(VtpFile, InconsistentInputThrowsBeforeTheFileIsTouched) {
  const Surface s = octahedron();
  const auto file = test::scratch_file("inconsistent.vtp");
  const std::string earlier = "an earlier frame";
  std::ofstream(file) << earlier;
  const auto surface = [&](const TriangleMatrix& triangles, std::vector<PointArray> arrays) {
    return [&, triangles, arrays] { write_surface_vtp(file, s.vertices, triangles, arrays); };
  };

  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      surface(s.triangles, {{"u", Eigen::VectorXd(5)}}),
      "point array 'u' has 5 rows, but there are 6 points"));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      surface(s.triangles, {{"u", VertexMatrix(7, 3)}}), "'u' has 7 rows"));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      surface(s.triangles, {{"state", ByteVector(6)}, {"state", Eigen::VectorXi(6)}}),
      "'state' has the name of another point array"));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      surface(s.triangles, {{"", Eigen::VectorXd(6)}}), "point array 0 has an empty name"));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      surface(s.triangles, {{"a\tb", Eigen::VectorXd(6)}}), "control character"));

  for (const int bad : {-1, 6}) {
    TriangleMatrix triangles = s.triangles;
    triangles(5, 1) = bad;
    try {
      surface(triangles, {})();
      ADD_FAILURE() << "index " << bad << " accepted";
    } catch (const reduced::MeshError& error) {
      EXPECT_EQ(error.element(), 5);
      EXPECT_NE(
          std::string(error.what())
              .find("triangle 5 has vertex index " + std::to_string(bad) + ", outside [0, 6)"),
          std::string::npos)
          << error.what();
    }
  }
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      [&] {
        write_point_cloud_vtp(file, s.vertices, {{"f", VertexMatrix(2, 3)}});
      },
      file.string() + ": point array 'f' has 2 rows"));

  EXPECT_EQ(test::read_bytes(file), earlier);
}

/// The files in `directory` whose names contain `text`.
std::vector<std::string> files_containing(const std::filesystem::path& directory,
                                          std::string_view text) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    const std::string name = entry.path().filename().string();
    if (name.find(text) != std::string::npos) names.push_back(name);
  }
  return names;
}

TEST(VtpFile, AFailedWriteThrowsIoErrorNamingTheFileAndLeavesNoTemporaryFile) {
  const VertexMatrix points = awkward_doubles(4, 8);
  // A regular file where a directory should be: not writable, even for root.
  const auto blocker = test::scratch_file("not_a_directory");
  std::ofstream(blocker) << "x";
  const auto unreachable = blocker / "frame.vtp";
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [&] { write_point_cloud_vtp(unreachable, points); }, unreachable.string() + ": "));

  // A directory in the file's place: the temporary file is written, the rename fails.
  const auto occupied = test::scratch_file("occupied.vtp");
  std::filesystem::create_directory(occupied);
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [&] { write_point_cloud_vtp(occupied, points); }, occupied.string() + ": cannot rename"));
  EXPECT_TRUE(std::filesystem::is_directory(occupied));
  EXPECT_EQ(files_containing(occupied.parent_path(), "partial"), std::vector<std::string>{});
}

// ---- .pvd ----

/// The DataSet elements of a .pvd file, which must be a well-formed collection.
std::vector<XmlElement> datasets_in(const std::filesystem::path& pvd) {
  const XmlElement root = parse_xml(test::read_bytes(pvd));
  EXPECT_EQ(root.name, "VTKFile");
  EXPECT_EQ(root.attribute("type"), "Collection");
  std::vector<XmlElement> result;
  for (const XmlElement* dataset : root.only("Collection").all("DataSet")) {
    result.push_back(*dataset);
  }
  return result;
}

TEST(PvdCollection, ListsEveryDatasetInOrderWithItsTimeAndPartAfterEachAdd) {
  const auto directory = test::scratch_directory("run_output");
  PvdCollection collection(directory, "run");
  EXPECT_EQ(collection.file(), directory / "run.pvd");
  EXPECT_TRUE(datasets_in(collection.file()).empty());

  const Surface s = octahedron();
  // Times that print with many digits must still read back as the same doubles.
  const double times[] = {0.0, 0.1, 1.0 / 3.0, 2.5e-3 + 1.0, 7.0};
  struct Expected {
    double time;
    std::string part;
    std::string file;
  };
  std::vector<Expected> expected;
  for (int step = 0; step < 5; ++step) {
    for (const std::string part : {"dino", "points"}) {
      if (part == "points" && step == 2) continue;  // a part may skip a time step
      const PvdEntry& entry =
          collection.add(times[step], part, [&](const std::filesystem::path& file) {
            VertexMatrix moved = s.vertices.array() + step;
            write_surface_vtp(file, moved, s.triangles);
          });
      const int index = part == "dino" ? step : step - (step > 2 ? 1 : 0);
      char name[32];
      std::snprintf(name, sizeof name, "run/%s_%06d.vtp", part.c_str(), index);
      expected.push_back({times[step], part, name});
      EXPECT_EQ(entry.file.generic_string(), name);

      // The collection on disk lists everything added so far, in order.
      const std::vector<XmlElement> datasets = datasets_in(collection.file());
      ASSERT_EQ(datasets.size(), expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i) {
        SCOPED_TRACE(i);
        const double time = std::strtod(datasets[i].attribute("timestep").c_str(), nullptr);
        EXPECT_EQ(std::bit_cast<std::uint64_t>(time),
                  std::bit_cast<std::uint64_t>(expected[i].time));
        EXPECT_EQ(datasets[i].attribute("part"), expected[i].part);
        EXPECT_EQ(datasets[i].attribute("name"), expected[i].part);
        EXPECT_EQ(datasets[i].attribute("file"), expected[i].file);
      }
    }
  }
  ASSERT_EQ(collection.entries().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(collection.entries()[i].time, expected[i].time);
    EXPECT_EQ(collection.entries()[i].part, expected[i].part);
    // Each listed file is the frame written for it.
    const VtpFile vtp = read_vtp(directory / expected[i].file);
    const auto points = vtp.values<double>(vtp.piece().only("Points").only("DataArray"), "Float64");
    const int step = static_cast<int>(
        std::find(std::begin(times), std::end(times), expected[i].time) - std::begin(times));
    EXPECT_EQ(points.front(), s.vertices(0, 0) + step) << expected[i].file;
  }
  EXPECT_EQ(files_containing(directory, "partial"), std::vector<std::string>{});
}

TEST(PvdCollection, RejectsBadTimesBeforeWritingAndStaysAsItWas) {
  PvdCollection collection(test::scratch_directory("bad_times"), "run");
  int writes = 0;
  const auto count_write = [&](const std::filesystem::path&) { ++writes; };
  collection.add(1.0, "dino", count_write);
  collection.add(1.0, "points", count_write);  // another part at the same time
  const std::string before = test::read_bytes(collection.file());

  const auto rejected = [&](double time, const char* part, const std::string& message) {
    EXPECT_TRUE(test::throws_with_message<reduced::Error>(
        [&] { collection.add(time, part, count_write); }, message));
  };
  const std::string pvd = collection.file().string() + ": ";
  rejected(std::numeric_limits<double>::quiet_NaN(), "dino", pvd + "dataset of part 'dino'");
  rejected(std::numeric_limits<double>::quiet_NaN(), "dino", "the time is not finite");
  rejected(std::numeric_limits<double>::infinity(), "forces", "the time is not finite");
  rejected(-std::numeric_limits<double>::infinity(), "forces", "the time is not finite");
  rejected(0.5, "forces", "at time 0.5 s is earlier than the previous dataset (1 s)");
  rejected(1.0, "dino", "is not later than the part's previous dataset (1 s)");
  EXPECT_EQ(writes, 2);
  EXPECT_EQ(collection.entries().size(), 2U);
  EXPECT_EQ(test::read_bytes(collection.file()), before);

  // Still usable; the part's numbering goes on.
  EXPECT_EQ(collection.add(1.5, "dino", count_write).file.generic_string(), "run/dino_000001.vtp");
  EXPECT_EQ(datasets_in(collection.file()).size(), 3U);
}

TEST(PvdCollection, RejectsNamesThatAreNotPlainFileNames) {
  const auto directory = test::scratch_directory("bad_names");
  for (const char* name : {"", ".hidden", "a/b", "../up", "with space", "quote\""}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(test::throws_with_message<reduced::Error>(
        [&] { (void)PvdCollection(directory, name); }, "is not a name of letters, digits"));
  }
  PvdCollection collection(directory, "run-1.final_2");
  int writes = 0;
  for (const char* part : {"", ".x", "dino/leg", "a&b"}) {
    SCOPED_TRACE(part);
    EXPECT_TRUE(test::throws_with_message<reduced::Error>(
        [&] { collection.add(0.0, part, [&](const std::filesystem::path&) { ++writes; }); },
        "part name '" + std::string(part) + "' is not a name"));
  }
  EXPECT_EQ(writes, 0);
  EXPECT_TRUE(datasets_in(collection.file()).empty());
}

TEST(PvdCollection, AFailedDatasetWriteRecordsNothing) {
  PvdCollection collection(test::scratch_directory("failed_dataset"), "run");
  const std::string before = test::read_bytes(collection.file());
  EXPECT_THROW(collection.add(0.0, "dino",
                              [](const std::filesystem::path& file) {
                                throw reduced::IoError(file.string() + ": disk full");
                              }),
               reduced::IoError);
  EXPECT_TRUE(collection.entries().empty());
  EXPECT_EQ(test::read_bytes(collection.file()), before);
  // The same time and the same file name are still free.
  EXPECT_EQ(collection.add(0.0, "dino", [](const std::filesystem::path&) {}).file.generic_string(),
            "run/dino_000000.vtp");
}

TEST(PvdCollection, AFailedCollectionWriteThrowsIoErrorNamingItAndUndoesTheAdd) {
  const auto directory = test::scratch_directory("failed_collection");
  PvdCollection collection(directory, "run");
  const auto nothing = [](const std::filesystem::path&) {};
  collection.add(0.0, "dino", nothing);
  // A directory in the collection's place makes the rename fail.
  std::filesystem::remove(collection.file());
  std::filesystem::create_directory(collection.file());
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [&] { collection.add(1.0, "dino", nothing); }, collection.file().string() + ": "));
  EXPECT_EQ(collection.entries().size(), 1U);
  EXPECT_EQ(files_containing(directory, "partial"), std::vector<std::string>{});

  std::filesystem::remove(collection.file());
  EXPECT_EQ(collection.add(1.0, "dino", nothing).file.generic_string(), "run/dino_000001.vtp");
  EXPECT_EQ(datasets_in(collection.file()).size(), 2U);
}

TEST(PvdCollection, AnUnwritableDirectoryThrowsIoErrorNamingIt) {
  const auto blocker = test::scratch_file("not_a_directory");
  std::ofstream(blocker) << "x";
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [&] { (void)PvdCollection(blocker / "out", "run"); }, (blocker / "out" / "run").string()));
}

TEST(PvdCollection, StartsEmptyOverAnEarlierRunsCollection) {
  const auto directory = test::scratch_directory("rerun");
  {
    PvdCollection first(directory, "run");
    first.add(0.0, "dino", [](const std::filesystem::path&) {});
    ASSERT_EQ(datasets_in(first.file()).size(), 1U);
  }
  const PvdCollection second(directory, "run");
  EXPECT_TRUE(datasets_in(second.file()).empty());
  EXPECT_TRUE(second.entries().empty());
}

}  // namespace
}  // namespace khz::series
