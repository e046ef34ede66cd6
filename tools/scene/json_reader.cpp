#include <cstdio>
#include "scene/json_reader.hpp"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

namespace xfdem::scene {

std::string number(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.17g", x);
  return buffer;
}

std::string join_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

namespace {
std::string type_name(const Json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  return "an object";
}
std::string describe_range(Range r) {
  std::string s;
  if (std::isfinite(r.lo)) s += (r.lo_open ? "> " : ">= ") + number(r.lo);
  if (std::isfinite(r.hi)) s += (s.empty() ? "" : " and ") + std::string(r.hi_open ? "< " : "<= ") + number(r.hi);
  return s;
}
}  // namespace

double read_real(const Json& value, const std::string& where, Range range) {
  if (!value.is_number()) throw SceneError("scene key '" + where + "': expected a number, got " + type_name(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw SceneError("scene key '" + where + "': must be finite");
  const bool below = range.lo_open ? !(x > range.lo) : !(x >= range.lo);
  const bool above = range.hi_open ? !(x < range.hi) : !(x <= range.hi);
  if (below || above)
    throw SceneError("scene key '" + where + "': must be " + describe_range(range) + " (got " + number(x) + ")");
  return x;
}

ObjectReader::ObjectReader(const Json& value, std::string path) : value_(value), path_(std::move(path)) {
  if (!value_.is_object())
    throw SceneError("scene key '" + (path_.empty() ? std::string("<top level>") : path_) +
                     "': expected an object, got " + type_name(value_));
}

bool ObjectReader::has(const char* key) const { return value_.contains(key); }

void ObjectReader::fail(const char* key, const std::string& what) const {
  throw SceneError("scene key '" + key_path(key) + "': " + what);
}

const Json& ObjectReader::get(const char* key) {
  if (!value_.contains(key)) fail(key, "missing (required)");
  read_.insert(key);
  return value_.at(key);
}

const Json& ObjectReader::raw(const char* key) { return get(key); }

double ObjectReader::check_real(const Json& value, const std::string& where, Range range) const {
  return read_real(value, where, range);
}

double ObjectReader::real(const char* key, Range range) { return check_real(get(key), key_path(key), range); }

double ObjectReader::real_or(const char* key, double fallback, Range range) {
  return has(key) ? real(key, range) : fallback;
}

long long ObjectReader::integer(const char* key, long long lo, long long hi) {
  const Json& v = get(key);
  if (!v.is_number_integer() && !(v.is_number_float() && std::nearbyint(v.get<double>()) == v.get<double>()))
    fail(key, "expected an integer, got " + (v.is_number() ? std::string("a fractional number") : type_name(v)));
  const double x = v.get<double>();
  if (!(x >= static_cast<double>(lo) && x <= static_cast<double>(hi)))
    fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " +
                  number(x) + ")");
  return static_cast<long long>(x);
}

long long ObjectReader::integer_or(const char* key, long long fallback, long long lo, long long hi) {
  return has(key) ? integer(key, lo, hi) : fallback;
}

bool ObjectReader::boolean_or(const char* key, bool fallback) {
  if (!has(key)) return fallback;
  const Json& v = get(key);
  if (!v.is_boolean()) fail(key, "expected true or false, got " + type_name(v));
  return v.get<bool>();
}

std::string ObjectReader::text(const char* key) {
  const Json& v = get(key);
  if (!v.is_string()) fail(key, "expected a string, got " + type_name(v));
  return v.get<std::string>();
}

std::string ObjectReader::choice(const char* key, std::initializer_list<const char*> options) {
  const std::string s = text(key);
  std::string list;
  for (const char* o : options) {
    if (s == o) return s;
    list += (list.empty() ? "" : " | ") + std::string(o);
  }
  fail(key, "'" + s + "' is not one of " + list);
}

std::string ObjectReader::choice_or(const char* key, const char* fallback, std::initializer_list<const char*> options) {
  return has(key) ? choice(key, options) : std::string(fallback);
}

std::vector<double> ObjectReader::vector(const char* key, std::size_t size, Range range) {
  const Json& v = get(key);
  if (!v.is_array()) fail(key, "expected an array of " + std::to_string(size) + " numbers, got " + type_name(v));
  if (v.size() != size)
    fail(key, "expected " + std::to_string(size) + " numbers (one per dimension), got " + std::to_string(v.size()));
  std::vector<double> out;
  out.reserve(size);
  for (std::size_t i = 0; i < size; ++i) out.push_back(check_real(v[i], key_path(key) + "." + std::to_string(i), range));
  return out;
}

ObjectReader ObjectReader::object(const char* key) { return ObjectReader(get(key), key_path(key)); }

std::vector<std::pair<const Json*, std::string>> ObjectReader::array(const char* key) {
  const Json& v = get(key);
  if (!v.is_array()) fail(key, "expected an array, got " + type_name(v));
  std::vector<std::pair<const Json*, std::string>> out;
  for (std::size_t i = 0; i < v.size(); ++i) out.emplace_back(&v[i], key_path(key) + "." + std::to_string(i));
  return out;
}

Json parse_json(const std::string& text, const std::string& path, bool ignore_comments) {
  // The parser reports every key as it reads it: each open object keeps the
  // keys seen so far, each open array counts its elements (for the path).
  struct Open {
    bool array = false;
    std::string path;
    std::set<std::string> keys;
    std::string key;        ///< the object's key whose value is being read
    std::size_t element = 0;  ///< the array's next element
  };
  std::vector<Open> open;
  const auto next_path = [&]() -> std::string {
    if (open.empty()) return path;
    Open& parent = open.back();
    return join_path(parent.path, parent.array ? std::to_string(parent.element++) : parent.key);
  };
  const Json::parser_callback_t check = [&](int, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start: {
        Open o;
        o.path = next_path();
        o.array = event == Json::parse_event_t::array_start;
        open.push_back(std::move(o));
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        open.pop_back();
        break;
      case Json::parse_event_t::key: {
        Open& object = open.back();
        std::string key = parsed.get<std::string>();
        if (!object.keys.insert(key).second) throw SceneError("scene key '" + join_path(object.path, key) + "': given twice");
        object.key = std::move(key);
        break;
      }
      case Json::parse_event_t::value:
        if (!open.empty() && open.back().array) ++open.back().element;
        break;
    }
    return true;
  };
  return Json::parse(text, check, /*allow_exceptions=*/true, ignore_comments);
}

void ObjectReader::finish() const {
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    if (read_.count(it.key()) == 0)
      throw SceneError("scene key '" + key_path(it.key().c_str()) + "': unknown key");
  }
}

}  // namespace xfdem::scene
