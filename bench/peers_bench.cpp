// dynid against Orocos KDL (ChainIdSolver_RNE, ChainDynParam, ChainFdSolver_RNE) and MuJoCo
// (mj_inverse, mj_forward, mj_step with RK4) on the same PUMA 560, in one run, single-threaded;
// dynid's RK4 step also in lanes (core/lanes.hpp: kLanes states per step), and per step of the GC
// error's rollouts as the searches run them (the lanes and instruction set chosen at run time).
//
// The model: the built-in PUMA 560 made physically consistent (makePuma560Consistent), because
// MuJoCo's compiler refuses the original (link 1 is massless with a rank-1 inertia, link 3 violates
// the triangle inequality; `dynid model check --robot puma560`). dynid exports the model to each
// peer (MJCF text, a KDL chain).
//
// Before timing, every peer's torques, mass matrix, accelerations and RK4 step are compared with
// dynid's at 16 seeded random states. A peer that disagrees by more than 1e-9 relative (round-off
// is about 1e-14) is not timed and has no ratio. A peer not found at build time (DYNID_HAVE_KDL,
// DYNID_HAVE_MUJOCO) is skipped with a message. After the run, a table prints each peer's time over
// dynid's.
//
// Run (the ratios in docs/PERFORMANCE.md):
//   build/bench/bench_peers --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include <benchmark/benchmark.h>

#include "bench/puma_problem.hpp"
#include "core/aba.hpp"
#include "core/crba.hpp"
#include "core/integrators-inl.hpp"
#include "core/lanes.hpp"
#include "core/perturb.hpp"
#include "core/rnea.hpp"
#include "data/mjcf.hpp"
#include "data/puma560.hpp"
#include "search/gc_error.hpp"

#ifdef DYNID_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#endif
#ifdef DYNID_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace {

using dynid::Data;
using dynid::Model;

constexpr double kStep = 1e-3;  // [s], the RK4 step of both engines

/// 64 seeded random states (q within limits, dq, ddq, tau in [-2, 2] times a scale).
struct States {
  explicit States(const Model& model) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < kCount; ++k) {
      const int n = model.numJoints();
      Eigen::VectorXd a(n), b(n), c(n), d(n);
      for (int i = 0; i < n; ++i) {
        a[i] = u(rng) * std::min(model.limits[i].upper, M_PI);
        b[i] = 2.0 * u(rng);
        c[i] = 2.0 * u(rng);
        d[i] = 20.0 * u(rng);
      }
      q.push_back(a), dq.push_back(b), ddq.push_back(c), tau.push_back(d);
    }
  }
  static constexpr int kCount = 64;
  std::vector<Eigen::VectorXd> q, dq, ddq, tau;
};

const Model& model() {
  static const Model m = dynid::makePuma560Consistent();
  return m;
}
const States& states() {
  static const States s(model());
  return s;
}

/// The timed loop: body(k) for state k, cycling through the 64 states.
template <typename Body>
void cycle(benchmark::State& state, Body body) {
  int k = 0;
  for (auto _ : state) {
    body(k);
    k = (k + 1) % States::kCount;
  }
}

/// |a - b| <= 1e-9 max(|a|, 1): the engines agree to round-off (unused without a peer).
[[maybe_unused]] bool agree(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                            const std::string& what, std::string& why) {
  const double scale = std::max(a.cwiseAbs().maxCoeff(), 1.0);
  const double error = (a - b).cwiseAbs().maxCoeff();
  if (error <= 1e-9 * scale) return true;
  why += what + ": differs by " + std::to_string(error) + " (scale " + std::to_string(scale) + ") ";
  return false;
}

// ----- dynid -----

void dynidRnea(benchmark::State& state) {
  Data data(model());
  cycle(state, [&](int k) {
    const States& s = states();
    benchmark::DoNotOptimize(dynid::rnea(model(), data, s.q[k], s.dq[k], s.ddq[k]).data());
  });
}
void dynidMass(benchmark::State& state) {
  Data data(model());
  cycle(state,
        [&](int k) { benchmark::DoNotOptimize(dynid::crba(model(), data, states().q[k]).data()); });
}
void dynidForward(benchmark::State& state) {
  Data data(model());
  cycle(state, [&](int k) {
    const States& s = states();
    benchmark::DoNotOptimize(dynid::aba(model(), data, s.q[k], s.dq[k], s.tau[k]).data());
  });
}
void dynidRk4(benchmark::State& state) {
  Data data(model());
  Eigen::VectorXd q, dq;
  cycle(state, [&](int k) {
    const States& s = states();
    q = s.q[k];
    dq = s.dq[k];
    dynid::rk4Step(model(), data, q, dq, s.tau[k], kStep);
    benchmark::DoNotOptimize(q.data());
  });
}

