// What the binding files share: NumPy conversion with checks at the boundary (a wrong dtype is a
// TypeError, a wrong shape a ValueError naming the argument; nothing reaches the algorithms
// unchecked), datasets given as a path or as a Dataset, and the per-file registration functions.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>

#include "analysis/estimation/training_rows.hpp"
#include "core/floating/floating_model.hpp"
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
/// identify's `torque_filter`: "auto" (std::nullopt: the prepare.json beside a data file), "none"
/// (order 0), a cutoff [Hz] (order 4) or (cutoff, order); ValueError otherwise.
TorqueFilterChoice torqueFilterArg(const py::handle& value);

/// An argument the binding reads itself (realArray, pathArg, dataArg, ...): any Python object,
/// held as it came, shown in signatures, docstrings and the .pyi stubs as the types it accepts
/// (Tag::name) rather than as pybind11's "handle".
template <typename Tag>
struct Typed : py::object {
  Typed() = default;
  Typed(py::handle h, borrowed_t b) : py::object(h, b) {}
  Typed(py::handle h, stolen_t s) : py::object(h, s) {}
  static bool check_(py::handle) { return true; }  // pybind11's caster: every object loads
};
/// A tag naming a Typed argument's accepted types (typing syntax that stubgen and mypy read).
#define DYNID_PYTHON_TYPE_NAME(Tag, text)                      \
  struct Tag {                                                 \
    static constexpr auto name = py::detail::const_name(text); \
  }
DYNID_PYTHON_TYPE_NAME(ArrayTag, "numpy.typing.ArrayLike");
DYNID_PYTHON_TYPE_NAME(OptionalArrayTag, "typing.Optional[numpy.typing.ArrayLike]");
DYNID_PYTHON_TYPE_NAME(PathTag, "typing.Union[str, os.PathLike[str]]");
DYNID_PYTHON_TYPE_NAME(OptionalPathTag, "typing.Optional[typing.Union[str, os.PathLike[str]]]");
DYNID_PYTHON_TYPE_NAME(PathsTag,
                       "typing.Optional[typing.Sequence[typing.Union[str, os.PathLike[str]]]]");
DYNID_PYTHON_TYPE_NAME(DataTag, "typing.Union[Dataset, str, os.PathLike[str]]");
DYNID_PYTHON_TYPE_NAME(TrainingTag, "typing.Union[Dataset, Summary, str, os.PathLike[str]]");
DYNID_PYTHON_TYPE_NAME(OptionalDataTag,
                       "typing.Optional[typing.Union[Dataset, str, os.PathLike[str]]]");
DYNID_PYTHON_TYPE_NAME(TermsTag, "typing.Union[str, typing.Sequence[str], None]");
DYNID_PYTHON_TYPE_NAME(OptionalFloatTag, "typing.Optional[float]");
DYNID_PYTHON_TYPE_NAME(PriorTag,
                       "typing.Union[str, os.PathLike[str], numpy.typing.ArrayLike, None]");
DYNID_PYTHON_TYPE_NAME(FrequencyTag, "typing.Union[float, str, None]");
DYNID_PYTHON_TYPE_NAME(
    TablesTag,
    "typing.Union[str, os.PathLike[str], typing.Sequence[typing.Union[str, os.PathLike[str]]], "
    "None]");
DYNID_PYTHON_TYPE_NAME(
    ProgressTag,
    "typing.Optional[typing.Callable[[typing.Dict[str, typing.Any]], typing.Optional[bool]]]");
DYNID_PYTHON_TYPE_NAME(TorqueFilterTag, "typing.Union[str, float, typing.Tuple[float, int]]");
DYNID_PYTHON_TYPE_NAME(FleetRobotsTag,
                       "typing.Mapping[str, typing.Union[Summary, str, os.PathLike[str], "
                       "typing.Sequence[typing.Union[str, os.PathLike[str]]]]]");
DYNID_PYTHON_TYPE_NAME(ClientTag, "typing.Optional[typing.Any]");  // a distributed.Client
DYNID_PYTHON_TYPE_NAME(StartTag, "typing.Union[Search, Estimate, str, os.PathLike[str]]");
DYNID_PYTHON_TYPE_NAME(
    SoleTag,
    "typing.Union[typing.Tuple[float, float], "
    "typing.Sequence[typing.Tuple[float, float]], numpy.typing.ArrayLike, None]");
