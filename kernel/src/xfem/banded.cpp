#include "xfdem/xfem/banded.hpp"

#include <algorithm>
#include <cmath>

namespace xfdem::xfem {

void SymmetricBand::resize(int n, int kd) {
  n_ = n;
  kd_ = kd;
  data_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(kd + 1), 0.0);
}

double SymmetricBand::get(int i, int j) const {
  if (i < j) std::swap(i, j);
  if (i - j > kd_) return 0.0;
  return data_[static_cast<std::size_t>(offset(i, j))];
}

void SymmetricBand::add(int i, int j, double value) {
  if (i < j) std::swap(i, j);
  data_[static_cast<std::size_t>(offset(i, j))] += value;
}

void SymmetricBand::multiply(const double* x, double* y) const {
  for (int i = 0; i < n_; ++i) y[i] = 0.0;
  subtract_product(x, y);
  for (int i = 0; i < n_; ++i) y[i] = -y[i];
}

void SymmetricBand::subtract_product(const double* x, double* y) const {
  const double* a = data_.data();
  for (int i = 0; i < n_; ++i) {
    const double* row = a + i * (kd_ + 1) + kd_;  // row[−(i−j)] = A(i, j)
    double yi = row[0] * x[i];
    const int j0 = std::max(0, i - kd_);
    for (int j = j0; j < i; ++j) {
      const double aij = row[j - i];
      yi += aij * x[j];
      y[j] -= aij * x[i];
    }
    y[i] -= yi;
  }
}

double SymmetricBand::quadratic(const double* x) const {
  const double* a = data_.data();
  double off = 0.0;
  double diag = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double* row = a + i * (kd_ + 1) + kd_;
    diag += row[0] * x[i] * x[i];
    const int j0 = std::max(0, i - kd_);
    for (int j = j0; j < i; ++j) off += row[j - i] * x[j] * x[i];
  }
  return diag + 2.0 * off;
}

bool BandLdlt::factor(const SymmetricBand& a) {
  ready_ = false;
  n_ = a.size();
  kd_ = a.bandwidth();
  const int w = kd_ + 1;
  scale_.assign(static_cast<std::size_t>(n_), 0.0);
  d_inv_.assign(static_cast<std::size_t>(n_), 0.0);
  l_ = a.data();
  for (int i = 0; i < n_; ++i) {
    const double aii = a.get(i, i);
    if (!(aii > 0.0) || !std::isfinite(aii)) return false;
    scale_[static_cast<std::size_t>(i)] = 1.0 / std::sqrt(aii);
  }
  // Scale in place: Â(i, j) = s_i A(i, j) s_j.
  for (int i = 0; i < n_; ++i) {
    double* row = l_.data() + i * w + kd_;
    for (int j = std::max(0, i - kd_); j <= i; ++j) row[j - i] *= scale_[static_cast<std::size_t>(i)] * scale_[static_cast<std::size_t>(j)];
  }
  // Row-oriented LDLᵀ on the band: for j < i,
  //   L(i, j) = (Â(i, j) − Σ_{k<j} L(i, k) D_k L(j, k)) / D_j,  D_i = Â(i, i) − Σ_{k<i} L(i, k)² D_k.
  std::vector<double> d(static_cast<std::size_t>(n_), 0.0);
  min_pivot_ = 1e300;
  max_pivot_ = 0.0;
  for (int i = 0; i < n_; ++i) {
    double* row_i = l_.data() + i * w + kd_;
    const int j0 = std::max(0, i - kd_);
    for (int j = j0; j < i; ++j) {
      const double* row_j = l_.data() + j * w + kd_;
      double s = row_i[j - i];
      for (int k = j0; k < j; ++k) s -= row_i[k - i] * d[static_cast<std::size_t>(k)] * row_j[k - j];
      row_i[j - i] = s / d[static_cast<std::size_t>(j)];
    }
    double di = row_i[0];
    for (int k = j0; k < i; ++k) di -= row_i[k - i] * row_i[k - i] * d[static_cast<std::size_t>(k)];
    if (!(di > 0.0) || !std::isfinite(di)) return false;
    d[static_cast<std::size_t>(i)] = di;
    d_inv_[static_cast<std::size_t>(i)] = 1.0 / di;
    row_i[0] = 1.0;
    min_pivot_ = std::min(min_pivot_, di);
    max_pivot_ = std::max(max_pivot_, di);
  }
  ready_ = true;
  return true;
}

void BandLdlt::solve(double* x) const {
  const int w = kd_ + 1;
  const double* l = l_.data();
  const double* s = scale_.data();
  // A = S⁻¹ L D Lᵀ S⁻¹  ⇒  x = S L⁻ᵀ D⁻¹ L⁻¹ S b.
  for (int i = 0; i < n_; ++i) {
    const double* row = l + i * w + kd_;
    double xi = x[i] * s[i];
    for (int j = std::max(0, i - kd_); j < i; ++j) xi -= row[j - i] * x[j];
    x[i] = xi;
  }
  for (int i = 0; i < n_; ++i) x[i] *= d_inv_[static_cast<std::size_t>(i)];
  for (int i = n_ - 1; i >= 0; --i) {
    const double* row = l + i * w + kd_;
    const double xi = x[i];
    for (int j = std::max(0, i - kd_); j < i; ++j) x[j] -= row[j - i] * xi;
  }
  for (int i = 0; i < n_; ++i) x[i] *= s[i];
}

}  // namespace xfdem::xfem
