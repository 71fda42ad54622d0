#include <khz/series/vtp_file.hpp>

#include <khz/reduced/errors.hpp>

#include "detail/number_text.hpp"
#include "detail/xml_text.hpp"
#include "file_replacement.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace khz::series {
namespace {

using reduced::detail::xml_escaped;

static_assert(sizeof(int) == sizeof(std::int32_t), "int arrays are written as VTK Int32");

/// Writes arithmetic values little-endian, whatever the host's byte order, through a buffer.
class LittleEndianWriter {
 public:
  explicit LittleEndianWriter(std::ostream& out) : m_out(out) { m_buffer.reserve(buffer_size); }

  template <typename T>
  void put(T value) {
    reduced::detail::append_binary(m_buffer, value, reduced::detail::Endian::little);
    if (m_buffer.size() >= buffer_size) flush();
  }
  void flush() {
    m_out.write(m_buffer.data(), static_cast<std::streamsize>(m_buffer.size()));
    m_buffer.clear();
  }

 private:
  static constexpr std::size_t buffer_size = std::size_t{1} << 16;
  std::ostream& m_out;
  std::string m_buffer;
};

template <typename T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) {
    return "Float64";
  } else if constexpr (std::is_same_v<T, std::int32_t>) {
    return "Int32";
  } else {
    static_assert(std::is_same_v<T, std::uint8_t>, "no VTK type for this scalar");
    return "UInt8";
  }
}

/// One DataArray of the file: declared in the XML with its offset into the appended block,
/// where it is a UInt64 byte count followed by the values.
struct AppendedArray {
  std::string name;  // empty for the Points array, which has no name
  const char* type;
  Eigen::Index components;
  std::uint64_t bytes;
  std::function<void(LittleEndianWriter&)> write_values;
};

/// The rows of `values` (not copied: it must outlive the write), row after row.
template <typename Derived>
AppendedArray matrix_array(std::string name, const Eigen::DenseBase<Derived>& values) {
  using Scalar = typename Derived::Scalar;
  const Derived& matrix = values.derived();
  return {std::move(name), vtk_type_name<Scalar>(), matrix.cols(),
          static_cast<std::uint64_t>(matrix.size()) * sizeof(Scalar),
          [&matrix](LittleEndianWriter& out) {
            for (Eigen::Index r = 0; r < matrix.rows(); ++r) {
              for (Eigen::Index c = 0; c < matrix.cols(); ++c) out.put<Scalar>(matrix(r, c));
            }
          }};
}

/// The Int32 values first, first + step, …, first + (count − 1)·step: vertex cells'
/// connectivity (first 0, step 1) or cells' offsets (their ends: first = step = cell size).
AppendedArray int_sequence(std::string name, Eigen::Index count, std::int32_t first,
                           std::int32_t step) {
  return {std::move(name), "Int32", 1, static_cast<std::uint64_t>(count) * sizeof(std::int32_t),
          [=](LittleEndianWriter& out) {
            for (Eigen::Index i = 0; i < count; ++i) {
              out.put(static_cast<std::int32_t>(first + static_cast<std::int32_t>(i) * step));
            }
          }};
}

/// The cells of a PolyData file we write: all vertices or all triangles.
enum class CellKind { vertex, triangle };

/// The one piece of a PolyData file: points, one kind of cells and point data.
struct PolyPiece {
  Eigen::Index points;
  CellKind cell_kind;
  Eigen::Index cells;
  std::vector<AppendedArray> point_data;
  AppendedArray coordinates;
  AppendedArray connectivity;
  AppendedArray offsets;
};

/// Rejects what VTK cannot read back: wrong row counts, unusable or repeated names.
void check_point_data(const std::filesystem::path& file, const std::vector<PointArray>& arrays,
                      Eigen::Index points) {
  for (std::size_t i = 0; i < arrays.size(); ++i) {
    const std::string& name = arrays[i].name;
    const std::string what = file.string() + ": point array '" + name + "'";
    if (name.empty()) {
      throw reduced::Error(file.string() + ": point array " + std::to_string(i) +
                           " has an empty name");
    }
    // XML 1.0 has no way to write most control characters, even escaped.
    if (std::any_of(name.begin(), name.end(), [](unsigned char c) { return c < ' '; })) {
      throw reduced::Error(what + " has a control character in its name");
    }
    const Eigen::Index rows = std::visit([](const auto& v) { return v.rows(); }, arrays[i].values);
    if (rows != points) {
      throw reduced::Error(what + " has " + std::to_string(rows) + " rows, but there are " +
                           std::to_string(points) + " points");
    }
    const auto same_name = [&](const PointArray& other) { return other.name == name; };
    if (std::any_of(arrays.begin(), arrays.begin() + static_cast<std::ptrdiff_t>(i), same_name)) {
      throw reduced::Error(what + " has the name of another point array");
    }
  }
}

/// Int32 connectivity and offsets hold values up to `largest`.
void check_int32_range(const std::filesystem::path& file, Eigen::Index largest,
                       const std::string& what) {
  if (largest > std::numeric_limits<std::int32_t>::max()) {
    throw reduced::Error(file.string() + ": " + what + " exceed the Int32 range of the file");
  }
}

