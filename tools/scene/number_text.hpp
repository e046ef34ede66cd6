// The text of a double as printf's "%.17g" writes it (every digit that reads
// back bit-exact), the format of the CSV columns.
#pragma once

namespace xfdem::scene {

/// Longest text write_g17 writes ("-1.2345678901234567e-308").
inline constexpr int kG17Chars = 32;

/// Writes "%.17g" of `value` at `out` (at least kG17Chars long) and returns
/// the end of the text. Values whose 17 significant digits 128-bit integer
/// arithmetic gives exactly (normal numbers from 1e-6 to 1e17) are converted
/// here, the others by std::to_chars (which the standard defines by printf):
/// the CSV writes one of these per column and row, and for them this costs a
/// few times less than std::to_chars' arbitrary-precision path.
char* write_g17(char* out, double value);

}  // namespace xfdem::scene
