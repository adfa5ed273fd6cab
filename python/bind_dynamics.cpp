// rnea, aba, crba and regressor: one state ((n,) arrays) or a batch ((N, n) arrays, one state per
// row) in one call. A batch runs without the GIL on `threads` threads (0: all cores), each thread
// with its own workspace; every output row is written by one thread, so the result does not
// depend on the thread count.
#include <algorithm>
#include <atomic>
#include <functional>
#include <memory>
#include <new>

#include "analysis/runs/arm.hpp"
#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/data.hpp"
#include "core/parallel.hpp"
#include "core/regressor.hpp"
#include "core/rnea.hpp"
#include "python/common.hpp"

namespace dynid::python {
namespace {

using Vector = Eigen::Map<const Eigen::VectorXd>;
/// One state's computation: inputs a, b, c (n entries each; c unused by crba), output `out`
/// (the function's per-state size, row-major).
using StateFunction =
    std::function<void(const Model&, Data&, const double*, const double*, const double*, double*)>;

constexpr int kBlockStates = 256;  // states per parallel task: ~0.3 ms of RNEA, far above its cost

struct Input {
  const char* name;
  py::handle value;
};

/// Checks the inputs (all (n,) or all (N, n), the same N), runs `f` on each state and returns
/// the outputs, shape `tail` for one state and (N, *tail) for a batch.
py::array evaluate(const Model& model, const std::vector<Input>& inputs,
                   const std::vector<py::ssize_t>& tail, int threads, const StateFunction& f) {
  checkThreads(threads);
  const py::ssize_t n = model.numJoints();
  std::vector<DoubleArray> arrays;
  for (const Input& in : inputs) arrays.push_back(realArray(in.value, in.name, {1, 2}));
  const DoubleArray& first = arrays.front();
  const bool single = first.ndim() == 1;
  const py::ssize_t count = single ? 1 : first.shape(0);
  for (std::size_t i = 0; i < arrays.size(); ++i) {
    const DoubleArray& a = arrays[i];
    const bool ok =
        a.ndim() == first.ndim() && a.shape(a.ndim() - 1) == n && (single || a.shape(0) == count);
    if (!ok)
      throw py::value_error(
          std::string(inputs[i].name) + ": expected shape " +
          (single ? "(" + std::to_string(n) + ",)"
                  : "(" + std::to_string(count) + ", " + std::to_string(n) + ")") +
          " (" + inputs[0].name + " has " + shapeText(first) + ", robot '" + model.name + "' " +
          std::to_string(n) + " joints), got " + shapeText(a));
  }
  std::vector<py::ssize_t> shape = tail;
  if (!single) shape.insert(shape.begin(), count);
  py::array_t<double> out(shape);
  py::ssize_t per_state = 1;
  for (py::ssize_t d : tail) per_state *= d;
  const double* in[3] = {nullptr, nullptr, nullptr};
  for (std::size_t i = 0; i < arrays.size(); ++i) in[i] = arrays[i].data();
  double* result = out.mutable_data();

  if (single) {  // a few microseconds: keep the GIL, no pool
    Data data(model);
    f(model, data, in[0], in[1], in[2], result);
    return out;
  }
  const Model local = model;  // another Python thread may change `model` once the GIL is free
  std::atomic<bool> out_of_memory{false};
  {
    py::gil_scoped_release release;
    const int blocks = static_cast<int>((count + kBlockStates - 1) / kBlockStates);
    ThreadPool pool(std::max(1, std::min(resolveThreads(threads), blocks)));
    // Each workspace is allocated by the thread that writes it (glibc gives each thread its own
    // arena), so no two threads' workspaces share a cache line.
    std::vector<std::unique_ptr<Data>> work(static_cast<std::size_t>(pool.numThreads()));
    pool.parallelFor(blocks, [&](int block, int thread) {
      std::unique_ptr<Data>& data = work[static_cast<std::size_t>(thread)];
      try {
        if (!data) data = std::make_unique<Data>(local);
      } catch (const std::bad_alloc&) {
        out_of_memory = true;
        return;
      }
      const py::ssize_t end = std::min<py::ssize_t>(count, (block + 1) * kBlockStates);
      for (py::ssize_t k = static_cast<py::ssize_t>(block) * kBlockStates; k < end; ++k)
        f(local, *data, in[0] + k * n, in[1] ? in[1] + k * n : nullptr,
          in[2] ? in[2] + k * n : nullptr, result + k * per_state);
    });
  }
  if (out_of_memory) throw std::bad_alloc();
  return out;
}

void copyRowMajor(const Eigen::MatrixXd& m, double* out) {
  Eigen::Map<RowMatrix>(out, m.rows(), m.cols()) = m;
}

}  // namespace

void bindDynamics(py::module_& m) {
  m.def(
      "rnea",
      [](const Model& model, const ArrayLike& q, const ArrayLike& dq, const ArrayLike& ddq,
         int threads) {
        const int n = model.numJoints();
        return evaluate(model, {{"q", q}, {"dq", dq}, {"ddq", ddq}}, {n}, threads,
                        [n](const Model& mo, Data& d, const double* a, const double* b,
                            const double* c, double* out) {
                          Eigen::Map<Eigen::VectorXd>(out, n) =
                              rnea(mo, d, Vector(a, n), Vector(b, n), Vector(c, n));
                        });
      },
      py::arg("model"), py::arg("q"), py::arg("dq"), py::arg("ddq"),
      py::arg("threads") = kAllThreads,
      "Inverse dynamics tau = M(q) ddq + C(q, dq) dq + g(q) (+ the drive terms the model "
      "enables). q, dq, ddq: (n,) -> tau (n,), or (N, n) -> (N, n). [rad, rad/s, rad/s^2 -> N m]");
  m.def(
      "aba",
      [](const Model& model, const ArrayLike& q, const ArrayLike& dq, const ArrayLike& tau,
         int threads) {
        const int n = model.numJoints();
        return evaluate(model, {{"q", q}, {"dq", dq}, {"tau", tau}}, {n}, threads,
                        [n](const Model& mo, Data& d, const double* a, const double* b,
                            const double* c, double* out) {
                          Eigen::Map<Eigen::VectorXd>(out, n) =
                              aba(mo, d, Vector(a, n), Vector(b, n), Vector(c, n));
                        });
      },
      py::arg("model"), py::arg("q"), py::arg("dq"), py::arg("tau"),
      py::arg("threads") = kAllThreads,
      "Forward dynamics ddq = M(q)^-1 (tau - C(q, dq) dq - g(q) - friction). q, dq, tau: (n,) -> "
      "ddq (n,), or (N, n) -> (N, n). Singular dynamics (a massless moving subtree) give "
      "non-finite ddq.");
  m.def(
      "crba",
      [](const Model& model, const ArrayLike& q, int threads) {
        const int n = model.numJoints();
        return evaluate(model, {{"q", q}}, {n, n}, threads,
                        [n](const Model& mo, Data& d, const double* a, const double*, const double*,
                            double* out) { copyRowMajor(crba(mo, d, Vector(a, n)), out); });
      },
      py::arg("model"), py::arg("q"), py::arg("threads") = kAllThreads,
      "Joint-space mass matrix M(q) (with the rotor inertias Ia when enabled). q: (n,) -> (n, n), "
      "or (N, n) -> (N, n, n). [kg m^2]");
  m.def(
      "regressor",
      [](const Model& model, const ArrayLike& q, const ArrayLike& dq, const ArrayLike& ddq,
         int threads) {
        const int n = model.numJoints();
        const int p = model.parameterLayout().size();
        return evaluate(model, {{"q", q}, {"dq", dq}, {"ddq", ddq}}, {n, p}, threads,
                        [n](const Model& mo, Data& d, const double* a, const double* b,
                            const double* c, double* out) {
                          copyRowMajor(
                              jointTorqueRegressor(mo, d, Vector(a, n), Vector(b, n), Vector(c, n)),
                              out);
                        });
      },
      py::arg("model"), py::arg("q"), py::arg("dq"), py::arg("ddq"),
      py::arg("threads") = kAllThreads,
      "Joint torque regressor Y with Y @ model.parameters == rnea(model, q, dq, ddq); columns in "
      "model.parameter_names order. q, dq, ddq: (n,) -> (n, p), or (N, n) -> (N, n, p).");
}

}  // namespace dynid::python
