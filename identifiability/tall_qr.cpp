#include "identifiability/tall_qr.hpp"

#include <algorithm>

#include <Eigen/QR>

#include "core/errors.hpp"

namespace dynid {

TallQr::TallQr(Eigen::Index cols, Eigen::Index block_rows)
    : cols_(cols),
      stack_(Eigen::MatrixXd::Zero(cols + std::max<Eigen::Index>(block_rows, 1), cols)) {}

void TallQr::add(const Eigen::Ref<const Eigen::MatrixXd>& rows) {
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
  Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(used);
  const Eigen::Index k = std::min(filled_, cols_);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(cols_, cols_);
  r.topRows(k) = qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
  stack_.topRows(cols_) = r;
  filled_ = cols_;
  pending_ = false;
}

Eigen::MatrixXd TallQr::r() {
  if (pending_) reduce();
  return stack_.topRows(cols_).triangularView<Eigen::Upper>();
}

}  // namespace dynid
