// Symmetric band matrices and their LDLᵀ factorisation, sized once at build.
//
// The bar's unknowns are numbered node by node, so every matrix of the bar is
// banded with a half-bandwidth of 1 (plain or conforming mesh) or 3 (the cut
// element couples its four unknowns). Storage is the lower band, row by row:
// entry (i, j) with i − kd ≤ j ≤ i lives at data[i·(kd+1) + kd − (i − j)].
// resize() and factor() allocate; multiply(), quadratic() and solve() never do.
#pragma once
#include <vector>

namespace xfdem::xfem {

class SymmetricBand {
 public:
  /// n × n, half-bandwidth kd ≥ 0, all zero. Allocates.
  void resize(int n, int kd);
  [[nodiscard]] int size() const { return n_; }
  [[nodiscard]] int bandwidth() const { return kd_; }
  /// Entry (i, j) of the symmetric matrix; |i − j| ≤ kd.
  [[nodiscard]] double get(int i, int j) const;
  /// A(i, j) += value and, for i ≠ j, A(j, i) += value (one stored entry).
  void add(int i, int j, double value);
  /// y = A x (x and y of size n, distinct).
  void multiply(const double* x, double* y) const;
  /// y −= A x.
  void subtract_product(const double* x, double* y) const;
  /// xᵀ A x.
  [[nodiscard]] double quadratic(const double* x) const;
  [[nodiscard]] const std::vector<double>& data() const { return data_; }

 private:
  [[nodiscard]] int offset(int i, int j) const { return i * (kd_ + 1) + kd_ - (i - j); }
  int n_ = 0;
  int kd_ = 0;
  std::vector<double> data_;
};

/// LDLᵀ of a symmetric positive definite band matrix after symmetric Jacobi
/// scaling (S A S with S = diag(1/√A_ii)), which makes the factors of the
/// enriched system independent of how small a cut piece is. No pivoting: the
/// matrices of the bar are SPD by construction.
class BandLdlt {
 public:
  /// Factors A. Allocates. Returns false (and leaves the factor unusable) if a
  /// diagonal entry or a pivot is not positive, i.e. A is not SPD.
  bool factor(const SymmetricBand& a);
  /// x ← A⁻¹ x in place. No allocation.
  void solve(double* x) const;
  [[nodiscard]] int size() const { return n_; }
  [[nodiscard]] bool ready() const { return ready_; }
  /// Smallest and largest pivot of the scaled factorisation (diagnostics: their
  /// ratio bounds how much the scaled system amplifies round-off).
  [[nodiscard]] double min_pivot() const { return min_pivot_; }
  [[nodiscard]] double max_pivot() const { return max_pivot_; }

 private:
  int n_ = 0;
  int kd_ = 0;
  bool ready_ = false;
  double min_pivot_ = 0.0;
  double max_pivot_ = 0.0;
  std::vector<double> scale_;  // S_ii = 1/√A_ii
  std::vector<double> l_;      // unit lower factor, band layout of SymmetricBand
  std::vector<double> d_inv_;  // 1/D_ii
};

}  // namespace xfdem::xfem
