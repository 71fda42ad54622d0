#pragma once
// NumPy arrays in and out: inputs checked for shape, dtype and finiteness with messages that
// name the argument; outputs as views of C++ memory where its layout allows.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <string_view>
#include <vector>

namespace khz::python {

namespace py = pybind11;

/// Rows of three coordinates read from an N×3 array-like (or one 3-vector), without a copy when
/// the input is already a C-contiguous float64 array.
struct PointRows {
  py::array_t<double, py::array::c_style> array;  ///< Owns (or borrows) the coordinates.
  Eigen::Index count = 0;                         ///< N, the number of points.
  bool single = false;  ///< Given as one 3-vector: results drop the leading axis.

  /// The N×3 coordinates (m).
  Eigen::Map<const reduced::VertexMatrix> rows() const { return {array.data(), count, 3}; }
};

/// The points of `input`: a NumPy array or nested sequence of real numbers (float or integer
/// dtype) of shape (N, 3) or (3,).
/// @throws TypeError for a non-numeric or complex dtype; ValueError for another shape or a
///         non-finite value, naming `what`, the shape and the first bad row.
PointRows point_rows(const py::handle& input, std::string_view what);

/// `input` as a float64 C-contiguous array of shape (rows, columns) (rows = -1: any), copied
/// into a row-major Eigen matrix; checks as point_rows(), for any column count.
Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> real_matrix(
    const py::handle& input, std::string_view what, Eigen::Index rows, Eigen::Index columns);

/// `input`, an integer array of shape (N, columns), as row-major int32 (the libraries' index
/// type).
/// @throws TypeError for a non-integer dtype; ValueError for another shape or a value outside
///         int32.
Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> index_matrix(
    const py::handle& input, std::string_view what, Eigen::Index columns);

/// One 3-vector (m, N, ...) from a (3,) array-like; checks as point_rows().
Eigen::Vector3d vector3_in(const py::handle& input, std::string_view what);

/// A unit quaternion from a (4,) array-like (w, x, y, z), normalised.
/// @throws ValueError, naming `what`, for another shape or a norm further than 1e-3 from 1.
Eigen::Quaterniond quaternion_in(const py::handle& input, std::string_view what);

/// A quaternion as a (4,) array (w, x, y, z).
py::array quaternion_out(const Eigen::Quaterniond& q);

/// `input` as a float64 vector of `size` entries (size = -1: any), given as (size,) or, for a
/// vector of per-vertex 3-vectors, as (size / 3, 3); checks as point_rows().
Eigen::VectorXd real_vector(const py::handle& input, std::string_view what, Eigen::Index size);

/// `input` as a list of int (e.g. vertex indices), from any 1-D integer array-like.
std::vector<int> index_list(const py::handle& input, std::string_view what);

/// A sparse matrix as scipy.sparse.csc_matrix when SciPy is importable, else the tuple (data,
/// indices, indptr, shape) of its compressed-column arrays (copies).
py::object sparse_out(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& matrix);

/// A NumPy array holding a copy of the vector `vector`.
py::array vector_out(const Eigen::Ref<const Eigen::VectorXd>& vector);

/// A NumPy view of the row-major matrix `matrix`, kept alive by `owner` (the Python object that
/// holds it); read-only unless `writeable`.
template <typename Matrix>
py::array view_of(Matrix& matrix, const py::handle& owner, bool writeable) {
  using Scalar = typename Matrix::Scalar;
  static_assert(Matrix::IsRowMajor || Matrix::ColsAtCompileTime == 1);
  const auto item = static_cast<py::ssize_t>(sizeof(Scalar));
  py::array view;
  if constexpr (Matrix::ColsAtCompileTime == 1) {
    view = py::array_t<Scalar>({static_cast<py::ssize_t>(matrix.rows())}, {item}, matrix.data(),
                               owner);
  } else {
    view = py::array_t<Scalar>(
        {static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())},
        {item * static_cast<py::ssize_t>(matrix.cols()), item}, matrix.data(), owner);
  }
  if (!writeable) view.attr("flags").attr("writeable") = false;
  return view;
}

/// A NumPy array holding a copy of the row-major matrix `matrix` (for results that outlive it).
template <typename Matrix>
py::array copy_of(const Matrix& matrix) {
  using Scalar = typename Matrix::Scalar;
  static_assert(Matrix::IsRowMajor || Matrix::ColsAtCompileTime == 1);
  if constexpr (Matrix::ColsAtCompileTime == 1) {
    return py::array_t<Scalar>(static_cast<py::ssize_t>(matrix.rows()), matrix.data());
  } else {
    return py::array_t<Scalar>(
        {static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())},
        matrix.data());
  }
}

}  // namespace khz::python
