#pragma once
/// @file
/// The error every file reader raises for a file it refuses (glTF, OBJ/PLY, Gaussian splats):
/// the message names the file, the element and the reason.
#include "sgfx/Export.h"

#include <stdexcept>

namespace sgfx {

class SGFX_API LoadError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace sgfx
