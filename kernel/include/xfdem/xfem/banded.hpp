// Symmetric matrices with a variable band (a "profile" or skyline), and their
// LDLᵀ factorisation, sized once at build.
//
// The bar's unknowns are numbered node by node, so row i of every matrix of the
// bar has nonzeros only from a column first(i) ≥ i − 3 on: i − 1 almost
// everywhere, i − 3 for the rows of the X-FEM cut element, whose four unknowns
// are all coupled. Storing each row from its own first column keeps the cut
// element from widening every other row. LDLᵀ creates no fill outside the
// profile. resize() allocates, and so does factor() unless the factor already
// holds one of a matrix of the same profile; multiply(), quadratic() and solve()
// never do.
//
// A profile whose rows are all short (at most kShortRow entries left of the
// diagonal: the bar's) is also described at resize() as runs of consecutive
// rows of one length, and the products and solve() walk it run by run
// with the row length a compile-time constant: the same operations in the same
// order as the general loops (so the same bits), without the loop control of
// inner loops one to three long. Wider profiles (the plate's) take the general
// loops.
#pragma once
#include <utility>
#include <vector>

namespace xfdem::xfem {

class SymmetricBand {
 public:
  /// n × n, row i stored from column first_column[i] (≤ i) to i; all zero. Allocates.
  void resize(int n, const std::vector<int>& first_column);
  /// Constant half-bandwidth kd: first column max(0, i − kd). Allocates.
  void resize(int n, int kd);
  [[nodiscard]] int size() const { return n_; }
  /// Largest i − first(i).
  [[nodiscard]] int bandwidth() const { return kd_; }
  [[nodiscard]] int first_column(int i) const { return first_[static_cast<std::size_t>(i)]; }
  /// Entry (i, j) of the symmetric matrix (0 outside the profile).
  [[nodiscard]] double get(int i, int j) const;
  /// A(i, j) += value and, for i ≠ j, A(j, i) += value (one stored entry). (i, j) must be in the profile.
  void add(int i, int j, double value);
  /// y = A x (x and y of size n, distinct).
  void multiply(const double* x, double* y) const;
  /// y −= A x.
  void subtract_product(const double* x, double* y) const;
  /// y ← −A x: the bits of zeroing y and subtract_product(x, y).
  void negated_product(const double* x, double* y) const;
  /// xᵀ A x.
  [[nodiscard]] double quadratic(const double* x) const;

  /// Rows at most this long left of the diagonal take the run-by-run kernels.
  static constexpr int kShortRow = 3;
  /// Whether the products and solve() take the run-by-run kernels.
  [[nodiscard]] bool short_rows() const { return !runs_.empty(); }
  /// The general loops, whatever the profile (the tests compare the two paths).
  void subtract_product_general(const double* x, double* y) const;

 private:
  friend class BandLdlt;
  /// Rows start .. start + count − 1, each with `length` entries left of the diagonal.
  struct Run {
    int start;
    int count;
    int length;
  };
  // Row i: entry (i, j) at data_[offset_[i] + j], offset_[i] = start of row i − first(i).
  int n_ = 0;
  int kd_ = 0;
  std::vector<int> first_;
  std::vector<long> offset_;
  std::vector<double> data_;
  std::vector<Run> runs_;  // empty unless every row is short
};

/// LDLᵀ of a symmetric positive definite profile matrix, computed on its Jacobi
/// scaling (S A S with S = diag(1/√A_ii)), whose pivots do not depend on how
/// small a cut piece is, then folded back into unit-lower L and D of A itself so
/// that a solve is two substitutions. No pivoting: the matrices of the bar are
/// SPD by construction.
class BandLdlt {
 public:
  /// Factors A. Allocates, unless this factor was computed before for a matrix
  /// of the same profile (then it reuses that storage). Returns false (and leaves the factor unusable) if a
  /// diagonal entry or a pivot is not positive, i.e. A is not SPD.
  bool factor(const SymmetricBand& a);
  /// x ← A⁻¹ x in place. No allocation.
  void solve(double* x) const;
  /// solve() through the general loops, whatever the profile.
  void solve_general(double* x) const;
  [[nodiscard]] int size() const { return l_.n_; }
  [[nodiscard]] bool ready() const { return ready_; }
  /// Smallest and largest pivot of the scaled factorisation (diagnostics: their
  /// ratio bounds how much the scaled system amplifies round-off).
  [[nodiscard]] double min_pivot() const { return min_pivot_; }
  [[nodiscard]] double max_pivot() const { return max_pivot_; }

