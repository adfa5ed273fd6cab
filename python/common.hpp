// What the binding files share: NumPy conversion with checks at the boundary (a wrong dtype is a
// TypeError, a wrong shape a ValueError naming the argument; nothing reaches the algorithms
// unchecked), datasets given as a path or as a Dataset, and the per-file registration functions.
#pragma once

#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>

#include "core/model.hpp"
#include "core/trajectory.hpp"

namespace dynid::python {

namespace py = pybind11;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using DoubleArray = py::array_t<double, py::array::c_style>;

/// `value` as a C-contiguous float64 array (a copy only when needed). Throws TypeError naming
/// `name` for None or anything that is not an array of real numbers (complex, object, text, bool),
/// ValueError when its number of dimensions is not one of `ndims`.
DoubleArray realArray(const py::handle& value, const char* name, std::vector<int> ndims);

/// A 1-D array of exactly n entries (ValueError otherwise).
Eigen::VectorXd vectorArg(const py::handle& value, const char* name, Eigen::Index n);

/// Shape as text, "(3, 6)".
std::string shapeText(const py::array& a);

/// A NumPy copy of an Eigen vector or matrix (row-major layout, the matrix's own shape).
py::array_t<double> toNumpy(const Eigen::VectorXd& v);
py::array_t<double> toNumpy(const Eigen::MatrixXd& m);

/// A dataset argument: a str or os.PathLike names a dynid CSV (read by the C++ side, streamed
/// where the pipeline streams), a Dataset holds arrays in memory.
struct DataArg {
  std::string path;                    // the file, or "<arrays>" for a Dataset
  const Trajectory* arrays = nullptr;  // the Dataset's samples (owned by the Python object)
};
/// Reads `value` as a DataArg; TypeError for anything else. A Dataset's joint count must be the
/// model's (ValueError).
DataArg dataArg(const py::handle& value, const char* name, const Model& model);
/// A `threads` argument: 0 (all cores) to ThreadPool::kMaxThreads; ValueError otherwise.
void checkThreads(int threads);
/// os.fspath(value) for str and os.PathLike, TypeError otherwise.
std::string pathArg(const py::handle& value, const char* name);
/// Drive terms as "fv,fc,fo" or a list or tuple of names (["fv", "fc"]); TypeError otherwise,
/// ValueError (InputError) for an unknown name.
DriveTerms driveTermsArg(const py::handle& value, const char* name);

// Registration, one function per file.
void bindModel(py::module_& m);
void bindDynamics(py::module_& m);
void bindIdentification(py::module_& m);
void bindSearch(py::module_& m);

}  // namespace dynid::python
