#pragma once
/// @file
/// OpenSceneGraph's `.view` viewer configurations (the text read by OSG's osgViewer plugin,
/// View_readLocalData in src/osgWrappers/deprecated-dotosg/osgViewer/View.cpp), read without OSG.
#include "sgfx/Export.h"
#include "sgfx/SphericalDisplay.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace sgfx {

struct SGFX_API OsgViewConfig {
    enum class Kind : std::uint8_t {
        SingleScreen, ///< setUpViewOnSingleScreen N: a plain channel filling screen N
        Spherical,    ///< setUpViewFor3DSphericalDisplay / setUpViewForPanoramicSphericalDisplay
    };
    Kind kind = Kind::SingleScreen;
    unsigned screenNum = 0;           ///< SingleScreen's screen (Spherical: spherical.screenNum)
    SphericalDisplayParams spherical; ///< Spherical only
};

/// Reads a `.view` file: one `osgViewer::View { ... }` holding setUpViewOnSingleScreen N or a
/// spherical display block with radius, collar, screenNum, intensityMap { angle percent ... },
/// intensityFormat and projectorMatrix { 16 numbers, OSG's row-vector order }. Anything else
/// (intensityFile, other setUpView* calls, unknown words, bad numbers, missing braces) throws
/// sgfx::LoadError naming the file, the line and the field.
SGFX_API OsgViewConfig loadOsgView(const std::filesystem::path& file);
/// The same for text in memory; `sourceName` stands for the file in messages.
SGFX_API OsgViewConfig parseOsgView(std::string_view text, const std::string& sourceName);

} // namespace sgfx
