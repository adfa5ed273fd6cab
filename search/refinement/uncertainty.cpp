#include "search/refinement/uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ceres/ceres.h>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace dynid {

using RowMajor = RowMajorMatrix;

Eigen::MatrixXd betaInformation(const Model& structure, const BetaLift& map,
                                const GcProblem& problem, const Eigen::VectorXd& beta,
                                Eigen::MatrixXd starts, const RefineOptions& options,
                                ThreadPool& pool, double& squared_sum) {
  const int b = static_cast<int>(beta.size()), n = structure.numJoints();
  const int segments = problem.numSegments();
  const bool with_start = options.estimate_initial_states;
  const int m = (with_start ? 4 : 2) * n;
  std::vector<RowMajor> jb(segments), js(segments), jn(segments);
  Eigen::VectorXd squared(segments);
  pool.parallelFor(segments, [&](int s, int) {
    const double continuity = continuityOf(problem, options, s);
    const auto cost = makeBetaSegmentCost(structure, map, problem, s, with_start, continuity);
    Eigen::VectorXd probe = beta;
    const std::vector<double*> blocks = segmentBlocks(problem, options, s, probe.data(), starts);
    const std::vector<const double*> parameters(blocks.begin(), blocks.end());
    jb[s].resize(m, b);
    js[s].resize(m, with_start ? 2 * n : 0);
    jn[s].resize(m, continuity > 0.0 ? 2 * n : 0);
    double* jacobians[3] = {jb[s].data(), js[s].data(), jn[s].data()};
    Eigen::VectorXd r(m);
    if (!cost->Evaluate(parameters.data(), r.data(), jacobians)) {
      jb[s].setZero(), js[s].setZero(), jn[s].setZero();
      squared[s] = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    squared[s] = r.squaredNorm();
  });
  squared_sum = squared.sum();
  return eliminateStarts(jb, js, jn);
}

Eigen::MatrixXd eliminateStarts(const std::vector<RowMajor>& jb, const std::vector<RowMajor>& js,
                                const std::vector<RowMajor>& jn) {
  const int segments = static_cast<int>(jb.size());
  if (segments == 0) return {};
  const Eigen::Index b = jb[0].cols();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(b, b);
  for (const RowMajor& j : jb) H.noalias() += j.transpose() * j;
  const Eigen::Index w = js[0].cols();
  if (w == 0) return H;
  // H - B^T A^-1 B with A = Js^T Js (block tridiagonal when chained) and B = Js^T Jb over the
  // stacked starts.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(w * segments, b);
  const auto add = [&](int row_block, int col_block, const Eigen::MatrixXd& block) {
    for (Eigen::Index i = 0; i < w; ++i)
      for (Eigen::Index j = 0; j < w; ++j)
        entries.emplace_back(row_block * w + i, col_block * w + j, block(i, j));
  };
  for (int s = 0; s < segments; ++s) {
    add(s, s, js[s].transpose() * js[s]);
    B.middleRows(s * w, w).noalias() += js[s].transpose() * jb[s];
    if (jn[s].cols() == 0) continue;
    const Eigen::MatrixXd cross = js[s].transpose() * jn[s];
    add(s, s + 1, cross);
    add(s + 1, s, cross.transpose());
    add(s + 1, s + 1, jn[s].transpose() * jn[s]);
    B.middleRows((s + 1) * w, w).noalias() += jn[s].transpose() * jb[s];
  }
  Eigen::SparseMatrix<double> A(w * segments, w * segments);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  if (ldlt.info() != Eigen::Success) return Eigen::MatrixXd::Constant(b, b, std::nan(""));
  H.noalias() -= B.transpose() * ldlt.solve(B);
  return H;
}

Eigen::VectorXd magnitudes(const Eigen::VectorXd& v) {
  const double mean = v.size() > 0 ? v.cwiseAbs().mean() : 0.0;
  const auto zero = [&](double e) { return std::abs(e) <= 1e-9 * mean; };
  double sum = 0.0;
  int count = 0;
  for (double e : v)
    if (!zero(e)) sum += std::abs(e), ++count;
  const double fallback = count > 0 ? sum / count : 1.0;
  Eigen::VectorXd out(v.size());
  for (int j = 0; j < v.size(); ++j) out[j] = zero(v[j]) ? fallback : std::abs(v[j]);
  return out;
}

FreeAnalysis analyseFreeDirections(const Model& structure, const ParameterSpace& space,
                                   const Eigen::MatrixXd& P, const Eigen::VectorXd& x) {
  const int k = space.numFree();
  const int p = static_cast<int>(P.cols());
  const auto map_cost = makeStandardOfFreeCost(structure, space);
  RowMajor jtheta(p, k);
  Eigen::VectorXd theta(p);
  const double* x_pointer[1] = {x.data()};
  double* jacobian[1] = {jtheta.data()};
  map_cost->Evaluate(x_pointer, theta.data(), jacobian);
  FreeAnalysis out;
  out.x_scale = magnitudes(x);
  for (int j = 0; j < k; ++j)
    if (x[j] == 0.0) out.x_scale[j] = 0.5 * (space.upper()[j] - space.lower()[j]);
  const Eigen::MatrixXd scaled =
      magnitudes(P * theta).cwiseInverse().asDiagonal() * P * jtheta * out.x_scale.asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeFullV);
  out.singular_values = svd.singularValues();
  out.v = svd.matrixV();
  const double top = out.singular_values.size() > 0 ? out.singular_values[0] : 0.0;
  for (double s : out.singular_values)
    if (s > 1e-9 * top) ++out.rank;
  return out;
}

