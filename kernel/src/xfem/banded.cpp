#include "xfdem/xfem/banded.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace xfdem::xfem {

namespace {

// The run-by-run kernels. `p` is the first stored entry of the run's first
// row; row start + r holds A(i, i − L .. i) at p + r (L + 1) .. p + r (L + 1) + L.
// Each is the general loop of its caller with the row length L fixed.

/// y −= A x over the run's rows; with kAssign, y[i] = 0 − (row i's sum)
/// instead of y[i] −= it: row i is the first to write y[i], so that is the
/// bits of zeroing y first.
template <int L, bool kAssign>
void product_run(const double* p, int start, int count, const double* x, double* y) {
  for (int r = 0; r < count; ++r, p += L + 1) {
    const int i = start + r;
    const double xi = x[i];
    double yi = p[L] * xi;
    for (int k = 0; k < L; ++k) {
      yi += p[k] * x[i - L + k];
      y[i - L + k] -= p[k] * xi;
    }
    if constexpr (kAssign)
      y[i] = 0.0 - yi;
    else
      y[i] -= yi;
  }
}

template <int L>
void forward_run(const double* p, int start, int count, double* x) {
  for (int r = 0; r < count; ++r, p += L + 1) {
    const int i = start + r;
    double xi = x[i];
    for (int k = 0; k < L; ++k) xi -= p[k] * x[i - L + k];
    x[i] = xi;
  }
}

template <int L>
void backward_run(const double* p, int start, int count, double* x) {
  for (int r = count - 1; r >= 0; --r) {
    const int i = start + r;
    const double* row = p + r * (L + 1);
    const double xi = x[i];
    for (int k = 0; k < L; ++k) x[i - L + k] -= row[k] * xi;
  }
}

/// f(std::integral_constant<int, L>{}) for the run's length L ≤ SymmetricBand::kShortRow.
template <class F>
void with_length(int length, F&& f) {
  static_assert(SymmetricBand::kShortRow == 3, "one case per short row length");
  switch (length) {
    case 0: f(std::integral_constant<int, 0>{}); break;
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 2: f(std::integral_constant<int, 2>{}); break;
    default: f(std::integral_constant<int, 3>{}); break;
  }
}

}  // namespace

void SymmetricBand::resize(int n, const std::vector<int>& first_column) {
  n_ = n;
  kd_ = 0;
  first_.assign(first_column.begin(), first_column.begin() + n);
  offset_.assign(static_cast<std::size_t>(n), 0);
  long next = 0;
  for (int i = 0; i < n; ++i) {
    const int f = std::clamp(first_[static_cast<std::size_t>(i)], 0, i);
    first_[static_cast<std::size_t>(i)] = f;
    kd_ = std::max(kd_, i - f);
    offset_[static_cast<std::size_t>(i)] = next - f;
    next += i - f + 1;
  }
  data_.assign(static_cast<std::size_t>(next), 0.0);
  runs_.clear();
  if (n > 0 && kd_ <= kShortRow) {
    for (int i = 0; i < n; ++i) {
      const int length = i - first_[static_cast<std::size_t>(i)];
      if (!runs_.empty() && runs_.back().length == length)
        ++runs_.back().count;
      else
        runs_.push_back({i, 1, length});
    }
  }
}

void SymmetricBand::resize(int n, int kd) {
  std::vector<int> first(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) first[static_cast<std::size_t>(i)] = std::max(0, i - kd);
  resize(n, first);
}

double SymmetricBand::get(int i, int j) const {
  if (i < j) std::swap(i, j);
  if (j < first_[static_cast<std::size_t>(i)]) return 0.0;
  return data_[static_cast<std::size_t>(offset_[static_cast<std::size_t>(i)] + j)];
}

void SymmetricBand::add(int i, int j, double value) {
  if (i < j) std::swap(i, j);
  data_[static_cast<std::size_t>(offset_[static_cast<std::size_t>(i)] + j)] += value;
}

void SymmetricBand::multiply(const double* x, double* y) const {
  for (int i = 0; i < n_; ++i) y[i] = 0.0;
  subtract_product(x, y);
  for (int i = 0; i < n_; ++i) y[i] = -y[i];
}

void SymmetricBand::subtract_product(const double* x, double* y) const {
  if (runs_.empty()) {
    subtract_product_general(x, y);
    return;
  }
  const double* a = data_.data();
  for (const Run& run : runs_) {
    const double* p = a + offset_[static_cast<std::size_t>(run.start)] + first_[static_cast<std::size_t>(run.start)];
    with_length(run.length, [&](auto length) { product_run<length(), false>(p, run.start, run.count, x, y); });
  }
}

void SymmetricBand::negated_product(const double* x, double* y) const {
  if (runs_.empty()) {
    for (int i = 0; i < n_; ++i) y[i] = 0.0;
    subtract_product_general(x, y);
    return;
  }
  const double* a = data_.data();
  for (const Run& run : runs_) {
    const double* p = a + offset_[static_cast<std::size_t>(run.start)] + first_[static_cast<std::size_t>(run.start)];
    with_length(run.length, [&](auto length) { product_run<length(), true>(p, run.start, run.count, x, y); });
  }
}

void SymmetricBand::subtract_product_general(const double* x, double* y) const {
  const double* a = data_.data();
  const int* first = first_.data();
  const long* offset = offset_.data();
  for (int i = 0; i < n_; ++i) {
    const double* row = a + offset[i];  // row[j] = A(i, j)
    const double xi = x[i];
    double yi = row[i] * xi;
    for (int j = first[i]; j < i; ++j) {
      yi += row[j] * x[j];
      y[j] -= row[j] * xi;
    }
    y[i] -= yi;
  }
}

