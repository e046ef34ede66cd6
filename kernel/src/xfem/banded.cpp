#include "xfdem/xfem/banded.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

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

void SparseLdlt::analyse(const SymmetricBand& a, const std::vector<std::pair<int, int>>& extra) {
  ready_ = false;
  const int n = a.size();
  n_ = n;
  // The pattern, both triangles (what AMDOrdering reads), in the original numbering.
  std::vector<Eigen::Triplet<double, int>> entries;
  for (int i = 0; i < n; ++i)
    for (int j = a.first_column(i); j <= i; ++j)
      if (i == j || a.get(i, j) != 0.0) {
        entries.emplace_back(i, j, 1.0);
        if (i != j) entries.emplace_back(j, i, 1.0);
      }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> pattern(n, n);
  pattern.setFromTriplets(entries.begin(), entries.end());  // duplicates summed: the pattern is what counts
  perm_.assign(static_cast<std::size_t>(n), 0);
  {
    // On a's own nonzeros: the extra entries (faces that may close) do not
    // move the ordering, so a plate with unilateral faces is ordered as the
    // same plate with free ones.
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;  // new position k ← unknown order(k)
    Eigen::AMDOrdering<int>()(pattern, order);
    for (int k = 0; k < n; ++k) perm_[static_cast<std::size_t>(order.indices()[k])] = k;
  }
  if (!extra.empty()) {
    for (const auto& [i, j] : extra)
      if (i != j) entries.emplace_back(i, j, 1.0), entries.emplace_back(j, i, 1.0);
    pattern.setFromTriplets(entries.begin(), entries.end());
  }

  // P A Pᵀ's upper triangle by columns, rows ascending in each column.
  std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double, Eigen::ColMajor, int>::InnerIterator it(pattern, j); it; ++it)
      if (it.row() >= j)
        ++count[static_cast<std::size_t>(
                    std::max(perm_[static_cast<std::size_t>(it.row())], perm_[static_cast<std::size_t>(j)])) +
                1];
  for (int k = 0; k < n; ++k) count[static_cast<std::size_t>(k) + 1] += count[static_cast<std::size_t>(k)];
  a_start_ = count;
  const std::size_t stored = static_cast<std::size_t>(a_start_[static_cast<std::size_t>(n)]);
  a_row_.assign(stored, 0);
  a_orig_row_.assign(stored, 0);
  a_orig_col_.assign(stored, 0);
  a_value_.assign(stored, 0.0);
  std::vector<int> next(a_start_.begin(), a_start_.end() - 1);
  std::vector<std::pair<int, std::pair<int, int>>> column;
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double, Eigen::ColMajor, int>::InnerIterator it(pattern, j); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (row < j) continue;
      const int pi = perm_[static_cast<std::size_t>(row)], pj = perm_[static_cast<std::size_t>(j)];
      const std::size_t at = static_cast<std::size_t>(next[static_cast<std::size_t>(std::max(pi, pj))]++);
      a_row_[at] = std::min(pi, pj);
      a_orig_row_[at] = row;  // ≥ j: the stored (lower) entry of the profile
      a_orig_col_[at] = j;
    }
  for (int k = 0; k < n; ++k) {  // rows ascending within each column
    const std::size_t b = static_cast<std::size_t>(a_start_[static_cast<std::size_t>(k)]);
    const std::size_t e = static_cast<std::size_t>(a_start_[static_cast<std::size_t>(k) + 1]);
    column.clear();
    for (std::size_t p = b; p < e; ++p) column.push_back({a_row_[p], {a_orig_row_[p], a_orig_col_[p]}});
    std::sort(column.begin(), column.end());
    for (std::size_t p = b; p < e; ++p)
      a_row_[p] = column[p - b].first, a_orig_row_[p] = column[p - b].second.first,
      a_orig_col_[p] = column[p - b].second.second;
  }

  // Symbolic: the elimination tree and L's column counts (LDL's ldl_symbolic).
  parent_.assign(static_cast<std::size_t>(n), -1);
  flag_.assign(static_cast<std::size_t>(n), -1);
  count_.assign(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    flag_[static_cast<std::size_t>(k)] = k;
    for (int p = a_start_[static_cast<std::size_t>(k)]; p < a_start_[static_cast<std::size_t>(k) + 1]; ++p)
      for (int i = a_row_[static_cast<std::size_t>(p)]; i < k && flag_[static_cast<std::size_t>(i)] != k;
           i = parent_[static_cast<std::size_t>(i)]) {
        if (parent_[static_cast<std::size_t>(i)] == -1) parent_[static_cast<std::size_t>(i)] = k;
        ++count_[static_cast<std::size_t>(i)];
        flag_[static_cast<std::size_t>(i)] = k;
      }
  }
  l_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int k = 0; k < n; ++k)
    l_start_[static_cast<std::size_t>(k) + 1] = l_start_[static_cast<std::size_t>(k)] + count_[static_cast<std::size_t>(k)];
  const std::size_t lnz = static_cast<std::size_t>(l_start_[static_cast<std::size_t>(n)]);
  l_row_.assign(lnz, 0);
  l_value_.assign(lnz, 0.0);
  // Supernodes (fundamental: column c + 1 is c's parent and holds c's rows but c + 1).
  sn_first_.assign(1, 0);
  sn_row_start_.assign(1, 0);
  sn_rows_.clear();
  for (int c = 0; c < n;) {
    int l = c;
    while (l + 1 < n && l + 1 - c < kMaxSupernode && parent_[static_cast<std::size_t>(l)] == l + 1 &&
           count_[static_cast<std::size_t>(l)] == count_[static_cast<std::size_t>(l) + 1] + 1)
      ++l;
    sn_first_.push_back(l + 1);
    sn_row_start_.push_back(sn_row_start_.back() + count_[static_cast<std::size_t>(l)]);
    c = l + 1;
  }
  sn_rows_.assign(static_cast<std::size_t>(sn_row_start_.back()), 0);
  d_inv_.assign(static_cast<std::size_t>(n), 0.0);
  pattern_.assign(static_cast<std::size_t>(n), 0);
  y_.assign(static_cast<std::size_t>(n), 0.0);
  scale_.assign(static_cast<std::size_t>(n), 0.0);
  pivots_.assign(static_cast<std::size_t>(n), 0.0);
}

