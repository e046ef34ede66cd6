// The band kernels: a profile of short rows (the bar's) is walked run by run
// with the row length fixed at compile time; that path must give the bits of
// the general loops, which the tests call directly, and both must solve the
// system (checked against Eigen's dense LDLᵀ of the same matrix).
// SparseLdlt (the plate's factor) against Eigen's dense LDLᵀ and its SimplicialLDLT.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <utility>
#include <random>
#include <vector>

#include "xfdem/bar.hpp"
#include "xfdem/platform/alloc_guard.hpp"
#include "xfdem/xfem/banded.hpp"
#include "xfem/reference.hpp"

namespace {

using xfdem::xfem::BandLdlt;
using xfdem::xfem::SymmetricBand;

/// A random SPD matrix (diagonally dominant) with row i stored from a random
/// first column in [i − max_length, i].
SymmetricBand random_band(std::mt19937_64& rng, int n, int max_length) {
  std::uniform_int_distribution<int> length(0, max_length);
  std::vector<int> first(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) first[static_cast<std::size_t>(i)] = std::max(0, i - length(rng));
  SymmetricBand a;
  a.resize(n, first);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> row_abs(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = a.first_column(i); j < i; ++j) {
      const double v = value(rng);
      a.add(i, j, v);
      row_abs[static_cast<std::size_t>(i)] += std::fabs(v);
      row_abs[static_cast<std::size_t>(j)] += std::fabs(v);
    }
  for (int i = 0; i < n; ++i) a.add(i, i, row_abs[static_cast<std::size_t>(i)] + 0.5 + std::fabs(value(rng)));
  return a;
}

/// Random entries of widely different sizes, with exact zeros of both signs.
std::vector<double> random_vector(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::uniform_int_distribution<int> kind(0, 9);
  std::vector<double> x(static_cast<std::size_t>(n));
  for (double& v : x) {
    const int k = kind(rng);
    v = k == 0 ? 0.0 : k == 1 ? -0.0 : std::ldexp(value(rng), exponent(rng));
  }
  return x;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
  return true;
}

TEST(Banded, ShortRowKernelsGiveTheGeneralLoopsBits) {
  std::mt19937_64 rng(20261125);
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 80);
    const int max_length = static_cast<int>(rng() % (SymmetricBand::kShortRow + 1));
    const SymmetricBand a = random_band(rng, n, max_length);
    ASSERT_TRUE(a.short_rows());
    BandLdlt f;
    ASSERT_TRUE(f.factor(a));
    const std::vector<double> x = random_vector(rng, n);
    std::vector<double> y_fast = random_vector(rng, n);
    std::vector<double> y_general = y_fast;
    a.subtract_product(x.data(), y_fast.data());
    a.subtract_product_general(x.data(), y_general.data());
    EXPECT_TRUE(same_bits(y_fast, y_general)) << "subtract_product, trial " << trial;
    std::vector<double> s_fast = x, s_general = x;
    f.solve(s_fast.data());
    f.solve_general(s_general.data());
    EXPECT_TRUE(same_bits(s_fast, s_general)) << "solve, trial " << trial;
    // And the solve solves: against the dense matrix, to round-off of a
    // diagonally dominant system.
    const Eigen::MatrixXd dense = xfdem::test::dense(a);
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(x.data(), n);
    const Eigen::VectorXd sol = Eigen::Map<const Eigen::VectorXd>(s_fast.data(), n);
    EXPECT_LE((dense * sol - b).norm(), 1e-13 * b.norm() + 1e-300) << "trial " << trial;
    ++checked;
  }
  EXPECT_EQ(checked, 400);
}

TEST(Banded, WideProfilesTakeTheGeneralLoops) {
  // The plate's profiles are wider than kShortRow: nothing changes for them.
  std::mt19937_64 rng(7);
  SymmetricBand a;
  a.resize(50, SymmetricBand::kShortRow + 1);
  EXPECT_FALSE(a.short_rows());
  const SymmetricBand b = random_band(rng, 60, 12);
  EXPECT_EQ(b.short_rows(), b.bandwidth() <= SymmetricBand::kShortRow);
}

