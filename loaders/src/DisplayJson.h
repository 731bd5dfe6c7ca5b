#pragma once
// Reading display descriptions: one JSON object at a time, each field by its JSON path, so every
// error names the file, the field and the reason; an object's keys are checked against the ones
// its layout knows before anything else, so a typo is reported as the unknown key it is.
#include "sgfx/DisplayChannel.h"
#include "sgfx/LoadError.h"

#include <nlohmann/json.hpp>

#include <array>
#include <initializer_list>
#include <string>
#include <vector>

namespace sgfx::display {

using Json = nlohmann::json;

/// A value as a message shows it: its JSON text, cut short.
std::string shown(const Json& v);
/// A number as a message shows it (no trailing zeros).
std::string num(double v);

/// Bounds of a number: [lo, hi], or open at either end.
struct Range {
    double lo, hi;
    bool openLo = false, openHi = false;
    bool contains(double v) const { return (openLo ? v > lo : v >= lo) && (openHi ? v < hi : v <= hi); }
    std::string text() const;
};

class Object {
public:
    using Keys = std::initializer_list<const char*>;
    /// `value` must be an object with no keys but `keys` (else LoadError naming the field).
    Object(const std::string& source, const Json& value, std::string path, Keys keys);

    [[noreturn]] void fail(const std::string& key, const std::string& why) const;
    [[noreturn]] static void fail(const std::string& source, const std::string& path, const std::string& why);
    const std::string& source() const { return source_; }
    /// The path of one of this object's fields ("wall" + "columns" = "wall.columns").
    std::string at(const std::string& key) const;

    bool has(const std::string& key) const;
    /// The field, or nullptr when absent.
    const Json* find(const std::string& key) const;
    /// The field; LoadError "is missing" when absent.
    const Json& require(const std::string& key, const char* what) const;

    double number(const std::string& key, Range range) const;
    double number(const std::string& key, Range range, double fallback) const;
    int integer(const std::string& key, int lo, int hi) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    Object object(const std::string& key, Keys keys) const;
    /// An array of `lo`..`hi` elements.
    const Json& array(const std::string& key, std::size_t lo, std::size_t hi, const char* what) const;
    /// [w, h], each 1..16384.
    std::array<int, 2> resolution(const std::string& key) const;
    /// [x, y] metres.
    std::array<double, 2> pair(const std::string& key, Range range) const;

private:
    const std::string& source_;
    const Json& value_;
    std::string path_;
};

/// A number element (arrays' elements), checked against `range`.
double numberAt(const std::string& source, const Json& v, const std::string& path, Range range);
/// An integer element in lo..hi.
int integerAt(const std::string& source, const Json& v, const std::string& path, int lo, int hi);

} // namespace sgfx::display
