#include "identifiability/tall_qr.hpp"

#include <algorithm>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

TallQr::TallQr(Eigen::Index cols, Eigen::Index block_rows)
    : cols_(cols),
      stack_(Eigen::MatrixXd::Zero(cols + std::max<Eigen::Index>(block_rows, 1), cols)) {}

template <class Rows>
void TallQr::addRows(const Rows& rows) {
  if (rows.cols() != cols_)
    throw InputError("TallQr: rows with " + std::to_string(rows.cols()) + " columns, expected " +
                     std::to_string(cols_));
  Eigen::Index done = 0;
  while (done < rows.rows()) {
    const Eigen::Index take = std::min(rows.rows() - done, stack_.rows() - filled_);
    stack_.middleRows(filled_, take) = rows.middleRows(done, take);
    filled_ += take;
    done += take;
    pending_ = true;
    if (filled_ == stack_.rows()) reduce();
  }
  added_ += rows.rows();
}

void TallQr::add(const Eigen::Ref<const Eigen::MatrixXd>& rows) { addRows(rows); }
void TallQr::addRowMajor(const Eigen::Ref<const RowMajorMatrix>& rows) { addRows(rows); }

void TallQr::addRow(const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  if (row.size() != cols_)
    throw InputError("TallQr: a row of " + std::to_string(row.size()) + " entries, expected " +
                     std::to_string(cols_));
  stack_.row(filled_++) = row;
  ++added_;
  pending_ = true;
  if (filled_ == stack_.rows()) reduce();
}

void TallQr::reduce() {
  auto used = stack_.topRows(filled_);
  // Householder QR in panels of kPanel columns, each applied to the rest as one block reflector
  // (matrix-matrix products): Eigen's HouseholderQR uses 48-column panels, which for the 20-100
  // columns of a regressor leaves nearly all the work in rank-1 updates.
  constexpr Eigen::Index kPanel = 8;
  const Eigen::Index k = std::min(filled_, cols_);
  h_coeffs_.resize(k);
  temp_.resize(cols_ + 1);
  Eigen::Ref<Eigen::MatrixXd> qr(used);
  Eigen::internal::householder_qr_inplace_blocked<Eigen::Ref<Eigen::MatrixXd>,
                                                  Eigen::VectorXd>::run(qr, h_coeffs_, kPanel,
                                                                        temp_.data());
  for (Eigen::Index c = 0; c < cols_; ++c) {  // R on top, zeros below its diagonal
    const Eigen::Index keep = std::min(c + 1, k);
    stack_.col(c).segment(keep, cols_ - keep).setZero();
  }
  filled_ = cols_;
  pending_ = false;
}

Eigen::MatrixXd TallQr::r() {
  if (pending_) reduce();
  return stack_.topRows(cols_).triangularView<Eigen::Upper>();
}

}  // namespace dynid
