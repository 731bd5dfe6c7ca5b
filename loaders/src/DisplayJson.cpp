#include "DisplayJson.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace sgfx::display {

std::string shown(const Json& v) {
    std::string text = v.dump(-1, ' ', true, Json::error_handler_t::replace);
    return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

std::string num(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

std::string Range::text() const {
    const auto end = [](double v) {
        if (v == std::numeric_limits<double>::infinity()) return std::string("inf");
        if (v == -std::numeric_limits<double>::infinity()) return std::string("-inf");
        return num(v);
    };
    return std::string(openLo ? "(" : "[") + end(lo) + ", " + end(hi) + (openHi ? ")" : "]");
}

namespace {

const char* typeName(const Json& v) {
    if (v.is_number_integer() || v.is_number_unsigned()) return "an integer";
    if (v.is_number()) return "a number";
    return v.type_name(); // "object", "array", "string", "boolean", "null"
}

} // namespace

Object::Object(const std::string& source, const Json& value, std::string path, Keys keys)
    : source_(source)
    , value_(value)
    , path_(std::move(path)) {
    if (!value_.is_object())
        fail(source_, path_.empty() ? "the description" : path_,
             std::string("is ") + typeName(value_) + " (" + shown(value_) + "), not an object");
    for (const auto& item : value_.items()) {
        bool known = false;
        std::string expected;
        for (const char* k : keys) {
            known = known || item.key() == k;
            expected += (expected.empty() ? "" : ", ") + std::string(k);
        }
        if (!known) fail(item.key(), "unknown key (expected one of: " + expected + ")");
    }
}

void Object::fail(const std::string& source, const std::string& path, const std::string& why) {
    throw LoadError("sgfx: display description '" + source + "': " + path + ": " + why);
}

void Object::fail(const std::string& key, const std::string& why) const {
    fail(source_, at(key), why);
}

std::string Object::at(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
}

bool Object::has(const std::string& key) const {
    return value_.contains(key);
}

const Json* Object::find(const std::string& key) const {
    const auto it = value_.find(key);
    return it == value_.end() ? nullptr : &*it;
}

const Json& Object::require(const std::string& key, const char* what) const {
    const Json* v = find(key);
    if (!v) fail(key, std::string("is missing (") + what + ")");
    return *v;
}

double numberAt(const std::string& source, const Json& v, const std::string& path, Range range) {
    if (!v.is_number())
        Object::fail(source, path, std::string("is ") + typeName(v) + " (" + shown(v) + "), not a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) Object::fail(source, path, shown(v) + " is not finite");
    if (!range.contains(d)) Object::fail(source, path, num(d) + " is out of range " + range.text());
    return d;
}

int integerAt(const std::string& source, const Json& v, const std::string& path, int lo, int hi) {
    if (!v.is_number_integer() && !v.is_number_unsigned())
        Object::fail(source, path, std::string("is ") + typeName(v) + " (" + shown(v) + "), not an integer");
    const bool inRange = v.is_number_unsigned() ? v.get<std::uint64_t>() <= std::uint64_t(hi) &&
                                                      std::int64_t(v.get<std::uint64_t>()) >= lo
                                                : v.get<std::int64_t>() >= lo && v.get<std::int64_t>() <= hi;
    if (!inRange)
        Object::fail(source, path,
                     shown(v) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
    return int(v.get<std::int64_t>());
}

double Object::number(const std::string& key, Range range) const {
    return numberAt(source_, require(key, ("a number in " + range.text()).c_str()), at(key), range);
}

double Object::number(const std::string& key, Range range, double fallback) const {
    const Json* v = find(key);
    return v ? numberAt(source_, *v, at(key), range) : fallback;
}

int Object::integer(const std::string& key, int lo, int hi) const {
    const std::string what = "an integer " + std::to_string(lo) + ".." + std::to_string(hi);
    return integerAt(source_, require(key, what.c_str()), at(key), lo, hi);
}

std::string Object::string(const std::string& key, const std::string& fallback) const {
    const Json* v = find(key);
    if (!v) return fallback;
    if (!v->is_string()) fail(key, std::string("is ") + typeName(*v) + " (" + shown(*v) + "), not a string");
    return v->get<std::string>();
}

Object Object::object(const std::string& key, Keys keys) const {
    return Object(source_, require(key, "an object"), at(key), keys);
}

const Json& Object::array(const std::string& key, std::size_t lo, std::size_t hi, const char* what) const {
    const Json& v = require(key, what);
    if (!v.is_array())
        fail(key, std::string("is ") + typeName(v) + " (" + shown(v) + "), not an array (" + what + ")");
    if (v.size() < lo || v.size() > hi)
        fail(key, "has " + std::to_string(v.size()) + " elements, expected " +
                      (lo == hi ? std::to_string(lo) : std::to_string(lo) + ".." + std::to_string(hi)) +
                      " (" + what + ")");
    return v;
}

std::array<int, 2> Object::resolution(const std::string& key) const {
    const Json& v = array(key, 2, 2, "[width, height] in pixels");
    return {integerAt(source_, v[0], at(key) + "[0]", 1, 16384),
            integerAt(source_, v[1], at(key) + "[1]", 1, 16384)};
}

std::array<double, 2> Object::pair(const std::string& key, Range range) const {
    const Json& v = array(key, 2, 2, "[x, y]");
    return {numberAt(source_, v[0], at(key) + "[0]", range), numberAt(source_, v[1], at(key) + "[1]", range)};
}

} // namespace sgfx::display