TEST(Banded, TheBarsMatricesTakeTheShortRowKernels) {
  // Case II's rod: 30 X-FEM elements with a tied interface (the cut element's
  // four unknowns coupled), and the conforming mesh.
  for (const auto method : {xfdem::BarDesc::Method::xfem, xfdem::BarDesc::Method::fem}) {
    xfdem::BarDesc d;
    d.length = 30.0;
    d.youngs_modulus = 3e7;
    d.area = 0.4;
    d.density = 2500.0;
    d.elements = 30;
    d.method = method;
    d.dt = 1e-3;
    d.interface = xfdem::BarInterfaceDesc{14.5, 1e9, xfdem::BarInterfaceDesc::Behaviour::tied};
    xfdem::BarModel m;
    xfdem::BarState s;
    xfdem::BarWorkspace w;
    ASSERT_TRUE(xfdem::build_bar(d, m, s, w).ok());
    EXPECT_TRUE(m.stiffness.short_rows());
    EXPECT_TRUE(m.mass.short_rows());
    std::mt19937_64 rng(11);
    const std::vector<double> x = random_vector(rng, m.dofs);
    std::vector<double> fast = x, general = x;
    m.effective_closed.solve(fast.data());
    m.effective_closed.solve_general(general.data());
    EXPECT_TRUE(same_bits(fast, general));
  }
}

}  // namespace

// ---- SparseLdlt: the plate's factor -------------------------------------------

namespace sparse {

using xfdem::xfem::SparseLdlt;

/// A random SPD matrix (diagonally dominant) in a profile of rows up to
/// `max_length` long, each entry left of the diagonal nonzero with probability
/// `fill`; the zero entries are listed in `zeros` (pairs a re-factor may fill).
SymmetricBand random_sparse(std::mt19937_64& rng, int n, int max_length, double fill,
                            std::vector<std::pair<int, int>>* zeros = nullptr) {
  std::vector<int> first(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) first[static_cast<std::size_t>(i)] = std::max(0, i - max_length);
  SymmetricBand a;
  a.resize(n, first);
  std::uniform_real_distribution<double> value(-1.0, 1.0), coin(0.0, 1.0);
  std::vector<double> row_abs(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = a.first_column(i); j < i; ++j) {
      if (coin(rng) > fill) {
        if (zeros != nullptr && coin(rng) < 0.05) zeros->emplace_back(i, j);
        continue;
      }
      const double v = value(rng);
      a.add(i, j, v);
      row_abs[static_cast<std::size_t>(i)] += std::fabs(v);
      row_abs[static_cast<std::size_t>(j)] += std::fabs(v);
    }
  for (int i = 0; i < n; ++i) a.add(i, i, row_abs[static_cast<std::size_t>(i)] + 0.5 + std::fabs(value(rng)));
  return a;
}

Eigen::MatrixXd dense(const SymmetricBand& a) {
  const int n = a.size();
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = a.get(i, j);
  return m;
}

/// max |x − y| / max |y|.
double relative_difference(const std::vector<double>& x, const Eigen::VectorXd& y) {
  double diff = 0.0, scale = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    diff = std::max(diff, std::fabs(x[k] - y(static_cast<Eigen::Index>(k))));
    scale = std::max(scale, std::fabs(y(static_cast<Eigen::Index>(k))));
  }
  return diff / scale;
}

}  // namespace sparse

using xfdem::xfem::SparseLdlt;

