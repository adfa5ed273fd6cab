#include "identifiability/tall_qr.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/errors.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define DYNID_TALL_QR_AVX2 1
#include <immintrin.h>
#else
#define DYNID_TALL_QR_AVX2 0
#endif

namespace dynid {

namespace {

/// Columns updated together: their partial sums stay in registers while the rows stream by
/// (16 with AVX2, 8 otherwise); the rows are padded with zeros to a whole tile past any column.
constexpr Eigen::Index kTile = 16;
/// Rows reduced together: a tile of them (kGroup x kTile doubles, 16 kB) stays in the L1 cache
/// between the reflector's dot products and its update.
constexpr Eigen::Index kGroup = 128;

/// The Householder reflection H = I - tau [1; v] [1; v]^T that maps (R_cc, x) to (beta, 0), x
/// the k entries of B's column c (at `x`, `step` apart): sets R_cc = beta, writes v and returns
/// tau; returns 0 (and changes nothing) when there is nothing to annihilate (as Eigen's
/// makeHouseholder: a tail below the smallest normal double is taken as zero). `tail`, when not
/// negative, is |x|^2 already summed in the same order.
inline double reflector(double* rc, Eigen::Index c, const double* x, Eigen::Index step,
                        Eigen::Index k, double* v, double tail = -1.0) {
  if (tail < 0.0) {
    tail = 0.0;
    for (Eigen::Index i = 0; i < k; ++i) tail += x[i * step] * x[i * step];
  }
  if (tail <= std::numeric_limits<double>::min()) return 0.0;
  const double c0 = rc[c];
  double beta = std::sqrt(c0 * c0 + tail);
  if (c0 >= 0.0) beta = -beta;
  const double scale = 1.0 / (c0 - beta);
  for (Eigen::Index i = 0; i < k; ++i) v[i] = x[i * step] * scale;
  rc[c] = beta;
  return (beta - c0) / beta;
}

/// Two doubles as one value (GCC/Clang vector extension): one SSE2 register. Loaded and stored
/// with memcpy (any alignment).
using Vec2 = double __attribute__((vector_size(16)));
inline Vec2 load2(const double* p) {
  Vec2 x;
  std::memcpy(&x, p, sizeof x);
  return x;
}
inline void store2(double* p, Vec2 x) { std::memcpy(p, &x, sizeof x); }

/// Reduces the k rows at `b` (row-major, `stride` apart) into the upper triangular `r` (cols x
/// cols, the same stride, zero below the diagonal and in the padding): column by column, c's
/// reflector applied to the columns after c, a tile at a time. Entries of b at and left of the
/// column reduced are left stale: they are zero in exact arithmetic and never read again.
/// The padding's w is zero, so it stays zero.
void reducePortable(double* r, double* b, Eigen::Index k, Eigen::Index cols, Eigen::Index stride,
                    double* v) {
  for (Eigen::Index c = 0; c < cols; ++c) {
    double* rc = r + c * stride;
    const double tau = reflector(rc, c, b + c, stride, k, v);
    if (tau == 0.0) continue;
    for (Eigen::Index j0 = c + 1; j0 < cols; j0 += 8) {
      // w = tau (R(c, tile) + v^T B(:, tile)): two partial sums per column for the adder's latency.
      Vec2 even[4], odd[4];
      for (int t = 0; t < 4; ++t) {
        even[t] = load2(rc + j0 + 2 * t);
        odd[t] = Vec2{};
      }
      const double* row = b + j0;
      Eigen::Index i = 0;
      for (; i + 1 < k; i += 2, row += 2 * stride) {
        const double v0 = v[i], v1 = v[i + 1];
        for (int t = 0; t < 4; ++t) {
          even[t] += v0 * load2(row + 2 * t);
          odd[t] += v1 * load2(row + stride + 2 * t);
        }
      }
      if (i < k)
        for (int t = 0; t < 4; ++t) even[t] += v[i] * load2(row + 2 * t);
      Vec2 w[4];
      for (int t = 0; t < 4; ++t) {
        w[t] = tau * (even[t] + odd[t]);
        store2(rc + j0 + 2 * t, load2(rc + j0 + 2 * t) - w[t]);
      }
      double* target = b + j0;
      for (Eigen::Index row2 = 0; row2 < k; ++row2, target += stride) {
        const double vi = v[row2];
        for (int t = 0; t < 4; ++t) store2(target + 2 * t, load2(target + 2 * t) - vi * w[t]);
      }
    }
  }
}

#if DYNID_TALL_QR_AVX2
/// Reflectors c and c + 1 (rows c and c + 1 of R, their tails, their taus and v_(c+1)^T v_c).
struct TwoReflectors {
  double *r0, *r1;
  const double *v0, *v1;
  __m256d tau0, tau1, overlap;
};

/// H_(c+1) H_c applied to the 4 NV columns from j0 of R's rows and of the k rows at `b` (a tile's
/// first column, `stride` apart); `panel`, when given, receives the tile's first four columns
/// after the update, four doubles a row: the next two reflectors' columns, contiguous.
template <int NV>
__attribute__((target("avx2,fma"), always_inline)) inline void applyTwo(const TwoReflectors& h,
                                                                        double* b, Eigen::Index j0,
                                                                        Eigen::Index k,
                                                                        Eigen::Index stride,
                                                                        double* panel) {
  __m256d d0[NV], d1[NV];
  for (int t = 0; t < NV; ++t) d0[t] = d1[t] = _mm256_setzero_pd();
  const double* row = b;
  for (Eigen::Index i = 0; i < k; ++i, row += stride) {
    const __m256d a0 = _mm256_set1_pd(h.v0[i]), a1 = _mm256_set1_pd(h.v1[i]);
    for (int t = 0; t < NV; ++t) {
      const __m256d x = _mm256_loadu_pd(row + 4 * t);
      d0[t] = _mm256_fmadd_pd(a0, x, d0[t]);
      d1[t] = _mm256_fmadd_pd(a1, x, d1[t]);
    }
  }
  __m256d w0[NV], w1[NV];
  for (int t = 0; t < NV; ++t) {
    double* p0 = h.r0 + j0 + 4 * t;
    double* p1 = h.r1 + j0 + 4 * t;
    const __m256d r0 = _mm256_loadu_pd(p0), r1 = _mm256_loadu_pd(p1);
    w0[t] = _mm256_mul_pd(h.tau0, _mm256_add_pd(r0, d0[t]));
    w1[t] = _mm256_mul_pd(h.tau1, _mm256_fnmadd_pd(h.overlap, w0[t], _mm256_add_pd(r1, d1[t])));
    _mm256_storeu_pd(p0, _mm256_sub_pd(r0, w0[t]));
    _mm256_storeu_pd(p1, _mm256_sub_pd(r1, w1[t]));
  }
  double* target = b;
  for (Eigen::Index i = 0; i < k; ++i, target += stride) {
    const __m256d a0 = _mm256_set1_pd(h.v0[i]), a1 = _mm256_set1_pd(h.v1[i]);
    for (int t = 0; t < NV; ++t) {
      __m256d x = _mm256_loadu_pd(target + 4 * t);
      x = _mm256_fnmadd_pd(a0, w0[t], x);
      x = _mm256_fnmadd_pd(a1, w1[t], x);
      _mm256_storeu_pd(target + 4 * t, x);
    }
    if (panel) _mm256_storeu_pd(panel + 4 * i, _mm256_loadu_pd(target));
  }
}

/// reducePortable's result with AVX2 and FMA, two reflectors at a time (compact WY with two
/// columns): reflector c is applied to column c + 1 alone, then H_(c+1) H_c to the columns after
/// them in one pass over the rows, which halves the loads and stores per flop. With d = v^T B,
///   w_c = tau_c (R_c + d_c),   w_(c+1) = tau_(c+1) (R_(c+1) + d_(c+1) - (v_(c+1)^T v_c) w_c),
///   B -= v_c w_c + v_(c+1) w_(c+1),
/// 16 columns a tile, four doubles a register. The pair's two columns are read from `panel`
/// (contiguous, four doubles a row), which the previous pass's first tile filled.
__attribute__((target("avx2,fma"))) void reduceAvx2(double* r, double* b, Eigen::Index k,
                                                    Eigen::Index cols, Eigen::Index stride,
                                                    double* v0, double* v1, double* panel) {
  // panel: columns c and c + 1 (lanes 0 and 1 of four doubles a row), written by the previous
  // pass's first tile; copied from b for the first pair.
  for (Eigen::Index i = 0; i < k; ++i) {
    panel[4 * i] = b[i * stride];
    panel[4 * i + 1] = b[i * stride + 1];  // the padding when cols == 1
  }
  for (Eigen::Index c = 0; c < cols; c += 2) {
    double* rc0 = r + c * stride;
    const double tau0 = reflector(rc0, c, panel, 4, k, v0);
    if (c + 1 == cols) break;
    if (tau0 == 0.0) std::fill(v0, v0 + k, 0.0);
    // Reflector c on column c + 1 alone, summing the squares of the result: c + 1's tail.
    double w = rc0[c + 1];
    for (Eigen::Index i = 0; i < k; ++i) w += v0[i] * panel[4 * i + 1];
    w *= tau0;
    rc0[c + 1] -= w;
    double tail = 0.0;
    for (Eigen::Index i = 0; i < k; ++i) {
      double& x = panel[4 * i + 1];
      x -= v0[i] * w;
      tail += x * x;
    }
    double* rc1 = rc0 + stride;
    const double tau1 = reflector(rc1, c + 1, panel + 1, 4, k, v1, tail);
    if (c + 2 >= cols) break;
    if (tau0 == 0.0 && tau1 == 0.0) {  // nothing to apply: the next pair's columns from b
      for (Eigen::Index i = 0; i < k; ++i) {
        panel[4 * i] = b[i * stride + c + 2];
        panel[4 * i + 1] = b[i * stride + c + 3];
      }
      continue;
    }
    if (tau1 == 0.0) std::fill(v1, v1 + k, 0.0);
    double overlap = 0.0;  // v_(c+1)^T v_c
    for (Eigen::Index i = 0; i < k; ++i) overlap += v1[i] * v0[i];
    const TwoReflectors two{
        rc0, rc1, v0, v1, _mm256_set1_pd(tau0), _mm256_set1_pd(tau1), _mm256_set1_pd(overlap)};
    // Tiles of 16 columns, the last one as narrow as it can be (4, 8, 12 or 16); the first one
    // hands the next pair's columns over in `panel`.
    for (Eigen::Index j0 = c + 2; j0 < cols; j0 += 16) {
      double* next = j0 == c + 2 ? panel : nullptr;
      const Eigen::Index left = cols - j0;
      if (left > 12)
        applyTwo<4>(two, b + j0, j0, k, stride, next);
      else if (left > 8)
        applyTwo<3>(two, b + j0, j0, k, stride, next);
      else if (left > 4)
        applyTwo<2>(two, b + j0, j0, k, stride, next);
      else
        applyTwo<1>(two, b + j0, j0, k, stride, next);
    }
  }
}
#endif

}  // namespace

bool TallQr::avx2Available() {
#if DYNID_TALL_QR_AVX2
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
#else
  return false;
#endif
}

TallQr::TallQr(Eigen::Index cols, Eigen::Index block_rows, Kernel kernel)
    : cols_(cols),
      stride_(cols + kTile),
      block_rows_(std::max<Eigen::Index>(block_rows, 1)),
      r_(static_cast<std::size_t>(cols * stride_), 0.0),
      block_(static_cast<std::size_t>(block_rows_ * stride_), 0.0),
      v_(static_cast<std::size_t>(6 * kGroup), 0.0) {
  if (kernel == Kernel::kAvx2 && !avx2Available())
    throw InputError("TallQr: the AVX2 kernel was asked for, but this CPU has no AVX2 and FMA");
  avx2_ = kernel == Kernel::kAvx2 || (kernel == Kernel::kAuto && avx2Available());
}

void TallQr::reset() {
  std::fill(r_.begin(), r_.end(), 0.0);
  filled_ = 0;
  added_ = 0;
}

template <class Rows>
void TallQr::addRows(const Rows& rows) {
  if (rows.cols() != cols_)
    throw InputError("TallQr: rows with " + std::to_string(rows.cols()) + " columns, expected " +
                     std::to_string(cols_));
  for (Eigen::Index i = 0; i < rows.rows(); ++i) {
    Eigen::Map<Eigen::RowVectorXd>(block_.data() + filled_ * stride_, cols_) = rows.row(i);
    if (++filled_ == block_rows_) reduce();
  }
  added_ += rows.rows();
}

void TallQr::add(const Eigen::Ref<const Eigen::MatrixXd>& rows) { addRows(rows); }
void TallQr::addRowMajor(const Eigen::Ref<const RowMajorMatrix>& rows) { addRows(rows); }

void TallQr::addRow(const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  if (row.size() != cols_)
    throw InputError("TallQr: a row of " + std::to_string(row.size()) + " entries, expected " +
                     std::to_string(cols_));
  addRows(row);
}

void TallQr::commitRows(Eigen::Index k) {
  if (k < 0 || k > room())
    throw InputError("TallQr: " + std::to_string(k) + " rows committed, room for " +
                     std::to_string(room()));
  filled_ += k;
  added_ += k;
  if (filled_ == block_rows_) reduce();
}

void TallQr::reduce() {
  for (Eigen::Index start = 0; start < filled_; start += kGroup) {
    double* rows = block_.data() + start * stride_;
    const Eigen::Index k = std::min(kGroup, filled_ - start);
#if DYNID_TALL_QR_AVX2
    if (avx2_) {
      reduceAvx2(r_.data(), rows, k, cols_, stride_, v_.data(), v_.data() + kGroup,
                 v_.data() + 2 * kGroup);
      continue;
    }
#endif
    reducePortable(r_.data(), rows, k, cols_, stride_, v_.data());
  }
  filled_ = 0;
}

void TallQr::flush() {
  if (filled_ > 0) reduce();
}

Eigen::MatrixXd TallQr::r() {
  flush();
  Eigen::MatrixXd out(cols_, cols_);
  for (Eigen::Index i = 0; i < cols_; ++i)
    out.row(i) = Eigen::Map<const Eigen::RowVectorXd>(r_.data() + i * stride_, cols_);
  return out.triangularView<Eigen::Upper>();
}

Eigen::MatrixXd stackedTriangularFactor(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                        const Eigen::Ref<const Eigen::MatrixXd>& b) {
  const Eigen::Index n = a.cols();
  if (a.rows() != n || b.rows() != n || b.cols() != n)
    throw InputError("stacked triangular factors must be square and of one size (" +
                     std::to_string(a.rows()) + "x" + std::to_string(n) + " and " +
                     std::to_string(b.rows()) + "x" + std::to_string(b.cols()) + ")");
  Eigen::MatrixXd r = a.triangularView<Eigen::Upper>();
  Eigen::MatrixXd t = b.triangularView<Eigen::Upper>();  // column k: rows 0..k only, ever
  Eigen::VectorXd v(n);
  Eigen::RowVectorXd w(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    // Column k's entries to annihilate: T(0..k, k); the reflector maps (R_kk, them) to (beta, 0).
    const Eigen::Index m = k + 1;
    double diagonal = r(k, k);
    const double tau = reflector(&diagonal, 0, t.col(k).data(), 1, m, v.data());
    if (tau == 0.0) continue;
    r(k, k) = diagonal;
    t.col(k).head(m).setZero();
    const Eigen::Index rest = n - k - 1;
    if (rest == 0) continue;
    // [R(k, k+1:); T(0..k, k+1:)] -= tau [1; v] ([1; v]^T [R(k, k+1:); T(0..k, k+1:)]).
    auto tail = t.block(0, k + 1, m, rest);
    w.head(rest).noalias() = v.head(m).transpose() * tail;
    w.head(rest) += r.row(k).tail(rest);
    w.head(rest) *= tau;
    r.row(k).tail(rest) -= w.head(rest);
    tail.noalias() -= v.head(m) * w.head(rest);
  }
  return r;
}

}  // namespace dynid
