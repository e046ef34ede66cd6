// Strict reading of scene JSON: every value is read through an ObjectReader,
// which knows the dotted path of the object ("dem.particles.0"), checks types,
// finiteness and ranges, and at finish() rejects every key nobody read. Errors
// are SceneError exceptions whose message names the key; the command line turns
// them into one line on stderr and a non-zero exit, before anything is written.
#pragma once
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace xfdem::scene {

using Json = nlohmann::json;

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A value as a message prints it: every digit that reads back bit-exact ("%.17g").
std::string number(double x);

/// Allowed interval for a number. Open ends exclude the bound.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;
};
inline constexpr Range kAny{};
inline constexpr Range kPositive{0.0, std::numeric_limits<double>::infinity(), true, false};
inline constexpr Range kNonNegative{0.0, std::numeric_limits<double>::infinity(), false, false};

/// "a.b" + "c" -> "a.b.c"; "" + "c" -> "c".
std::string join_path(const std::string& parent, const std::string& key);

class ObjectReader {
 public:
  /// Throws SceneError if `value` is not an object.
  ObjectReader(const Json& value, std::string path);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] bool has(const char* key) const;
  /// Full dotted path of a key of this object, for messages.
  [[nodiscard]] std::string key_path(const char* key) const { return join_path(path_, key); }

  double real(const char* key, Range range = kAny);
  double real_or(const char* key, double fallback, Range range = kAny);
  long long integer(const char* key, long long lo, long long hi);
  long long integer_or(const char* key, long long fallback, long long lo, long long hi);
  bool boolean_or(const char* key, bool fallback);
  std::string text(const char* key);
  /// A string that must be one of `options`.
  std::string choice(const char* key, std::initializer_list<const char*> options);
  std::string choice_or(const char* key, const char* fallback, std::initializer_list<const char*> options);
  /// An array of exactly `size` finite numbers.
  std::vector<double> vector(const char* key, std::size_t size, Range range = kAny);
  ObjectReader object(const char* key);
  /// The elements of an array (each with its own path "key.i").
  std::vector<std::pair<const Json*, std::string>> array(const char* key);
  /// The raw value of a key (marked as read).
  const Json& raw(const char* key);

  /// Throws SceneError naming the first key that was not read.
  void finish() const;

  /// Throws SceneError "<path>: <what>".
  [[noreturn]] void fail(const char* key, const std::string& what) const;

 private:
  const Json& get(const char* key);
  double check_real(const Json& value, const std::string& where, Range range) const;

  const Json& value_;
  std::string path_;
  std::set<std::string> read_;
};

/// Checks that a JSON value is a finite number inside range; `where` names it.
double read_real(const Json& value, const std::string& where, Range range = kAny);

/// Parses JSON text as nlohmann::json does, but a key given twice in one
/// object, at any depth, is a SceneError naming it ("scene key
/// 'dem.particles.0.mass': given twice") instead of the last one silently
/// winning. `path` is the dotted key of the text's value (an override's key;
/// empty for a whole scene). Syntax errors are Json::parse_error as usual.
Json parse_json(const std::string& text, const std::string& path, bool ignore_comments);

}  // namespace xfdem::scene
