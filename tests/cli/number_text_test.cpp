// write_g17 (the CSV's number text) against printf's "%.17g", which defines
// it: random bit patterns over every exponent, random values over the range
// the exact path takes, ties at the 17th digit (dyadic fractions with 18
// significant digits), the neighbours of every power of ten where the
// exponent and the choice of style change, and the values std::to_chars
// takes (zeros, subnormals, infinities, NaN).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "scene/number_text.hpp"

namespace xfdem::scene {
namespace {

std::string printf_g17(double value) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.17g", value);
  return text;
}

std::string ours(double value) {
  char text[kG17Chars];
  return std::string(text, write_g17(text, value));
}

/// Compares both texts of value and -value; returns the number of mismatches.
int check(double value) {
  int bad = 0;
  for (const double v : {value, -value}) {
    const std::string expected = printf_g17(v), got = ours(v);
    if (expected != got) {
      if (++bad <= 5) ADD_FAILURE() << "value bits " << std::hexfloat << v << ": printf " << expected << ", write_g17 " << got;
    }
  }
  return bad;
}

TEST(NumberText, RandomBitPatterns) {
  std::mt19937_64 rng(1);
  int bad = 0;
  for (int k = 0; k < 300000; ++k) {
    const std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    bad += check(v);
  }
  EXPECT_EQ(bad, 0);
}

TEST(NumberText, RandomValuesOverTheExactRange) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> exponent(-8.0, 19.0), unit(0.0, 1.0);
  int bad = 0;
  for (int k = 0; k < 300000; ++k) bad += check(std::pow(10.0, exponent(rng)));
  // Few-digit decimals (0.1, 33.5, 1e-3: the CSV's time column and scene values)
  for (int k = 0; k < 100000; ++k) bad += check(static_cast<double>(rng() % 100000000) * std::pow(10.0, -static_cast<int>(rng() % 12)));
  for (int k = 0; k < 100000; ++k) bad += check(static_cast<double>(k) * 1e-3);
  EXPECT_EQ(bad, 0);
}

TEST(NumberText, TiesAtTheSeventeenthDigit) {
  // m · 2^-k has k digits after the point; those with 18 significant digits
  // ending in 5 are exact ties, which printf rounds to even.
  int bad = 0, ties = 0;
  for (int k = 1; k <= 90; ++k)
    for (std::uint64_t m = 1; m < 4096; m += 2) {
      const double v = std::ldexp(static_cast<double>(m), -k);
      char text[64];
      std::snprintf(text, sizeof(text), "%.40e", v);
      std::string mantissa(text, std::strchr(text, 'e'));
      while (mantissa.back() == '0') mantissa.pop_back();
      if (mantissa.size() == 19 /* d.ddd: 18 digits */ && mantissa.back() == '5') ++ties;
      bad += check(v);
    }
  EXPECT_GT(ties, 100);  // the sweep reaches ties
  EXPECT_EQ(bad, 0);
}

TEST(NumberText, AroundPowersOfTen) {
  int bad = 0;
  for (int p = -12; p <= 20; ++p) {
    const double ten = std::pow(10.0, p);
    double up = ten, down = ten;
    for (int k = 0; k < 40; ++k) {
      bad += check(up) + check(down);
      up = std::nextafter(up, std::numeric_limits<double>::infinity());
      down = std::nextafter(down, 0.0);
    }
  }
  EXPECT_EQ(bad, 0);
}

TEST(NumberText, ValuesLeftToToChars) {
  int bad = 0;
  for (const double v : {0.0, std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                         std::numeric_limits<double>::max(), std::numeric_limits<double>::infinity(), 1e300, 1e-300})
    bad += check(v);
  EXPECT_EQ(ours(std::numeric_limits<double>::quiet_NaN()), printf_g17(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_EQ(bad, 0);
}

}  // namespace
}  // namespace xfdem::scene