void baseUncertainty(const Model& structure, const ParameterSpace& space, const GcProblem& problem,
                     const BaseCoordinates& base, const RefineOptions& options,
                     RefineResult& result, ThreadPool& pool) {
  const bool with_start = options.estimate_initial_states;
  const Eigen::VectorXd theta = space.standardAt(result.x);
  const Eigen::MatrixXd& P = base.projection;  // its size checked by refineGc
  const int b = static_cast<int>(P.rows()), n = structure.numJoints();
  const int segments = problem.numSegments();
  result.beta = P * theta;
  const Eigen::MatrixXd lift = P.completeOrthogonalDecomposition().pseudoInverse();
  const BetaLift map{theta, result.beta, lift};
  double squared = 0.0;
  const Eigen::MatrixXd H = betaInformation(structure, map, problem, result.beta,
                                            result.initial_states, options, pool, squared);
  const int m = (with_start ? 4 : 2) * n;
  const long rows = static_cast<long>(segments) * m;
  const long unknowns = b + (with_start ? 2L * n * segments : 0L);
  result.degrees_of_freedom = static_cast<int>(std::max(rows - unknowns, 1L));
  result.sigma2 = squared / result.degrees_of_freedom;
  // cov = sigma^2 H^-1, through the symmetric eigendecomposition of the Jacobi-scaled H.
  Eigen::VectorXd d(b);
  for (int j = 0; j < b; ++j) d[j] = H(j, j) > 0.0 ? 1.0 / std::sqrt(H(j, j)) : 1.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(d.asDiagonal() * H * d.asDiagonal());
  const Eigen::VectorXd values = eigen.eigenvalues();
  const double largest = values.cwiseAbs().maxCoeff();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(b);
  result.information_rank = 0;
  for (int j = 0; j < b; ++j)
    if (values[j] > 1e-12 * largest) inverse[j] = 1.0 / values[j], ++result.information_rank;
  result.beta_covariance = result.sigma2 * d.asDiagonal() * eigen.eigenvectors() *
                           inverse.asDiagonal() * eigen.eigenvectors().transpose() * d.asDiagonal();
  result.beta_std_dev = result.beta_covariance.diagonal().cwiseMax(0.0).cwiseSqrt();

  // The directions of x that leave beta unchanged, at the estimate.
  if (space.numFree() == 0) return;
  const FreeAnalysis analysis = analyseFreeDirections(structure, space, P, result.x);
  result.beta_singular = analysis.singular_values;
  result.free_parameter_rank = analysis.rank;
  const std::vector<std::string> names = space.freeNames();
  for (int c = analysis.rank; c < space.numFree(); ++c) {
    const Eigen::VectorXd v = analysis.x_scale.asDiagonal() * analysis.v.col(c);
    const double lead = v.cwiseAbs().maxCoeff();
    std::vector<std::pair<std::string, double>> combination;
    for (int j = 0; j < space.numFree(); ++j)
      if (std::abs(v[j]) >= 1e-3 * lead) combination.emplace_back(names[j], v[j] / lead);
    std::sort(combination.begin(), combination.end(), [](const auto& a, const auto& b2) {
      return std::abs(a.second) > std::abs(b2.second);
    });
    // Sign: the leading coefficient positive.
    if (!combination.empty() && combination.front().second < 0)
      for (auto& entry : combination) entry.second = -entry.second;
    result.free_directions.push_back({combination});
  }
}

}  // namespace dynid
