// loadOsg when sgfx was built without OpenSceneGraph (libopenscenegraph-dev absent, or
// -DSGFX_WITH_OSG=OFF): every call says so, naming the file.
#include <sgfx/OsgLoader.h>

namespace sgfx {

bool osgSupported() {
    return false;
}

const std::vector<std::string>& osgExtensions() {
    static const std::vector<std::string> none;
    return none;
}

std::shared_ptr<Group> loadOsg(const std::filesystem::path& file, const OsgOptions&, OsgStats*) {
    throw LoadError("sgfx: model '" + file.string() +
                    "': this sgfx was built without the OpenSceneGraph bridge; install libopenscenegraph-dev "
                    "and configure again (SGFX_WITH_OSG=ON) to read OpenSceneGraph formats");
}

std::shared_ptr<Group> loadOsgFromMemory(std::span<const std::byte>, const std::string&,
                                         const std::string& name, const OsgOptions& options,
                                         OsgStats* stats) {
    return loadOsg(name, options, stats);
}

} // namespace sgfx