 private:
  bool ready_ = false;
  double min_pivot_ = 0.0;
  double max_pivot_ = 0.0;
  SymmetricBand l_;            // unit lower factor of A (diagonal unused), same profile
  std::vector<double> d_inv_;  // 1/D_ii of A
  std::vector<double> scale_;  // scratch of factor(): 1/√A_ii
  std::vector<double> pivots_; // scratch of factor(): D of the scaled matrix
};

/// LDLᵀ of a symmetric positive definite matrix on a fill-reducing ordering
/// (Eigen's approximate minimum degree, AMDOrdering), in compressed columns
/// whose pattern is fixed by analyse(): the plate's factor. A profile factor
/// of a plate of n unknowns stores O(n^{3/2}) entries; on this ordering L
/// stores 0.69 as many at 10⁴ unknowns (docs/benchmarks.md, "2D plate").
///
/// Eigen's SimplicialLDLT allocates in factorize() (the permuted copy of the
/// matrix, and its scratch), so the numeric factor here is the up-looking
/// LDLᵀ of Eigen's SimplicialLDLT (Davis' LDL) into storage sized by
/// analyse(): factor() and solve() never allocate, and a re-factor of a
/// matrix on the same pattern (the plate's active-set changes) does it inside
/// a step. Computed on the Jacobi scaling, folded back, as BandLdlt. One
/// thread, a fixed order of operations: the same bits every run.
class SparseLdlt {
 public:
  /// The pattern: the nonzeros of `a` (lower triangle) and the pairs `extra`
  /// (i, j), entries that a later matrix may hold where `a` is zero; the
  /// ordering; L's pattern (elimination tree and column counts). Allocates.
  /// The ordering is computed on a's nonzeros alone (`extra` does not move it).
  void analyse(const SymmetricBand& a, const std::vector<std::pair<int, int>>& extra);
  /// Factors a, whose nonzeros must lie in the analysed pattern (its entries
  /// outside it are not read). No allocation. Returns false (the factor is
  /// then unusable) if a diagonal entry or a pivot is not positive.
  bool factor(const SymmetricBand& a);
  /// x ← A⁻¹ x; `work` holds size() doubles (scratch). No allocation.
  void solve(double* x, double* work) const;
  [[nodiscard]] int size() const { return n_; }
  [[nodiscard]] bool ready() const { return ready_; }
  /// The solve's supernodes (below).
  [[nodiscard]] int supernodes() const { return static_cast<int>(sn_first_.size()) - 1; }
  /// Stored entries of L below the diagonal.
  [[nodiscard]] long nonzeros() const { return static_cast<long>(l_row_.size()); }
  /// Bytes of the factor a solve reads: L's values, the supernodes' row
  /// indices and column starts, 1/D and the ordering.
  [[nodiscard]] double bytes() const;
  /// Smallest and largest pivot of the scaled factorisation (as BandLdlt's).
  [[nodiscard]] double min_pivot() const { return min_pivot_; }
  [[nodiscard]] double max_pivot() const { return max_pivot_; }
  /// The ordering: unknown i is row perm(i) of the factored matrix P A Pᵀ.
  [[nodiscard]] int perm(int i) const { return perm_[static_cast<std::size_t>(i)]; }

 private:
  bool ready_ = false;
  int n_ = 0;
  double min_pivot_ = 0.0;
  double max_pivot_ = 0.0;
  std::vector<int> perm_;  // original → permuted
  // P A Pᵀ's upper triangle by columns (column k: rows ≤ k, the diagonal
  // included), and where each value comes from in the original numbering.
  std::vector<int> a_start_, a_row_, a_orig_row_, a_orig_col_;
  std::vector<double> a_value_;
  // L by columns, unit diagonal not stored; the elimination tree.
  std::vector<int> l_start_, l_row_, parent_;
  // The solve's view of L: supernodes, runs of at most kMaxSupernode
  // consecutive columns f..l where column c's rows are c + 1 .. l then the
  // rows of column l (stored once, at sn_rows_[sn_row_start_[s]…]): the
  // solve reads one row index per row of a supernode, not per entry.
  static constexpr int kMaxSupernode = 8;
  std::vector<int> sn_first_, sn_row_start_, sn_rows_;
  std::vector<double> l_value_, d_inv_;
  // Scratch of factor().
  std::vector<int> flag_, pattern_, count_;
  std::vector<double> y_, scale_, pivots_;
};

}  // namespace xfdem::xfem
