// A sampled joint trajectory: what a simulation produces and a dataset file holds.
#pragma once

#include <Eigen/Core>

namespace dynid {

/// Column k of each matrix is sample k (n x N); time has N entries [s], strictly increasing.
/// tau[:, k] is the torque applied from time[k] to time[k+1] (zero-order hold).
struct Trajectory {
  Eigen::VectorXd time;
  Eigen::MatrixXd q, dq, ddq, tau;

  int numSamples() const { return static_cast<int>(time.size()); }
  int numJoints() const { return static_cast<int>(q.rows()); }
  /// The mean sampling rate [Hz]: (samples - 1) over the time spanned; 0 with fewer than 2.
  double meanRate() const {
    const int n = numSamples();
    return n < 2 || !(time[n - 1] > time[0]) ? 0.0 : (n - 1) / (time[n - 1] - time[0]);
  }
  /// Allocates n x N zero matrices.
  void resize(int num_joints, int num_samples) {
    time.setZero(num_samples);
    q.setZero(num_joints, num_samples);
    dq.setZero(num_joints, num_samples);
    ddq.setZero(num_joints, num_samples);
    tau.setZero(num_joints, num_samples);
  }

  /// A copy of samples [first, first + count): a chunk, as a stream hands them over.
  /// Requires 0 <= first, 0 <= count and first + count <= numSamples().
  Trajectory samples(int first, int count) const {
    Trajectory out;
    out.time = time.segment(first, count);
    out.q = q.middleCols(first, count);
    out.dq = dq.middleCols(first, count);
    out.ddq = ddq.middleCols(first, count);
    out.tau = tau.middleCols(first, count);
    return out;
  }

  /// Keeps the first num_samples samples (at most numSamples()).
  void truncate(int num_samples) {
    time.conservativeResize(num_samples);
    for (Eigen::MatrixXd* m : {&q, &dq, &ddq, &tau}) m->conservativeResize(m->rows(), num_samples);
  }
};

}  // namespace dynid
