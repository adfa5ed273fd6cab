// The `dynid` Python module: registration and the translation of dynid's exceptions.
//   dynid.InputError(ValueError)       an invalid argument or option (sizes, values)
//   dynid.ParseError(ValueError)       a malformed file; .file, .line (0: unknown), .field
//   dynid.NumericalError(RuntimeError) a computation failed on valid input
//   dynid.Error(RuntimeError)          any other failure (a file that cannot be read or written)
#include <exception>
#include <new>

#include "core/errors.hpp"
#include "python/common.hpp"

namespace dynid::python {
namespace {

void registerExceptions(py::module_& m) {
  // Created once and kept for the interpreter's lifetime (the module object holds them too).
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<NumericalError> numerical(m, "NumericalError", PyExc_RuntimeError);
  static py::exception<InputError> input(m, "InputError", PyExc_ValueError);
  static py::exception<ParseError> parse(m, "ParseError", PyExc_ValueError);
  error.doc() = "A dynid failure that is not the input's fault (a file that cannot be read).";
  numerical.doc() = "A computation failed on valid input (singular dynamics, unexcited data).";
  input.doc() = "An invalid argument: a size, a value or an option dynid cannot use.";
  parse.doc() = "A malformed file; .file, .line (1-based, 0 when unknown) and .field say where.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ParseError& e) {
      PyObject* type = parse.ptr();
      py::object instance = py::reinterpret_borrow<py::object>(type)(pythonText(e.what()));
      instance.attr("file") = e.file();
      instance.attr("line") = e.line();
      instance.attr("field") = pythonText(e.element());
      PyErr_SetObject(type, instance.ptr());
    } catch (const InputError& e) {
      input(pythonText(e.what()).c_str());
    } catch (const NumericalError& e) {
      numerical(pythonText(e.what()).c_str());
    } catch (const Error& e) {
      error(pythonText(e.what()).c_str());
    }
  });
}

}  // namespace

std::string pythonText(std::string_view text) {
  return respellFields(text, [](std::string_view field) { return std::string(field); });
}

void pythonTexts(std::vector<std::string>& texts) {
  for (std::string& text : texts) text = pythonText(text);
}

}  // namespace dynid::python

PYBIND11_MODULE(dynid, m) {
  m.doc() =
      "dynid: inertial-parameter identification of robot manipulators.\n\n"
      "Arrays are NumPy float64 in SI units and radians. A batch of states is an (N, n) array, "
      "one row per state; one state is an (n,) array. Standard parameters per link: m, mx, my, "
      "mz, Ixx, Ixy, Ixz, Iyy, Iyz, Izz (then the drive terms Ia, Fv, Fc, Fo, Fa, Fs that the "
      "model "
      "enables), named m1, mx1, ..., Ia1. Datasets are a path to a dynid CSV or a Dataset.";
  m.attr("__version__") = DYNID_VERSION;
  dynid::python::registerExceptions(m);
  dynid::python::bindModel(m);
  dynid::python::bindDynamics(m);
  dynid::python::bindRunsSummarize(m);
  dynid::python::bindRunsIdentify(m);
  dynid::python::bindRunsPredict(m);
  dynid::python::bindPayload(m);
  dynid::python::bindMonitor(m);
  dynid::python::bindStudies(m);
  dynid::python::bindFloating(m);
  dynid::python::bindStanding(m);
  dynid::python::bindFleet(m);
  dynid::python::bindRunsSearch(m);
  dynid::python::bindExcitation(m);
  dynid::python::bindLogs(m);
}