bool SparseLdlt::factor(const SymmetricBand& a) {
  ready_ = false;
  const int n = n_;
  if (a.size() != n) return false;
  for (int i = 0; i < n; ++i) {
    const double aii = a.get(i, i);
    if (!(aii > 0.0) || !std::isfinite(aii)) return false;
    scale_[static_cast<std::size_t>(perm_[static_cast<std::size_t>(i)])] = 1.0 / std::sqrt(aii);
  }
  // Gather P A Pᵀ, scaled: Â(i, j) = s_i A(i, j) s_j.
  const std::size_t stored = a_value_.size();
  for (std::size_t p = 0; p < stored; ++p) a_value_[p] = a.get(a_orig_row_[p], a_orig_col_[p]);
  for (int k = 0; k < n; ++k)
    for (int p = a_start_[static_cast<std::size_t>(k)]; p < a_start_[static_cast<std::size_t>(k) + 1]; ++p)
      a_value_[static_cast<std::size_t>(p)] *=
          scale_[static_cast<std::size_t>(a_row_[static_cast<std::size_t>(p)])] * scale_[static_cast<std::size_t>(k)];
  // Up-looking LDLᵀ (LDL's ldl_numeric, the numeric factor of Eigen's
  // SimplicialLDLT): row k of L from the triangular solve L₀ y = Â(0:k, k)
  // over the rows the elimination tree reaches from column k's entries.
  int* flag = flag_.data();
  int* pattern = pattern_.data();
  int* filled = count_.data();
  double* y = y_.data();
  double* d = pivots_.data();
  const int* parent = parent_.data();
  const int* lp = l_start_.data();
  int* li = l_row_.data();
  double* lx = l_value_.data();
  min_pivot_ = 1e300;
  max_pivot_ = 0.0;
  for (int k = 0; k < n; ++k) {
    y[k] = 0.0;
    int top = n;
    flag[k] = k;
    filled[k] = 0;
    for (int p = a_start_[static_cast<std::size_t>(k)]; p < a_start_[static_cast<std::size_t>(k) + 1]; ++p) {
      int i = a_row_[static_cast<std::size_t>(p)];
      y[i] += a_value_[static_cast<std::size_t>(p)];
      int len = 0;
      for (; flag[i] != k; i = parent[i]) {
        pattern[len++] = i;
        flag[i] = k;
      }
      while (len > 0) pattern[--top] = pattern[--len];
    }
    double dk = y[k];
    y[k] = 0.0;
    for (; top < n; ++top) {
      const int i = pattern[top];
      const double yi = y[i];
      y[i] = 0.0;
      const int end = lp[i] + filled[i];
      for (int p = lp[i]; p < end; ++p) y[li[p]] -= lx[p] * yi;
      const double lki = yi / d[i];
      dk -= lki * yi;
      li[end] = k;
      lx[end] = lki;
      ++filled[i];
    }
    if (!(dk > 0.0) || !std::isfinite(dk)) return false;
    d[k] = dk;
    min_pivot_ = std::min(min_pivot_, dk);
    max_pivot_ = std::max(max_pivot_, dk);
  }
  // Fold the scaling back as BandLdlt does: L'(i, j) = L(i, j) s_j / s_i, D'_i = D_i / s_i².
  for (int j = 0; j < n; ++j) {
    const double sj = scale_[static_cast<std::size_t>(j)];
    for (int p = lp[j]; p < lp[j + 1]; ++p) lx[p] *= sj / scale_[static_cast<std::size_t>(li[p])];
    d_inv_[static_cast<std::size_t>(j)] = sj * sj / d[j];
  }
  // The supernodes' rows: those of their last column (the same every factor).
  for (std::size_t sn = 0; sn + 1 < sn_first_.size(); ++sn) {
    const int l = sn_first_[sn + 1] - 1;
    for (int p = lp[l]; p < lp[l + 1]; ++p)
      sn_rows_[static_cast<std::size_t>(sn_row_start_[sn] + p - lp[l])] = li[p];
  }
  ready_ = true;
  return true;
}