std::vector<AppendedArray> point_data_arrays(const std::vector<PointArray>& arrays) {
  std::vector<AppendedArray> result;
  for (const PointArray& array : arrays) {
    result.push_back(std::visit(
        [&](const auto& values) { return matrix_array(array.name, values); }, array.values));
  }
  return result;
}

/// Declares `array` at `offset` into the appended block; returns the offset of the next one.
std::uint64_t declare(std::ostream& out, const AppendedArray& array, std::uint64_t offset) {
  out << "        <DataArray type=\"" << array.type << '"';
  if (!array.name.empty()) out << " Name=\"" << xml_escaped(array.name) << '"';
  out << " NumberOfComponents=\"" << array.components << '"';
  out << " format=\"appended\" offset=\"" << offset << "\"/>\n";
  return offset + sizeof(std::uint64_t) + array.bytes;
}

/// The first array of `components` components, as the value of an active-attribute attribute.
void declare_active(std::ostream& out, const char* attribute,
                    const std::vector<AppendedArray>& arrays, Eigen::Index components) {
  const auto active = std::find_if(arrays.begin(), arrays.end(), [&](const AppendedArray& a) {
    return a.components == components;
  });
  if (active != arrays.end()) out << ' ' << attribute << "=\"" << xml_escaped(active->name) << '"';
}

void write_piece(std::ostream& out, const PolyPiece& piece) {
  const bool verts = piece.cell_kind == CellKind::vertex;
  const char* const cell_section = verts ? "Verts" : "Polys";
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n"
         "  <PolyData>\n"
      << "    <Piece NumberOfPoints=\"" << piece.points << "\" NumberOfVerts=\""
      << (verts ? piece.cells : 0) << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\""
      << (verts ? 0 : piece.cells) << "\">\n";
  std::uint64_t offset = 0;
  if (!piece.point_data.empty()) {
    out << "      <PointData";
    declare_active(out, "Scalars", piece.point_data, 1);
    declare_active(out, "Vectors", piece.point_data, 3);
    out << ">\n";
    for (const AppendedArray& array : piece.point_data) offset = declare(out, array, offset);
    out << "      </PointData>\n";
  }
  out << "      <Points>\n";
  offset = declare(out, piece.coordinates, offset);
  out << "      </Points>\n      <" << cell_section << ">\n";
  offset = declare(out, piece.connectivity, offset);
  declare(out, piece.offsets, offset);
  out << "      </" << cell_section << ">\n    </Piece>\n  </PolyData>\n"
      << "  <AppendedData encoding=\"raw\">\n   _";

  LittleEndianWriter data(out);
  const auto append = [&](const AppendedArray& array) {
    data.put(array.bytes);
    array.write_values(data);
  };
  std::for_each(piece.point_data.begin(), piece.point_data.end(), append);
  append(piece.coordinates);
  append(piece.connectivity);
  append(piece.offsets);
  data.flush();
  out << "\n  </AppendedData>\n</VTKFile>\n";
}

void write_polydata(const std::filesystem::path& file, const PolyPiece& piece) {
  detail::replace_file(file, [&](std::ostream& out) { write_piece(out, piece); });
}

}  // namespace

void write_surface_vtp(const std::filesystem::path& file,
                       const Eigen::Ref<const reduced::VertexMatrix>& vertices,
                       const Eigen::Ref<const reduced::TriangleMatrix>& triangles,
                       const std::vector<PointArray>& point_data) {
  const Eigen::Index count = vertices.rows();
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      const int index = triangles(t, k);
      if (index < 0 || index >= count) {
        throw reduced::MeshError(file.string() + ": triangle " + std::to_string(t) +
                                     " has vertex index " + std::to_string(index) +
                                     ", outside [0, " + std::to_string(count) + ")",
                                 t);
      }
    }
  }
  check_point_data(file, point_data, count);
  check_int32_range(file, 3 * triangles.rows(), "the triangles' offsets");
  AppendedArray connectivity = matrix_array("connectivity", triangles);
  connectivity.components = 1;  // one flat list of indices, three per triangle
  write_polydata(file, {count, CellKind::triangle, triangles.rows(), point_data_arrays(point_data),
                        matrix_array("", vertices), std::move(connectivity),
                        int_sequence("offsets", triangles.rows(), 3, 3)});
}

void write_point_cloud_vtp(const std::filesystem::path& file,
                           const Eigen::Ref<const reduced::VertexMatrix>& points,
                           const std::vector<PointArray>& point_data) {
  const Eigen::Index count = points.rows();
  check_point_data(file, point_data, count);
  check_int32_range(file, count, "the points' vertex cells");
  write_polydata(file, {count, CellKind::vertex, count, point_data_arrays(point_data),
                        matrix_array("", points), int_sequence("connectivity", count, 0, 1),
                        int_sequence("offsets", count, 1, 1)});
}

}  // namespace khz::series