/// kLanes states at once through rk4Step<Lanes> (core/lanes.hpp), as the GC error rolls segments:
/// the table divides the time by kLanes (per state, beside a one-state step).
void dynidRk4Lanes(benchmark::State& state) {
  using L = dynid::Lanes<dynid::kLanes>;
  const dynid::ModelTpl<L> lanes = model().cast<L>();
  dynid::DataTpl<L> data(lanes);
  const int n = model().numJoints();
  dynid::VectorX<L> q(n), dq(n), tau(n);
  cycle(state, [&](int k) {
    const States& s = states();
    for (int l = 0; l < dynid::kLanes; ++l) {
      const int m = (k + l) % States::kCount;
      for (int j = 0; j < n; ++j)
        q[j].set(l, s.q[m][j]), dq[j].set(l, s.dq[m][j]), tau[j].set(l, s.tau[m][j]);
    }
    dynid::rk4Step(lanes, data, q, dq, tau, L(kStep));
    benchmark::DoNotOptimize(q.data());
  });
}

/// The GC error's rollouts as the searches run them (search/gc_error.hpp: 100 PUMA segments of 50
/// RK4 steps, one thread, defaultGcLanes() lanes in the widest instruction set this build and CPU
/// offer, gcLaneIsa()): the time of one evaluation divided by its 5000 steps, for a per-core RK4
/// step rate beside MuJoCo's. Includes what a rollout adds to its steps (each sample's torques
/// into the lanes, each segment's start state and error).
void dynidGcRolloutStep(benchmark::State& state) {
  static const dynid::GcProblem problem = dynid::bench::pumaProblem(100);
  const Model candidate = dynid::perturbedModel(dynid::makePuma560(), 0.3, 1);  // as bench_search
  dynid::ThreadPool pool(1);
  dynid::GcWorkspace workspace(1);
  for (auto _ : state)
    benchmark::DoNotOptimize(dynid::gcError(candidate, problem, workspace, pool));
  state.counters["lanes"] = workspace.lanes;
  state.counters["isa"] = workspace.lane_isa;
}

// ----- Orocos KDL -----
#ifdef DYNID_HAVE_KDL
/// The model as a KDL chain: segment i is joint frame i, its joint at the frame placement's origin
/// with the axis in the parent's frame, its tip (given at q = 0, as KDL takes it) the frame
/// placement, its inertia the joint-frame inertia. Serial chains only.
KDL::Chain kdlChain(const Model& m) {
  KDL::Chain chain;
  for (int i = 0; i < m.numJoints(); ++i) {
    if (m.parents()[i] != i - 1) throw std::runtime_error("KDL: not a serial chain");
    const dynid::Pose<double>& placement = m.frame_placements()[i];
    const Eigen::Matrix3d& R = placement.rotation;
    const Eigen::Vector3d& t = placement.translation;
    const Eigen::Vector3d axis = R * m.axes()[i];
    const KDL::Joint joint(m.joint_names[i], KDL::Vector(t.x(), t.y(), t.z()),
                           KDL::Vector(axis.x(), axis.y(), axis.z()),
                           m.joint_types()[i] == dynid::JointType::kPrismatic
                               ? KDL::Joint::TransAxis
                               : KDL::Joint::RotAxis);
    const KDL::Frame tip(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2),
                                       R(2, 0), R(2, 1), R(2, 2)),
                         KDL::Vector(t.x(), t.y(), t.z()));
    const dynid::RigidInertia<double>& I = m.frame_inertias()[i];
    const Eigen::Vector3d c =
        I.mass != 0.0 ? Eigen::Vector3d(I.first_moment / I.mass) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d Ic =
        I.inertia - I.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    chain.addSegment(KDL::Segment(
        m.link_names[i], joint, tip,
        KDL::RigidBodyInertia(
            I.mass, KDL::Vector(c.x(), c.y(), c.z()),
            KDL::RotationalInertia(Ic(0, 0), Ic(1, 1), Ic(2, 2), Ic(0, 1), Ic(0, 2), Ic(1, 2)))));
  }
  return chain;
}

