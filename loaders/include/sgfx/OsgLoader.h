#pragma once
/// @file
/// OpenSceneGraph content into sgfx: anything osgDB reads (.osgt, .osgb, .osgx, .ive, .osg,
/// OpenFlight .flt, and every format a Debian osgDB plugin handles) converted into sgfx nodes,
/// states and foreign shaders. Built when OpenSceneGraph's development package was found at
/// configure time (osgSupported()); without it loadOsg throws LoadError saying so. The coverage
/// table is in docs/coming-from-osg.md.
#include "sgfx/Export.h"
#include <sgfx/GltfLoader.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace sgfx {

/// How OSG content is read.
struct SGFX_API OsgOptions {
    /// Where the file's images and external files are looked for, before OSG_FILE_PATH and the
    /// file's own folder (osgDB::Options' database path list).
    std::vector<std::filesystem::path> databasePaths;
    /// Bytes of vertex, index and image data one load may make (past it: LoadError).
    std::size_t memoryLimit = std::size_t(2) << 30;
    /// osgDB's readers crash on some corrupt files (a flipped byte in an .osgt is enough). With
    /// this on, each file is first read in a child process (fork): a reader that crashes or runs
    /// past `readTimeout` there gives a LoadError instead of taking the application down, at the
    /// price of reading the file twice. Turn it off for trusted content to halve the load time.
    bool isolateReader = true;
    double readTimeout = 60.0; ///< seconds the isolated read may take
};

/// What a load met, in OpenSceneGraph's terms (each Geometry counted once per parent path, as
/// OSG's own statistics do), and what it could not convert.
struct SGFX_API OsgStats {
    std::size_t drawables = 0; ///< osg::Geometry (ShapeDrawable included) per parent path
    std::size_t vertices = 0;  ///< their vertex array sizes
    std::size_t triangles = 0; ///< from their primitive sets, strips, fans, quads and polygons expanded
    std::size_t programs = 0;  ///< osg::Program objects turned into foreign shaders
    /// One line per class (or feature) that was not converted, naming the first node path it was
    /// met on: "osgText::Text at /root/Geode 'label' (3 in all): not converted".
    std::vector<std::string> warnings;
};

/// True when this sgfx was built with the OpenSceneGraph bridge.
SGFX_API bool osgSupported();

/// The extensions osgDB's plugins read (lower case, with the dot), for loadModel's dispatch;
/// empty without the bridge.
SGFX_API const std::vector<std::string>& osgExtensions();

/// Reads `file` with osgDB and converts the graph. A file osgDB cannot read (missing, truncated,
/// garbage, no plugin) throws LoadError naming the file and the reason. Warnings go to
/// stats->warnings, or to stderr when `stats` is null.
SGFX_API std::shared_ptr<Group> loadOsg(const std::filesystem::path& file, const OsgOptions& options = {},
                                        OsgStats* stats = nullptr);

/// The same from bytes in memory, read by the osgDB plugin for `extension` (".osgt", ".osgb",
/// ".ive", ...). Images and external files resolve against options.databasePaths only.
/// `nameForErrors` stands in for the file name in messages.
SGFX_API std::shared_ptr<Group> loadOsgFromMemory(std::span<const std::byte> bytes,
                                                  const std::string& extension,
                                                  const std::string& nameForErrors,
                                                  const OsgOptions& options = {}, OsgStats* stats = nullptr);

} // namespace sgfx
