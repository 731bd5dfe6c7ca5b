// A reader for OSG's `.view` text (no OSG libraries): the fields View_readLocalData
// (OSG src/osgWrappers/deprecated-dotosg/osgViewer/View.cpp) accepts for the display set-ups sgfx has.
#include "sgfx/LoadError.h"
#include "sgfx/OsgViewConfig.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace sgfx {

namespace {

struct Token {
    std::string text;
    int line = 0;
};

std::vector<Token> tokenize(std::string_view s) {
    std::vector<Token> out;
    int line = 1;
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        if (c == '\n') ++line;
        if (std::isspace(static_cast<unsigned char>(c))) {
            ++i;
        } else if (c == '{' || c == '}') {
            out.push_back({std::string(1, c), line});
            ++i;
        } else {
            std::size_t j = i;
            while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j])) && s[j] != '{' &&
                   s[j] != '}')
                ++j;
            out.push_back({std::string(s.substr(i, j - i)), line});
            i = j;
        }
    }
    return out;
}

class Parser {
public:
    Parser(std::vector<Token> tokens, std::string source)
        : t_(std::move(tokens))
        , source_(std::move(source)) {}

    OsgViewConfig parse();

private:
    [[noreturn]] void fail(int line, std::string_view field, std::string_view why) const {
        throw LoadError(source_ + ":" + std::to_string(line) + ": " + std::string(field) + ": " +
                        std::string(why));
    }
    int lineHere() const { return pos_ < t_.size() ? t_[pos_].line : (t_.empty() ? 1 : t_.back().line); }
    const Token& next(std::string_view field) {
        if (pos_ >= t_.size()) fail(lineHere(), field, "unexpected end of file");
        return t_[pos_++];
    }
    void expect(std::string_view what, std::string_view field) {
        const Token& tok = next(field);
        if (tok.text != what)
            fail(tok.line, field, "expected '" + std::string(what) + "', got '" + tok.text + "'");
    }
    bool peek(std::string_view what) const { return pos_ < t_.size() && t_[pos_].text == what; }
    double number(std::string_view field) {
        const Token& tok = next(field);
        double v = 0.0;
        const char* b = tok.text.data();
        const auto [end, ec] = std::from_chars(b, b + tok.text.size(), v);
        if (ec != std::errc() || end != b + tok.text.size() || !std::isfinite(v))
            fail(tok.line, field, "expected a number, got '" + tok.text + "'");
        return v;
    }
    unsigned count(std::string_view field) {
        const int line = lineHere();
        const double v = number(field);
        if (v < 0.0 || v > 65535.0 || v != std::floor(v))
            fail(line, field, "expected a whole number 0..65535");
        return unsigned(v);
    }
    void spherical(OsgViewConfig& c, SphericalDisplayKind kind, int line);
    void intensityMap(SphericalDisplayParams& p);
    void projectorMatrix(SphericalDisplayParams& p);

    std::vector<Token> t_;
    std::string source_;
    std::size_t pos_ = 0;
};

void Parser::intensityMap(SphericalDisplayParams& p) {
    expect("{", "intensityMap");
    std::vector<std::pair<IntensityPoint, int>> points;
    while (!peek("}")) {
        const int line = lineHere();
        const double angle = number("intensityMap angle");
        const double percent = number("intensityMap percent");
        if (angle < 0.0 || angle > 180.0) fail(line, "intensityMap angle", "must be in [0, 180]");
        if (percent < 0.0) fail(line, "intensityMap percent", "must be >= 0");
        points.push_back({{float(angle), float(percent)}, line});
    }
    expect("}", "intensityMap");
    // OSG keeps the points in a std::map: any order, sorted by angle.
    std::stable_sort(points.begin(), points.end(),
                     [](const auto& a, const auto& b) { return a.first.angleDeg < b.first.angleDeg; });
    for (std::size_t i = 1; i < points.size(); ++i)
        if (points[i].first.angleDeg == points[i - 1].first.angleDeg)
            fail(points[i].second, "intensityMap angle",
                 "repeated angle " + std::to_string(points[i].first.angleDeg));
    if (points.size() > std::size_t(SphericalDisplayParams::kMaxIntensityPoints))
        fail(points.back().second, "intensityMap",
             "at most " + std::to_string(SphericalDisplayParams::kMaxIntensityPoints) + " points");
    p.intensityMap.clear();
    for (const auto& q : points)
        p.intensityMap.push_back(q.first);
}