// The solve agrees with Eigen's dense LDLᵀ, and L holds as many entries as
// Eigen's SimplicialLDLT on the same ordering (AMDOrdering) of the same pattern.
TEST(SparseLdlt, SolvesAsEigensDenseLdltWithEigensFill) {
  std::mt19937_64 rng(41);
  for (const int n : {1, 2, 17, 300}) {
    const SymmetricBand a = sparse::random_sparse(rng, n, 40, 0.15);
    SparseLdlt f;
    f.analyse(a, {});
    ASSERT_TRUE(f.factor(a));
    std::vector<double> b(static_cast<std::size_t>(n)), x, work(static_cast<std::size_t>(n));
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    for (double& v : b) v = value(rng);
    x = b;
    f.solve(x.data(), work.data());
    const Eigen::MatrixXd m = sparse::dense(a);
    const Eigen::VectorXd expected = m.ldlt().solve(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
    EXPECT_LE(sparse::relative_difference(x, expected), 1e-13) << "n = " << n;

    Eigen::SparseMatrix<double> s = m.sparseView();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> eigen(s);
    ASSERT_EQ(eigen.info(), Eigen::Success);
    EXPECT_EQ(f.nonzeros(), eigen.matrixL().nestedExpression().nonZeros()) << "n = " << n;
    std::printf("sparse LDLt, n = %d: %ld entries in L (%d supernodes), profile %ld, solve vs dense %.3g\n", n,
                f.nonzeros(), f.supernodes(),
                [&] {
                  long e = 0;
                  for (int i = 0; i < n; ++i) e += i - a.first_column(i);
                  return e;
                }(),
                sparse::relative_difference(x, expected));
  }
}

// The plate's re-factor: the pattern holds pairs where the analysed matrix is
// zero; a matrix with values there factors on it without allocating, and
// solves as the dense LDLᵀ (so does the first matrix, with and without the
// extra pairs in its pattern). Solves repeat bit for bit.
TEST(SparseLdlt, RefactorsOnTheFixedPatternWithoutAllocating) {
  std::mt19937_64 rng(7);
  const int n = 200;
  std::vector<std::pair<int, int>> zeros;
  const SymmetricBand a = sparse::random_sparse(rng, n, 30, 0.1, &zeros);
  ASSERT_FALSE(zeros.empty());
  SymmetricBand b = a;
  for (const auto& [i, j] : zeros) {
    b.add(i, j, 0.25);
    b.add(i, i, 0.25);
    b.add(j, j, 0.25);
  }
  SparseLdlt plain, with_extra;
  plain.analyse(a, {});
  with_extra.analyse(a, zeros);
  ASSERT_TRUE(plain.factor(a));
  ASSERT_TRUE(with_extra.factor(a));
  std::vector<double> rhs(static_cast<std::size_t>(n)), x1, x2, work(static_cast<std::size_t>(n));
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (double& v : rhs) v = value(rng);
  x1 = rhs;
  x2 = rhs;
  plain.solve(x1.data(), work.data());
  with_extra.solve(x2.data(), work.data());
  const Eigen::VectorXd for_a = sparse::dense(a).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(rhs.data(), n));
  EXPECT_LE(sparse::relative_difference(x1, for_a), 1e-13);
  EXPECT_LE(sparse::relative_difference(x2, for_a), 1e-13);

  bool ok = false;
  {
    xfdem::platform::AllocationCounter counter;
    ok = with_extra.factor(b);
    x2 = rhs;  // same size: no allocation
    with_extra.solve(x2.data(), work.data());
    EXPECT_EQ(counter.allocations(), 0u);
  }
  ASSERT_TRUE(ok);
  const Eigen::VectorXd expected = sparse::dense(b).ldlt().solve(Eigen::Map<const Eigen::VectorXd>(rhs.data(), n));
  EXPECT_LE(sparse::relative_difference(x2, expected), 1e-13);
  std::vector<double> again = rhs;
  with_extra.solve(again.data(), work.data());
  for (int k = 0; k < n; ++k)
    EXPECT_EQ(std::bit_cast<std::uint64_t>(again[k]), std::bit_cast<std::uint64_t>(x2[k]));
}

// Not SPD: a diagonal entry that is not positive, or a pivot that is not
// (positive diagonal, indefinite), is refused.
TEST(SparseLdlt, RefusesAMatrixThatIsNotPositiveDefinite) {
  SymmetricBand a;
  a.resize(3, 2);
  a.add(0, 0, 1.0);
  a.add(1, 1, -1.0);
  a.add(2, 2, 1.0);
  SparseLdlt f;
  f.analyse(a, {});
  EXPECT_FALSE(f.factor(a));
  EXPECT_FALSE(f.ready());
  SymmetricBand b;
  b.resize(2, 1);
  b.add(0, 0, 1.0);
  b.add(1, 1, 1.0);
  b.add(1, 0, 2.0);  // eigenvalues 3 and −1
  f.analyse(b, {});
  EXPECT_FALSE(f.factor(b));
}