struct Kdl {
  Kdl()
      : chain(kdlChain(model())),
        gravity(model().gravity().x(), model().gravity().y(), model().gravity().z()),
        id(chain, gravity),
        param(chain, gravity),
        fd(chain, gravity),
        n(model().numJoints()),
        q(n),
        dq(n),
        ddq(n),
        tau(n),
        mass(n),
        wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero()) {}
  void load(int k, const Eigen::VectorXd& third) {
    q.data = states().q[k];
    dq.data = states().dq[k];
    ddq.data = third;
  }
  KDL::Chain chain;
  KDL::Vector gravity;
  KDL::ChainIdSolver_RNE id;
  KDL::ChainDynParam param;
  KDL::ChainFdSolver_RNE fd;
  int n;
  KDL::JntArray q, dq, ddq, tau;
  KDL::JntSpaceInertiaMatrix mass;
  KDL::Wrenches wrenches;
};

void kdlRnea(benchmark::State& state) {
  Kdl kdl;
  cycle(state, [&](int k) {
    kdl.load(k, states().ddq[k]);
    kdl.id.CartToJnt(kdl.q, kdl.dq, kdl.ddq, kdl.wrenches, kdl.tau);
    benchmark::DoNotOptimize(kdl.tau.data.data());
  });
}
void kdlMass(benchmark::State& state) {
  Kdl kdl;
  cycle(state, [&](int k) {
    kdl.q.data = states().q[k];
    kdl.param.JntToMass(kdl.q, kdl.mass);
    benchmark::DoNotOptimize(kdl.mass.data.data());
  });
}
void kdlForward(benchmark::State& state) {
  Kdl kdl;
  cycle(state, [&](int k) {
    kdl.load(k, states().tau[k]);  // ddq holds the torques here
    kdl.fd.CartToJnt(kdl.q, kdl.dq, kdl.ddq, kdl.wrenches, kdl.tau);
    benchmark::DoNotOptimize(kdl.tau.data.data());
  });
}

std::string checkKdl() {
  Kdl kdl;
  Data data(model());
  std::string why;
  for (int k = 0; k < 16; ++k) {
    const States& s = states();
    kdl.load(k, s.ddq[k]);
    if (kdl.id.CartToJnt(kdl.q, kdl.dq, kdl.ddq, kdl.wrenches, kdl.tau) < 0)
      return "ChainIdSolver_RNE failed";
    agree(dynid::rnea(model(), data, s.q[k], s.dq[k], s.ddq[k]), kdl.tau.data, "torques", why);
    kdl.param.JntToMass(kdl.q, kdl.mass);
    const Eigen::MatrixXd M = dynid::crba(model(), data, s.q[k]);
    agree(Eigen::Map<const Eigen::VectorXd>(M.data(), M.size()),
          Eigen::Map<const Eigen::VectorXd>(kdl.mass.data.data(), kdl.mass.data.size()),
          "mass matrix", why);
    kdl.load(k, s.tau[k]);
    if (kdl.fd.CartToJnt(kdl.q, kdl.dq, kdl.ddq, kdl.wrenches, kdl.tau) < 0)
      return "ChainFdSolver_RNE failed";
    agree(dynid::aba(model(), data, s.q[k], s.dq[k], s.tau[k]), kdl.tau.data, "accelerations", why);
    if (!why.empty()) return "state " + std::to_string(k) + ": " + why;
  }
  return "";
}
#endif