void Parser::projectorMatrix(SphericalDisplayParams& p) {
    expect("{", "projectorMatrix");
    // The file lists OSG's matrix row by row (row vectors); its transpose acts on column vectors,
    // i.e. entry k goes to glm column k / 4, row k % 4.
    for (int k = 0; k < 16; ++k)
        p.projector[k / 4][k % 4] = number("projectorMatrix");
    expect("}", "projectorMatrix");
}

void Parser::spherical(OsgViewConfig& c, SphericalDisplayKind kind, int line) {
    SphericalDisplayParams& p = c.spherical;
    p.kind = kind;
    c.kind = OsgViewConfig::Kind::Spherical;
    expect("{", "setUpViewForSphericalDisplay");
    int collarLine = line;
    while (!peek("}")) {
        const Token& key = next("setUpViewForSphericalDisplay");
        if (key.text == "radius") {
            p.radius = number("radius");
            if (!(p.radius > 0.0)) fail(key.line, "radius", "must be > 0");
        } else if (key.text == "collar") {
            p.collar = number("collar");
            collarLine = key.line;
            if (p.collar < 0.0) fail(key.line, "collar", "must be >= 0");
        } else if (key.text == "screenNum") {
            p.screenNum = count("screenNum");
        } else if (key.text == "intensityMap") {
            intensityMap(p);
        } else if (key.text == "intensityFormat") {
            const unsigned f = count("intensityFormat"); // a GPU storage hint in OSG (8, 16, 32 bits)
            if (f != 8 && f != 16 && f != 32) fail(key.line, "intensityFormat", "expected 8, 16 or 32");
        } else if (key.text == "projectorMatrix") {
            projectorMatrix(p);
        } else if (key.text == "intensityFile") {
            fail(key.line, "intensityFile", "intensity images are not supported; give an intensityMap");
        } else {
            fail(key.line, key.text, "unknown field of a spherical display");
        }
    }
    expect("}", "setUpViewForSphericalDisplay");
    if (p.collar >= p.radius) fail(collarLine, "collar", "must be smaller than radius");
}

OsgViewConfig Parser::parse() {
    OsgViewConfig c;
    const Token& head = next("osgViewer::View");
    if (head.text != "osgViewer::View" && head.text != "View")
        fail(head.line, "osgViewer::View", "expected 'osgViewer::View', got '" + head.text + "'");
    expect("{", "osgViewer::View");
    bool set = false;
    while (!peek("}")) {
        const Token& key = next("osgViewer::View");
        if (set) fail(key.line, key.text, "a view holds one display set-up");
        set = true;
        if (key.text == "setUpViewFor3DSphericalDisplay") {
            spherical(c, SphericalDisplayKind::ThreeD, key.line);
        } else if (key.text == "setUpViewForPanoramicSphericalDisplay") {
            spherical(c, SphericalDisplayKind::Panoramic, key.line);
        } else if (key.text == "setUpViewOnSingleScreen") {
            c.kind = OsgViewConfig::Kind::SingleScreen;
            c.screenNum = count("setUpViewOnSingleScreen");
        } else {
            fail(key.line, key.text,
                 "unsupported (sgfx reads setUpViewOnSingleScreen and the spherical displays)");
        }
    }
    expect("}", "osgViewer::View");
    if (pos_ < t_.size()) fail(t_[pos_].line, t_[pos_].text, "text after the view (one view per file)");
    return c;
}

} // namespace

OsgViewConfig parseOsgView(std::string_view text, const std::string& sourceName) {
    return Parser(tokenize(text), sourceName).parse();
}

OsgViewConfig loadOsgView(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw LoadError(file.string() + ":0: file: cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parseOsgView(ss.str(), file.string());
}

} // namespace sgfx