#undef DYNID_PYTHON_TYPE_NAME
using ArrayLike = Typed<ArrayTag>;                  // a NumPy array or anything np.asarray takes
using OptionalArrayLike = Typed<OptionalArrayTag>;  // ... or None
using PathLike = Typed<PathTag>;                    // str or os.PathLike
using OptionalPathLike = Typed<OptionalPathTag>;    // ... or None
using PathsLike = Typed<PathsTag>;                  // a list of paths, or None
using DataLike = Typed<DataTag>;                    // a Dataset or a dataset CSV's path
using OptionalDataLike = Typed<OptionalDataTag>;    // ... or None
using TrainingLike = Typed<TrainingTag>;            // ... or a Summary (identify's data)
using SoleLike = Typed<SoleTag>;                  // (length, width), corners [(x, y), ...], or None
using TermsLike = Typed<TermsTag>;                // driveTermsArg's "fv,fc" or ["fv", "fc"]
using OptionalFloat = Typed<OptionalFloatTag>;    // a number or None
using PriorLike = Typed<PriorTag>;                // payload's prior: a file or 10 values
using FrequencyLike = Typed<FrequencyTag>;        // prepare's cutoffs: Hz, "auto"/"none", None
using TablesLike = Typed<TablesTag>;              // prepare's log files
using StartLike = Typed<StartTag>;                // refine's start: a result or its file
using TorqueFilterLike = Typed<TorqueFilterTag>;  // "auto", "none", a cutoff or (cutoff, order)
using ProgressLike = Typed<ProgressTag>;          // search's callback: dict -> False to stop
using FleetRobotsLike = Typed<FleetRobotsTag>;    // fleet's robots: {name: Summary or logs}
using ClientLike = Typed<ClientTag>;              // a Dask distributed.Client, or None

/// A floating-base robot (a URDF path) with the drive terms asked for (bind_floating.cpp).
FloatingModel floatingRobot(const PathLike& robot, const TermsLike& drive_terms);
/// sole=(length, width) [m], a rectangle centred at the frame, or [(x, y), ...] [m], its corners
/// (bind_floating.cpp).
std::vector<Eigen::Vector2d> soleOf(const py::object& sole);

/// The Python spelling of the request fields library messages name (`cutoff`: cutoff), for every
/// message a binding reports (exceptions, warnings): the keyword argument's own name.
std::string pythonText(std::string_view text);
/// Each of `texts` through pythonText.
void pythonTexts(std::vector<std::string>& texts);

// Registration, one function per file.
void bindModel(py::module_& m);
void bindDynamics(py::module_& m);
// One per wing (or, for the runs wing, per family of rooms), in the order module.cpp calls them.
void bindRunsIdentify(py::module_& m);   // bind_runs_identify.cpp
void bindRunsSummarize(py::module_& m);  // bind_runs_summarize.cpp
void bindRunsPredict(py::module_& m);    // bind_runs_predict.cpp
void bindRunsSearch(py::module_& m);     // bind_runs_search.cpp
void bindLogs(py::module_& m);           // bind_logs.cpp
void bindExcitation(py::module_& m);     // bind_excitation.cpp
void bindPayload(py::module_& m);        // bind_payload.cpp
void bindMonitor(py::module_& m);        // bind_monitor.cpp
void bindStudies(py::module_& m);        // bind_studies.cpp
void bindFloating(py::module_& m);       // bind_floating.cpp
void bindStanding(py::module_& m);       // bind_standing.cpp
void bindFleet(py::module_& m);          // bind_fleet.cpp

}  // namespace dynid::python

namespace pybind11::detail {
/// Typed<Tag> takes any object (the binding checks it and raises TypeError or ValueError naming
/// the argument) and is named Tag::name in signatures.
template <typename Tag>
struct handle_type_name<dynid::python::Typed<Tag>> {
  static constexpr auto name = Tag::name;
};
}  // namespace pybind11::detail
