#!/usr/bin/env bash
# Builds sgfx with shared libraries for /usr and makes its Debian packages with CPack:
#   libsgfx0 (the libraries), libsgfx-dev (headers, CMake config, sgfx.pc), sgfx-tools (sgfx-view).
# Usage: scripts/package.sh [BUILD_DIR]   (default build-package; the .deb files land in it)
# Install them with: apt-get install ./build-package/*.deb
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build-package}
cmake -S . -B "$out" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON -DCMAKE_INSTALL_PREFIX=/usr \
  -DSGFX_BUILD_TESTS=OFF -DSGFX_BUILD_BENCH=OFF
cmake --build "$out" -j "$(nproc)"
(cd "$out" && cpack -G DEB)
ls -l "$out"/*.deb
