#include "sgfx/DisplayConfig.h"

#include "DisplayLayouts.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sgfx {
namespace {

using display::Json;
using display::Object;

// Deeper nesting than any description needs is refused while parsing (no deep recursion later).
constexpr int kMaxDepth = 16;

Json parseJson(std::string_view text, const std::string& source) {
    bool blank = true;
    for (char c : text)
        blank = blank && std::isspace(static_cast<unsigned char>(c));
    if (blank) Object::fail(source, "the description", "the text is empty (expected a JSON object)");
    const auto depthGuard = [&](int depth, Json::parse_event_t, Json&) {
        if (depth > kMaxDepth)
            Object::fail(source, "the description",
                         "nested deeper than " + std::to_string(kMaxDepth) + " levels");
        return true;
    };
    try {
        return Json::parse(text.begin(), text.end(), depthGuard);
    } catch (const Json::exception& e) {
        // nlohmann's message names the line and column ("[json.exception.parse_error.101] parse
        // error at line 3, column 5: syntax error ...") or the number too large for a double
        // ("[json.exception.out_of_range.406] number overflow parsing '1e400'").
        std::string why = e.what();
        if (const auto cut = why.find("] "); cut != std::string::npos) why = why.substr(cut + 2);
        throw LoadError("sgfx: display description '" + source + "': invalid JSON: " + why);
    }
}

} // namespace

DisplayConfig DisplayConfig::parse(std::string_view json, const std::string& source) {
    const Json doc = parseJson(json, source);
    const Object root(source, doc, "", {"name", "description", "wall", "cylinder", "dome", "channels"});
    DisplayConfig config;
    config.name = root.string("name", std::filesystem::path(source).stem().string());
    root.string("description", "");
    if (config.name.empty()) root.fail("name", "is empty");
    for (const char* layout : {"wall", "cylinder", "dome", "channels"}) {
        if (!root.has(layout)) continue;
        if (!config.layout.empty())
            root.fail(layout, "a description has one layout, and this one already has " + config.layout);
        config.layout = layout;
    }
    if (config.layout.empty())
        Object::fail(source, "the description",
                     "has no layout (one of the keys wall, cylinder, dome, channels)");
    try {
        display::Layout built = config.layout == "wall"       ? display::readWall(root)
                                : config.layout == "cylinder" ? display::readCylinder(root)
                                : config.layout == "dome"     ? display::readDome(root)
                                                              : display::readChannels(root);
        // What the layout made of the numbers (each frustum, the viewports' overlaps) is checked
        // here; the message names the channel and its field.
        validateChannels(built.channels);
        if (built.overall) built.overall->validate("overall frustum");
        config.channels = std::move(built.channels);
        config.overall = built.overall;
    } catch (const std::invalid_argument& e) {
        std::string why = e.what();
        if (why.rfind("sgfx: ", 0) == 0) why = why.substr(6);
        Object::fail(source, config.layout, why);
    }
    config.composite = compositeViewport(config.channels);
    return config;
}

DisplayConfig DisplayConfig::load(const std::filesystem::path& file) {
    const std::string source = file.string();
    std::ifstream in(file, std::ios::binary);
    if (!in) Object::fail(source, "the file", "cannot be opened");
    std::string text;
    char buf[4096];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
        text.append(buf, std::size_t(in.gcount()));
        if (text.size() > kMaxFileBytes)
            Object::fail(source, "the file", "is larger than " + std::to_string(kMaxFileBytes) + " bytes");
    }
    if (in.bad()) Object::fail(source, "the file", "cannot be read");
    return parse(text, source);
}

const DisplayChannel* DisplayConfig::find(std::string_view channelName) const {
    for (const DisplayChannel& c : channels)
        if (c.name == channelName) return &c;
    return nullptr;
}

} // namespace sgfx
