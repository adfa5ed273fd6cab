// Once a Data exists, RNEA, CRBA, ABA, forward kinematics and the integrator steps allocate
// nothing. Checked on the core library as shipped (its release objects, not a rebuild of them):
// this program replaces the C allocator, which operator new and Eigen both call, with one that
// counts its calls. glibc lets a program define malloc and its siblings; these forward to glibc's
// own allocator through its exported __libc_* entry points. Not built under the sanitizers, whose
// runtime replaces the allocator itself (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <cstddef>

#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/floating/floating_aba.hpp"
#include "core/floating/floating_regressor.hpp"
#include "core/floating/floating_rnea.hpp"
#include "core/integrators.hpp"
#include "core/kinematics.hpp"
#include "core/rnea.hpp"
#include "data/puma560.hpp"

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
}

namespace {

std::atomic<bool> counting{false};
std::atomic<long> allocations{0};

void noteAllocation() {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
}

/// The allocations made between its construction and allocationsSoFar().
class AllocationCount {
 public:
  AllocationCount() {
    allocations = 0;
    counting = true;
  }
  ~AllocationCount() { counting = false; }
  long allocationsSoFar() const { return allocations.load(); }
};

}  // namespace

extern "C" {
void* malloc(std::size_t size) noexcept {
  noteAllocation();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  noteAllocation();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  noteAllocation();
  return __libc_realloc(pointer, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  noteAllocation();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  noteAllocation();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  noteAllocation();
  void* pointer = __libc_memalign(alignment, size);
  if (pointer == nullptr) return ENOMEM;
  *out = pointer;
  return 0;
}
}

namespace dynid {
namespace {

TEST(NoMalloc, TheCountSeesEigenAndOperatorNew) {
  // The mechanism itself: Eigen's allocations (a Data is sized to its model on the heap) and
  // operator new's inside a library (the data library builds a model's vectors and strings).
  long eigen = -1, library = -1;
  const Model model = makePuma560();
  {
    const AllocationCount count;
    const Data data(model);
    eigen = count.allocationsSoFar();
    EXPECT_EQ(data.tau.size(), 6);
  }
  {
    const AllocationCount count;
    const Model built = makePuma560(true);
    library = count.allocationsSoFar();
    EXPECT_EQ(built.numJoints(), 6);
  }
  EXPECT_GT(eigen, 0);
  EXPECT_GT(library, 0);
}

TEST(NoMalloc, AlgorithmsAllocateNothing) {
  for (bool drives : {false, true}) {
    const Model model = makePuma560(drives);
    Data data(model);
    Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.3),
                    ddq = Eigen::VectorXd::Constant(6, -0.2),
                    tau = Eigen::VectorXd::Constant(6, 1.0);
    long made = -1;
    {
      const AllocationCount count;
      rnea(model, data, q, dq, ddq);
      crba(model, data, q);
      aba(model, data, q, dq, tau);
      forwardKinematics(model, data, q);
      rk4Step(model, data, q, dq, tau, 1e-3);
      semiImplicitEulerStep(model, data, q, dq, tau, 1e-3);
      made = count.allocationsSoFar();
    }
    EXPECT_EQ(made, 0) << (drives ? "with drives" : "without drives");
    EXPECT_TRUE(q.allFinite());
  }
}

TEST(NoMalloc, FloatingBaseAlgorithmsAllocateNothing) {
  for (bool drives : {false, true}) {
    RigidInertia<double> trunk;
    trunk.mass = 12.0, trunk.first_moment << 0.1, 0.0, -0.2, trunk.inertia.diagonal() << 0.4, 0.5,
    0.3;
    const FloatingModel model(makePuma560(drives), trunk);
    FloatingData data(model);
    const Eigen::VectorXd q = puma560Pose("qn"), dq = Eigen::VectorXd::Constant(6, 0.3),
                          ddq = Eigen::VectorXd::Constant(6, -0.2),
                          tau = Eigen::VectorXd::Constant(6, 1.0);
    BaseMotion base;
    base.twist << 0.1, -0.2, 0.3, 0.5, 0.0, -0.1;
    base.acceleration << 0.2, 0.1, 0.0, -0.3, 0.4, 0.2;
    const Vector6<double> wrench = Vector6<double>::Constant(2.0);
    long made = -1;
    {
      const AllocationCount count;
      floatingRnea(model, data, base, q, dq, ddq);
      floatingRegressor(model, data, base, q, dq, ddq);
      floatingCrba(model, data, q);
      floatingForwardDynamics(model, data, base, q, dq, tau, wrench);
      floatingAba(model, data, base, q, dq, tau, wrench);
      made = count.allocationsSoFar();
    }
    EXPECT_EQ(made, 0) << (drives ? "with drives" : "without drives");
    EXPECT_TRUE(data.acceleration.allFinite());
  }
}

}  // namespace
}  // namespace dynid
