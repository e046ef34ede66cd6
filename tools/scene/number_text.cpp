#include "scene/number_text.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>

namespace xfdem::scene {
namespace {

__extension__ typedef unsigned __int128 Wide;

constexpr std::uint64_t kPow10[20] = {1ull,
                                      10ull,
                                      100ull,
                                      1000ull,
                                      10000ull,
                                      100000ull,
                                      1000000ull,
                                      10000000ull,
                                      100000000ull,
                                      1000000000ull,
                                      10000000000ull,
                                      100000000000ull,
                                      1000000000000ull,
                                      10000000000000ull,
                                      100000000000000ull,
                                      1000000000000000ull,
                                      10000000000000000ull,
                                      100000000000000000ull,
                                      1000000000000000000ull,
                                      10000000000000000000ull};
constexpr std::uint64_t kLow = kPow10[16], kHigh = kPow10[17];  // 17 digits: [1e16, 1e17)

/// 10^s, s in [0, 22] (10^22 < 2^74).
Wide pow10(int s) { return s < 20 ? Wide{kPow10[s]} : Wide{kPow10[19]} * kPow10[s - 19]; }

/// m · 2^e · 10^s (m < 2^53, s in [0, 22]) rounded to an integer, ties to
/// even, as printf rounds the exact value; false when it needs more than 128
/// bits. `floor` is the value before rounding.
bool scaled(std::uint64_t m, int e, int s, std::uint64_t& q, std::uint64_t& floor) {
  const Wide num = Wide{m} * pow10(s);  // < 2^53 · 2^74: fits
  if (e >= 0) {
    if (e > 8 || (num >> 119) != 0) return false;  // so that the shift cannot overflow
    const Wide whole = num << e;
    if ((whole >> 64) != 0) return false;
    q = floor = static_cast<std::uint64_t>(whole);
    return true;
  }
  const int k = -e;
  if (k >= 127) return false;
  const Wide whole = num >> k;
  if ((whole >> 64) != 0) return false;
  const Wide rest = num - (whole << k), half = Wide{1} << (k - 1);
  floor = static_cast<std::uint64_t>(whole);
  q = floor + ((rest > half || (rest == half && (floor & 1) != 0)) ? 1 : 0);
  return true;
}

/// The 17 digits of q in [1e16, 1e17) and the decimal exponent X of their
/// first digit, for a positive normal value; false outside the exact range.
bool digits17(double value, char (&digits)[17], int& exponent) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  if (biased == 0 || biased == 0x7ff) return false;  // zero, subnormal, infinite, NaN
  const std::uint64_t m = (bits & ((std::uint64_t{1} << 52) - 1)) | (std::uint64_t{1} << 52);
  const int e = biased - 1075;  // value = m · 2^e
  const int e2 = biased - 1023;  // 2^e2 <= value < 2^(e2 + 1)
  // floor(e2 · log10 2) (exact for |e2| < 1650): the exponent X is it or one more.
  int x = (e2 * 78913) >> 18;
  std::uint64_t q, floor;
  if (16 - x < 0 || 16 - x > 22 || !scaled(m, e, 16 - x, q, floor)) return false;
  if (floor >= kHigh) {  // X is one more: scale the exact value again (no double rounding)
    ++x;
    if (16 - x < 0 || !scaled(m, e, 16 - x, q, floor)) return false;
  }
  if (q == kHigh) {  // rounded up to the next power of ten
    q = kLow;
    ++x;
  }
  if (q < kLow || q >= kHigh) return false;
  for (int i = 16; i >= 0; --i) {
    digits[i] = static_cast<char>('0' + q % 10);
    q /= 10;
  }
  exponent = x;
  return true;
}

}  // namespace

char* write_g17(char* out, double value) {
  char digits[17];
  int x = 0;
  const bool negative = value < 0;
  if (!digits17(negative ? -value : value, digits, x))
    return std::to_chars(out, out + kG17Chars, value, std::chars_format::general, 17).ptr;
  char* p = out;
  if (negative) *p++ = '-';
  int last = 16;  // the last digit %g keeps: trailing zeros go
  while (last > 0 && digits[last] == '0') --last;
  if (x < -4 || x >= 17) {  // style e
    *p++ = digits[0];
    if (last > 0) {
      *p++ = '.';
      std::memcpy(p, digits + 1, static_cast<std::size_t>(last));
      p += last;
    }
    *p++ = 'e';
    *p++ = x < 0 ? '-' : '+';
    int a = x < 0 ? -x : x;
    if (a >= 100) {
      *p++ = static_cast<char>('0' + a / 100);
      a %= 100;
    }
    *p++ = static_cast<char>('0' + a / 10);
    *p++ = static_cast<char>('0' + a % 10);
  } else if (x >= 0) {  // style f: X + 1 digits before the point
    std::memcpy(p, digits, static_cast<std::size_t>(x + 1));
    p += x + 1;
    if (last > x) {
      *p++ = '.';
      std::memcpy(p, digits + x + 1, static_cast<std::size_t>(last - x));
      p += last - x;
    }
  } else {  // style f, 1e-4 <= value < 1: "0." and -X - 1 zeros before the digits
    *p++ = '0';
    *p++ = '.';
    for (int i = 0; i < -x - 1; ++i) *p++ = '0';
    std::memcpy(p, digits, static_cast<std::size_t>(last + 1));
    p += last + 1;
  }
  return p;
}

}  // namespace xfdem::scene