namespace {

// The shared rows of a supernode of W columns (col[c]: column c's values
// from its first shared row on), W a compile-time constant.
template <int W>
void forward_shared(const double* const* col, const double* y, const int* rows, int m, double* work) {
  double yc[W];
  for (int c = 0; c < W; ++c) yc[c] = y[c];
  for (int t = 0; t < m; ++t) {
    double sum = col[0][t] * yc[0];
    for (int c = 1; c < W; ++c) sum += col[c][t] * yc[c];
    work[rows[t]] -= sum;
  }
}

template <int W>
void backward_shared(const double* const* col, const int* rows, int m, const double* work, double* z) {
  double zc[W];
  for (int c = 0; c < W; ++c) zc[c] = z[c];
  for (int t = 0; t < m; ++t) {
    const double v = work[rows[t]];
    for (int c = 0; c < W; ++c) zc[c] -= col[c][t] * v;
  }
  for (int c = 0; c < W; ++c) z[c] = zc[c];
}

template <class F>
void with_width(int w, F&& f) {
  switch (w) {
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 2: f(std::integral_constant<int, 2>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 4: f(std::integral_constant<int, 4>{}); break;
    case 5: f(std::integral_constant<int, 5>{}); break;
    case 6: f(std::integral_constant<int, 6>{}); break;
    case 7: f(std::integral_constant<int, 7>{}); break;
    default: f(std::integral_constant<int, 8>{}); break;
  }
}

}  // namespace

void SparseLdlt::solve(double* x, double* work) const {
  const int n = n_;
  const int* perm = perm_.data();
  const int* lp = l_start_.data();
  const double* lx = l_value_.data();
  const double* d_inv = d_inv_.data();
  const int* first = sn_first_.data();
  const int* row_start = sn_row_start_.data();
  const int* rows = sn_rows_.data();
  const int supernodes = static_cast<int>(sn_first_.size()) - 1;
  for (int i = 0; i < n; ++i) work[perm[i]] = x[i];
  // L y = P b, supernode by supernode: its own triangle column by column,
  // then each shared row once, with the supernode's columns in order.
  for (int s = 0; s < supernodes; ++s) {
    const int f = first[s], l = first[s + 1] - 1;
    for (int c = f; c < l; ++c) {
      const double yc = work[c];
      for (int r = c + 1; r <= l; ++r) work[r] -= lx[lp[c] + (r - c - 1)] * yc;
    }
    const int* sr = rows + row_start[s];
    const int m = row_start[s + 1] - row_start[s];
    const double* col[kMaxSupernode];
    const int w = l - f + 1;
    for (int c = 0; c < w; ++c) col[c] = lx + lp[f + c] + (w - 1 - c);
    with_width(w, [&](auto width) { forward_shared<width()>(col, work + f, sr, m, work); });
  }
  for (int j = 0; j < n; ++j) work[j] *= d_inv[j];
  // Lᵀ z = D⁻¹ y, supernodes in reverse: each column's dot product over the
  // shared rows (one pass for all of them), then the supernode's triangle.
  for (int s = supernodes - 1; s >= 0; --s) {
    const int f = first[s], l = first[s + 1] - 1;
    const int* sr = rows + row_start[s];
    const int m = row_start[s + 1] - row_start[s];
    const double* col[kMaxSupernode];
    double z[kMaxSupernode];
    const int w = l - f + 1;
    for (int c = 0; c < w; ++c) col[c] = lx + lp[f + c] + (w - 1 - c), z[c] = work[f + c];
    with_width(w, [&](auto width) { backward_shared<width()>(col, sr, m, work, z); });
    for (int c = w - 1; c >= 0; --c) {
      double zc = z[c];
      for (int r = f + c + 1; r <= l; ++r) zc -= lx[lp[f + c] + (r - f - c - 1)] * work[r];
      work[f + c] = zc;
    }
  }
  for (int i = 0; i < n; ++i) x[i] = work[perm[i]];
}

double SparseLdlt::bytes() const {
  return static_cast<double>(l_value_.size()) * sizeof(double) +
         static_cast<double>(sn_rows_.size() + sn_first_.size() + sn_row_start_.size() + l_start_.size()) *
             sizeof(int) +
         static_cast<double>(n_) * (sizeof(double) + sizeof(int));
}

}  // namespace xfdem::xfem
