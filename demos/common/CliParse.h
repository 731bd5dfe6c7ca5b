#pragma once
// The demos' command lines, parsed by CLI11: value checks whose messages name the option and the
// value (numbers, integers, choices, WxH), and one way to run a parse: --help prints the usage and
// exits 0, a usage error prints "PROGRAM: message" and exits 2 (CLI11's own exit codes are not the
// demos'). Option callbacks run in the order the options were set up, not the command line's.
#include <CLI/CLI.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace demo {

// `text` as a finite number in [lo, hi] (CLI::Range lets NaN through); else a usage error.
inline double number(const std::string& option, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream range;
        range << "[" << lo << ", " << hi << "]";
        throw CLI::ValidationError(option, "'" + text + "' is not a number in " + range.str());
    }
    return v;
}

// `text` as an integer in [lo, hi]; else a usage error.
template <class T> T integer(const std::string& option, const std::string& text, T lo, T hi) {
    T v{};
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end || v < lo || v > hi)
        throw CLI::ValidationError(option, "'" + text + "' is not an integer in [" + std::to_string(lo) +
                                               ", " + std::to_string(hi) + "]");
    return v;
}

// One of `values`' names, as what it stands for; else a usage error naming the option and value.
template <class T>
T choice(const std::string& option, const std::string& v,
         const std::vector<std::pair<std::string, T>>& values, const char* expected) {
    for (const auto& [name, value] : values)
        if (v == name) return value;
    throw CLI::ValidationError(option, "'" + v + "' is not " + expected);
}

// on|off as a bool.
inline bool onOff(const std::string& option, const std::string& v) {
    return choice<bool>(option, v, {{"on", true}, {"off", false}}, "on or off");
}

// --size WxH, each in [lo, hi]; `given`, when not null, is set when the option is.
inline CLI::Option* addSize(CLI::App& app, int& width, int& height, int lo, int hi, const std::string& what,
                            bool* given = nullptr) {
    return app
        .add_option_function<std::string>(
            "--size",
            [&width, &height, lo, hi, given](const std::string& v) {
                const auto x = v.find('x');
                if (x == std::string::npos)
                    throw CLI::ValidationError("--size", "expected WxH, got '" + v + "'");
                width = integer("--size", v.substr(0, x), lo, hi);
                height = integer("--size", v.substr(x + 1), lo, hi);
                if (given) *given = true;
            },
            what)
        ->type_name("WxH");
}

// The figure programs' common options: --out-dir DIR and --size WxH (1..4096, default 480x320).
inline void addFigureOptions(CLI::App& app, std::filesystem::path& dir, int& width, int& height) {
    app.add_option("--out-dir", dir, "folder of the PNGs (default .)")->type_name("DIR");
    addSize(app, width, height, 1, 4096, "image size, 1..4096 each (default 480x320)");
}

// A repeated option takes its last value, as the demos' hand-written parsers did (scripts pass
// defaults first and the caller's options after them).
inline void lastValueWins(CLI::App& app) {
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

// A usage error that is not one option's value (two options that do not go together, ...).
[[noreturn]] inline void usageError(const std::string& message) {
    throw CLI::ValidationError(message);
}

// Wraps the options' descriptions to `width` columns beside CLI11's column of names.
inline void wrapHelp(CLI::App& app, std::size_t width = 100) {
    const std::size_t column = 30;
    app.get_formatter()->column_width(column);
    for (CLI::Option* option : app.get_options()) {
        std::istringstream words(option->get_description());
        std::string text, line, word;
        while (words >> word) {
            if (!line.empty() && line.size() + 1 + word.size() > width - column)
                text += line + "\n", line.clear();
            line += (line.empty() ? "" : " ") + word;
        }
        option->description(text + line);
    }
}

// Parses argv, then runs `checks` (cross-option checks that throw CLI::ParseError). Returns -1
// when the program goes on, else its exit status: 0 after --help, 2 after a usage error.
inline int parse(CLI::App& app, int argc, char** argv, const std::function<void()>& checks = {}) {
    try {
        app.parse(argc, argv);
        if (checks) checks();
        return -1;
    } catch (const CLI::CallForHelp&) {
        wrapHelp(app);
        std::cout << app.help();
        return 0;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "%s: %s\n%s --help lists the options\n", app.get_name().c_str(), e.what(),
                     app.get_name().c_str());
        return 2;
    }
}

} // namespace demo