// ----- MuJoCo -----
#ifdef DYNID_HAVE_MUJOCO
struct MuJoCo {
  MuJoCo() {
    // mj_loadXML reads a file: the exported MJCF goes through a temporary one.
    const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                       ("dynid_peers_" + std::to_string(::getpid()) + ".xml");
    {
      std::ofstream out(path);
      out << dynid::modelToMjcf(model(), {.timestep = kStep, .integrator = "RK4"});
    }
    char error[1000] = "";
    m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
    std::filesystem::remove(path);
    if (m == nullptr) throw std::runtime_error(std::string("MuJoCo: ") + error);
    d = mj_makeData(m);
  }
  ~MuJoCo() {
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  MuJoCo(const MuJoCo&) = delete;
  MuJoCo& operator=(const MuJoCo&) = delete;
  void set(const Eigen::VectorXd& qpos, const Eigen::VectorXd& qvel) {
    Eigen::Map<Eigen::VectorXd>(d->qpos, m->nq) = qpos;
    Eigen::Map<Eigen::VectorXd>(d->qvel, m->nv) = qvel;
  }
  Eigen::Map<Eigen::VectorXd> vec(mjtNum* p) const { return {p, m->nv}; }
  mjModel* m = nullptr;
  mjData* d = nullptr;
};

void mujocoInverse(benchmark::State& state) {
  MuJoCo mj;
  cycle(state, [&](int k) {
    const States& s = states();
    mj.set(s.q[k], s.dq[k]);
    mj.vec(mj.d->qacc) = s.ddq[k];
    mj_inverse(mj.m, mj.d);
    benchmark::DoNotOptimize(mj.d->qfrc_inverse);
  });
}
void mujocoForward(benchmark::State& state) {
  MuJoCo mj;
  cycle(state, [&](int k) {
    const States& s = states();
    mj.set(s.q[k], s.dq[k]);
    mj.vec(mj.d->qfrc_applied) = s.tau[k];
    mj_forward(mj.m, mj.d);
    benchmark::DoNotOptimize(mj.d->qacc);
  });
}
void mujocoStep(benchmark::State& state) {
  MuJoCo mj;
  cycle(state, [&](int k) {
    const States& s = states();
    mj.set(s.q[k], s.dq[k]);
    mj.vec(mj.d->qfrc_applied) = s.tau[k];
    mj_step(mj.m, mj.d);
    benchmark::DoNotOptimize(mj.d->qpos);
  });
}

std::string checkMujoco() {
  MuJoCo mj;
  Data data(model());
  const int n = model().numJoints();
  if (mj.m->nv != n) return "MuJoCo has " + std::to_string(mj.m->nv) + " dofs";
  std::string why;
  for (int k = 0; k < 16; ++k) {
    const States& s = states();
    mj.set(s.q[k], s.dq[k]);
    mj.vec(mj.d->qacc) = s.ddq[k];
    mj_inverse(mj.m, mj.d);
    agree(dynid::rnea(model(), data, s.q[k], s.dq[k], s.ddq[k]), mj.vec(mj.d->qfrc_inverse),
          "torques", why);
    mj.vec(mj.d->qfrc_applied) = s.tau[k];
    mj_forward(mj.m, mj.d);
    agree(dynid::aba(model(), data, s.q[k], s.dq[k], s.tau[k]), mj.vec(mj.d->qacc), "accelerations",
          why);
    Eigen::MatrixXd M(n, n);
    mj_fullM(mj.m, M.data(), mj.d->qM);  // symmetric: row- or column-major alike
    const Eigen::MatrixXd Md = dynid::crba(model(), data, s.q[k]);
    agree(Eigen::Map<const Eigen::VectorXd>(Md.data(), Md.size()),
          Eigen::Map<const Eigen::VectorXd>(M.data(), M.size()), "mass matrix", why);
    mj.d->time = 0.0;
    mj_step(mj.m, mj.d);
    Eigen::VectorXd q = s.q[k], dq = s.dq[k];
    dynid::rk4Step(model(), data, q, dq, s.tau[k], kStep);
    agree(q, Eigen::Map<const Eigen::VectorXd>(mj.d->qpos, n), "RK4 step q", why);
    agree(dq, mj.vec(mj.d->qvel), "RK4 step dq", why);
    // The lanes' step, every lane from state k.
    using L = dynid::Lanes<dynid::kLanes>;
    const dynid::ModelTpl<L> lanes = model().cast<L>();
    dynid::DataTpl<L> lane_data(lanes);
    dynid::VectorX<L> ql = s.q[k].cast<L>(), dql = s.dq[k].cast<L>();
    dynid::rk4Step(lanes, lane_data, ql, dql, s.tau[k].cast<L>().eval(), L(kStep));
    for (int l = 0; l < dynid::kLanes; ++l) {
      for (int j = 0; j < n; ++j) q[j] = ql[j][l], dq[j] = dql[j][l];
      agree(q, Eigen::Map<const Eigen::VectorXd>(mj.d->qpos, n), "RK4 lanes q", why);
      agree(dq, mj.vec(mj.d->qvel), "RK4 lanes dq", why);
    }
    if (!why.empty()) return "state " + std::to_string(k) + ": " + why;
  }
  return "";
}
#endif

/// Records each benchmark's time (the median when repeated) for the ratio table.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      const std::string name = run.run_name.function_name;
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name != "median") continue;
      if (run.error_occurred) continue;
      // A repeated benchmark reports its median last; a single one its only run.
      times[name] = run.GetAdjustedRealTime();
    }
  }
  std::map<std::string, double> times;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::cout << "Model: " << model().name << " (data/puma560.hpp)\n";

  // quantity -> (engine, benchmark name)
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> table = {
      {"inverse dynamics (RNEA)", {{"dynid", "RNEA/dynid"}}},
      {"mass matrix", {{"dynid", "MassMatrix/dynid"}}},
      {"forward dynamics", {{"dynid", "ForwardDynamics/dynid"}}},
      {"RK4 step (1 ms)", {{"dynid", "Rk4Step/dynid"}}},
      {"RK4 step, per lane", {{"dynid", "Rk4Step/dynid-lanes"}}},
      {"RK4 step in the GC rollout", {{"dynid", "Rk4Step/dynid-gc-rollout"}}}};
  benchmark::RegisterBenchmark("RNEA/dynid", dynidRnea);
  benchmark::RegisterBenchmark("MassMatrix/dynid", dynidMass);
  benchmark::RegisterBenchmark("ForwardDynamics/dynid", dynidForward);
  benchmark::RegisterBenchmark("Rk4Step/dynid", dynidRk4);
  benchmark::RegisterBenchmark("Rk4Step/dynid-lanes", dynidRk4Lanes);
  benchmark::RegisterBenchmark("Rk4Step/dynid-gc-rollout", dynidGcRolloutStep);