double SymmetricBand::quadratic(const double* x) const {
  double off = 0.0;
  double diag = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double* row = data_.data() + offset_[static_cast<std::size_t>(i)];
    diag += row[i] * x[i] * x[i];
    for (int j = first_[static_cast<std::size_t>(i)]; j < i; ++j) off += row[j] * x[j] * x[i];
  }
  return diag + 2.0 * off;
}

bool BandLdlt::factor(const SymmetricBand& a) {
  ready_ = false;
  // Copies and assign() reuse the storage of an earlier factor of the same
  // profile, so refactoring (the bar's event substeps) does not allocate.
  l_ = a;
  const int n = a.size();
  std::vector<double>& scale = scale_;
  scale.assign(static_cast<std::size_t>(n), 0.0);
  d_inv_.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    const double aii = a.get(i, i);
    if (!(aii > 0.0) || !std::isfinite(aii)) return false;
    scale[static_cast<std::size_t>(i)] = 1.0 / std::sqrt(aii);
  }
  auto row = [&](int i) { return l_.data_.data() + l_.offset_[static_cast<std::size_t>(i)]; };
  auto first = [&](int i) { return l_.first_[static_cast<std::size_t>(i)]; };
  auto s = [&](int i) { return scale[static_cast<std::size_t>(i)]; };
  // Scale in place: Â(i, j) = s_i A(i, j) s_j.
  for (int i = 0; i < n; ++i)
    for (int j = first(i); j <= i; ++j) row(i)[j] *= s(i) * s(j);
  // Row-oriented LDLᵀ within the profile: for j < i,
  //   L(i, j) = (Â(i, j) − Σ_k L(i, k) D_k L(j, k)) / D_j,  D_i = Â(i, i) − Σ_{k<i} L(i, k)² D_k,
  // k running over the columns both rows store.
  std::vector<double>& d = pivots_;
  d.assign(static_cast<std::size_t>(n), 0.0);
  min_pivot_ = 1e300;
  max_pivot_ = 0.0;
  for (int i = 0; i < n; ++i) {
    double* ri = row(i);
    for (int j = first(i); j < i; ++j) {
      const double* rj = row(j);
      double sum = ri[j];
      for (int k = std::max(first(i), first(j)); k < j; ++k) sum -= ri[k] * d[static_cast<std::size_t>(k)] * rj[k];
      ri[j] = sum / d[static_cast<std::size_t>(j)];
    }
    double di = ri[i];
    for (int k = first(i); k < i; ++k) di -= ri[k] * ri[k] * d[static_cast<std::size_t>(k)];
    if (!(di > 0.0) || !std::isfinite(di)) return false;
    d[static_cast<std::size_t>(i)] = di;
    ri[i] = 1.0;
    min_pivot_ = std::min(min_pivot_, di);
    max_pivot_ = std::max(max_pivot_, di);
  }
  // Fold the scaling back: S⁻¹ L D Lᵀ S⁻¹ = L' D' L'ᵀ with L'(i, j) = L(i, j) s_j / s_i
  // and D'_i = D_i / s_i², so a solve is two substitutions and nothing else.
  for (int i = 0; i < n; ++i) {
    for (int j = first(i); j < i; ++j) row(i)[j] *= s(j) / s(i);
    d_inv_[static_cast<std::size_t>(i)] = s(i) * s(i) / d[static_cast<std::size_t>(i)];
  }
  ready_ = true;
  return true;
}

void BandLdlt::solve(double* x) const {
  const std::vector<SymmetricBand::Run>& runs = l_.runs_;
  if (runs.empty()) {
    solve_general(x);
    return;
  }
  const int n = l_.n_;
  const double* l = l_.data_.data();
  const long* offset = l_.offset_.data();
  const int* first = l_.first_.data();
  for (const SymmetricBand::Run& run : runs) {  // L y = b
    const double* p = l + offset[run.start] + first[run.start];
    with_length(run.length, [&](auto length) { forward_run<length()>(p, run.start, run.count, x); });
  }
  const double* d_inv = d_inv_.data();
  for (int i = 0; i < n; ++i) x[i] *= d_inv[i];
  for (auto run = runs.rbegin(); run != runs.rend(); ++run) {  // Lᵀ x = D⁻¹ y
    const double* p = l + offset[run->start] + first[run->start];
    with_length(run->length, [&](auto length) { backward_run<length()>(p, run->start, run->count, x); });
  }
}

void BandLdlt::solve_general(double* x) const {
  const int n = l_.n_;
  const double* l = l_.data_.data();
  const int* first = l_.first_.data();
  const long* offset = l_.offset_.data();
  for (int i = 0; i < n; ++i) {  // L y = b
    const double* row = l + offset[i];
    double xi = x[i];
    for (int j = first[i]; j < i; ++j) xi -= row[j] * x[j];
    x[i] = xi;
  }
  for (int i = 0; i < n; ++i) x[i] *= d_inv_[static_cast<std::size_t>(i)];
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = D⁻¹ y, column by column
    const double* row = l + offset[i];
    const double xi = x[i];
    for (int j = first[i]; j < i; ++j) x[j] -= row[j] * xi;
  }
}

}  // namespace xfdem::xfem
