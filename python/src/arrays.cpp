// Checked conversions between NumPy arrays and the libraries' Eigen matrices.

#include "arrays.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

namespace khz::python {

using namespace pybind11::literals;

namespace {

std::string shape_of(const py::array& array) {
  std::ostringstream text;
  text << '(';
  for (py::ssize_t axis = 0; axis < array.ndim(); ++axis) {
    text << (axis ? ", " : "") << array.shape(axis);
  }
  text << (array.ndim() == 1 ? ",)" : ")");
  return text.str();
}

/// `input` as a NumPy array whose dtype kind is one of `kinds` ('f' float, 'i'/'u' integer).
py::array numeric_array(const py::handle& input, std::string_view what, std::string_view kinds,
                        std::string_view expected) {
  const auto array = py::array::ensure(input);
  if (!array) {
    throw py::type_error(std::string(what) + ": expected " + std::string(expected) + ", got " +
                         std::string(py::str(py::type::handle_of(input).attr("__name__"))));
  }
  const char kind = array.dtype().kind();
  if (kinds.find(kind) == std::string_view::npos) {
    throw py::type_error(std::string(what) + ": expected " + std::string(expected) +
                         ", got dtype " + std::string(py::str(array.dtype())));
  }
  return array;
}

void check_finite(const double* values, Eigen::Index rows, Eigen::Index columns,
                  std::string_view what) {
  for (Eigen::Index row = 0; row < rows; ++row) {
    for (Eigen::Index column = 0; column < columns; ++column) {
      if (!std::isfinite(values[row * columns + column])) {
        throw py::value_error(std::string(what) + ": row " + std::to_string(row) +
                              " is not finite (" + std::to_string(values[row * columns + column]) +
                              ")");
      }
    }
  }
}

}  // namespace

PointRows point_rows(const py::handle& input, std::string_view what) {
  const auto array = numeric_array(input, what, "fiu", "an (N, 3) array of real numbers");
  const bool single = array.ndim() == 1 && array.shape(0) == 3;
  if (!single && !(array.ndim() == 2 && array.shape(1) == 3)) {
    throw py::value_error(std::string(what) + ": expected shape (N, 3) or (3,), got " +
                          shape_of(array));
  }
  PointRows points;
  points.array = py::array_t<double, py::array::c_style>::ensure(array);
  points.single = single;
  points.count = single ? 1 : array.shape(0);
  check_finite(points.array.data(), points.count, 3, what);
  return points;
}

Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> real_matrix(
    const py::handle& input, std::string_view what, Eigen::Index rows, Eigen::Index columns) {
  const auto array = numeric_array(input, what, "fiu", "an array of real numbers");
  if (array.ndim() != 2 || array.shape(1) != columns || (rows >= 0 && array.shape(0) != rows)) {
    throw py::value_error(std::string(what) + ": expected shape (" +
                          (rows >= 0 ? std::to_string(rows) : std::string("N")) + ", " +
                          std::to_string(columns) + "), got " + shape_of(array));
  }
  const auto contiguous = py::array_t<double, py::array::c_style>::ensure(array);
  check_finite(contiguous.data(), array.shape(0), columns, what);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      contiguous.data(), array.shape(0), columns);
}

Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> index_matrix(
    const py::handle& input, std::string_view what, Eigen::Index columns) {
  const auto array = numeric_array(
      input, what, "iu", "an (N, " + std::to_string(columns) + ") array of integer indices");
  if (array.ndim() != 2 || array.shape(1) != columns) {
    throw py::value_error(std::string(what) + ": expected shape (N, " + std::to_string(columns) +
                          "), got " + shape_of(array));
  }
  const auto wide =
      py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(array);
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> indices(array.shape(0),
                                                                              columns);
  const std::int64_t* values = wide.data();
  for (Eigen::Index i = 0; i < indices.size(); ++i) {
    if (values[i] < std::numeric_limits<int>::min() ||
        values[i] > std::numeric_limits<int>::max()) {
      throw py::value_error(std::string(what) + ": row " + std::to_string(i / columns) + " holds " +
                            std::to_string(values[i]) + ", outside int32");
    }
    indices.data()[i] = static_cast<int>(values[i]);
  }
  return indices;
}

Eigen::Vector3d vector3_in(const py::handle& input, std::string_view what) {
  const PointRows point = point_rows(input, what);
  if (!point.single) throw py::value_error(std::string(what) + ": expected shape (3,)");
  return point.rows().row(0).transpose();
}

Eigen::Quaterniond quaternion_in(const py::handle& input, std::string_view what) {
  const auto wxyz = real_matrix(py::array::ensure(input).attr("reshape")(1, -1), what, 1, 4);
  const Eigen::Quaterniond q(wxyz(0, 0), wxyz(0, 1), wxyz(0, 2), wxyz(0, 3));
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    throw py::value_error(std::string(what) + ": expected a unit quaternion (w, x, y, z), norm " +
                          std::to_string(q.norm()));
  }
  return q.normalized();
}

py::array quaternion_out(const Eigen::Quaterniond& q) {
  const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
  return py::array_t<double>(4, wxyz);
}

Eigen::VectorXd real_vector(const py::handle& input, std::string_view what, Eigen::Index size) {
  const auto array = numeric_array(input, what, "fiu", "a vector of real numbers");
  const bool flat = array.ndim() == 1 && (size < 0 || array.shape(0) == size);
  const bool rows =
      array.ndim() == 2 && array.shape(1) == 3 && (size < 0 || array.shape(0) * 3 == size);
  if (!flat && !rows) {
    const std::string n = size < 0 ? std::string("n") : std::to_string(size);
    throw py::value_error(
        std::string(what) + ": expected shape (" + n + ",)" +
        (size < 0 || size % 3 == 0
             ? " or (" + (size < 0 ? std::string("n") : std::to_string(size / 3)) + ", 3)"
             : std::string()) +
        ", got " + shape_of(array));
  }
  const auto contiguous = py::array_t<double, py::array::c_style>::ensure(array);
  const auto count = static_cast<Eigen::Index>(contiguous.size());
  check_finite(contiguous.data(), count, 1, what);
  return Eigen::Map<const Eigen::VectorXd>(contiguous.data(), count);
}

std::vector<int> index_list(const py::handle& input, std::string_view what) {
  const auto column = index_matrix(py::array::ensure(input).attr("reshape")(-1, 1), what, 1);
  return {column.data(), column.data() + column.size()};
}

py::object sparse_out(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& matrix) {
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> compressed = matrix;
  compressed.makeCompressed();
  const auto nonzeros = static_cast<py::ssize_t>(compressed.nonZeros());
  py::array_t<double> data(nonzeros, compressed.valuePtr());
  py::array_t<int> indices(nonzeros, compressed.innerIndexPtr());
  py::array_t<int> indptr(compressed.cols() + 1, compressed.outerIndexPtr());
  const py::tuple shape = py::make_tuple(compressed.rows(), compressed.cols());
  try {
    const py::module_ sparse = py::module_::import("scipy.sparse");
    return sparse.attr("csc_matrix")(py::make_tuple(data, indices, indptr), "shape"_a = shape);
  } catch (py::error_already_set& error) {
    if (!error.matches(PyExc_ImportError)) throw;
    return py::make_tuple(data, indices, indptr, shape);
  }
}

py::array vector_out(const Eigen::Ref<const Eigen::VectorXd>& vector) {
  return py::array_t<double>(vector.size(), vector.data());
}

}  // namespace khz::python