#ifdef DYNID_HAVE_KDL
  if (const std::string why = checkKdl(); why.empty()) {
    std::cout << "Orocos KDL: agrees with dynid at 16 states (torques, mass matrix, "
                 "accelerations)\n";
    benchmark::RegisterBenchmark("RNEA/KDL-ChainIdSolver_RNE", kdlRnea);
    benchmark::RegisterBenchmark("MassMatrix/KDL-ChainDynParam", kdlMass);
    benchmark::RegisterBenchmark("ForwardDynamics/KDL-ChainFdSolver_RNE", kdlForward);
    table[0].second.push_back({"KDL", "RNEA/KDL-ChainIdSolver_RNE"});
    table[1].second.push_back({"KDL", "MassMatrix/KDL-ChainDynParam"});
    table[2].second.push_back({"KDL", "ForwardDynamics/KDL-ChainFdSolver_RNE"});
  } else {
    std::cout << "Orocos KDL: DISAGREES with dynid, not timed: " << why << "\n";
  }
#else
  std::cout << "Orocos KDL: not found at build time (liborocos-kdl-dev), skipped\n";
#endif
#ifdef DYNID_HAVE_MUJOCO
  try {
    if (const std::string why = checkMujoco(); why.empty()) {
      std::cout << "MuJoCo " << mj_versionString()
                << ": agrees with dynid at 16 states (torques, mass matrix, accelerations, "
                   "RK4 step, alone and in lanes)\n";
      benchmark::RegisterBenchmark("RNEA/MuJoCo-mj_inverse", mujocoInverse);
      benchmark::RegisterBenchmark("ForwardDynamics/MuJoCo-mj_forward", mujocoForward);
      benchmark::RegisterBenchmark("Rk4Step/MuJoCo-mj_step", mujocoStep);
      table[0].second.push_back({"MuJoCo", "RNEA/MuJoCo-mj_inverse"});
      table[2].second.push_back({"MuJoCo", "ForwardDynamics/MuJoCo-mj_forward"});
      table[3].second.push_back({"MuJoCo", "Rk4Step/MuJoCo-mj_step"});
      table[4].second.push_back({"MuJoCo", "Rk4Step/MuJoCo-mj_step"});
      table[5].second.push_back({"MuJoCo", "Rk4Step/MuJoCo-mj_step"});
    } else {
      std::cout << "MuJoCo: DISAGREES with dynid, not timed: " << why << "\n";
    }
  } catch (const std::exception& e) {
    std::cout << "MuJoCo: could not load the exported model, not timed: " << e.what() << "\n";
  }
#else
  std::cout << "MuJoCo: not found at build time (libmujoco-dev), skipped\n";
#endif

  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();

  std::cout << "\nPeer time / dynid time (same run; > 1: dynid is faster)\n";
  for (const auto& [quantity, engines] : table) {
    const auto own = reporter.times.find(engines.front().second);
    if (own == reporter.times.end()) continue;
    // The lanes' time is for kLanes states, the GC rollout's for its 100 x 50 steps.
    const double own_ns = own->first == "Rk4Step/dynid-lanes"        ? own->second / dynid::kLanes
                          : own->first == "Rk4Step/dynid-gc-rollout" ? own->second / 5000.0
                                                                     : own->second;
    std::printf("  %-26s dynid %9.1f ns", quantity.c_str(), own_ns);
    for (std::size_t e = 1; e < engines.size(); ++e) {
      const auto peer = reporter.times.find(engines[e].second);
      if (peer == reporter.times.end()) continue;
      std::printf(" | %s %9.1f ns = %5.2fx", engines[e].first.c_str(), peer->second,
                  peer->second / own_ns);
    }
    std::printf("\n");
  }
  return 0;
}
