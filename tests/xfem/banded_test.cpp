// The band kernels: a profile of short rows (the bar's) is walked run by run
// with the row length fixed at compile time; that path must give the bits of
// the general loops, which the tests call directly, and both must solve the
// system (checked against Eigen's dense LDLᵀ of the same matrix).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "xfdem/bar.hpp"
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
