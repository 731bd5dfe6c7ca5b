#!/usr/bin/env bash
# Installs what is missing, builds everything and runs the whole test suite through CTest:
# first the normal (Release) build, then the same suite built with AddressSanitizer,
# UndefinedBehaviorSanitizer and LeakSanitizer (suppressions: tests/sanitizers/lsan.supp).
# SGFX_SKIP_SANITIZERS=1 runs the first stage only (for quick local runs). Then the scene-query tests
# are built with ThreadSanitizer and run (SGFX_SKIP_TSAN=1 skips them). A last stage builds the
# glTF loader's and the OSG bridge's libFuzzer targets with clang and runs each for 60 s, the display descriptions' for 20 s (scripts/fuzz.sh); SGFX_SKIP_FUZZ=1
# skips it. The packaging stage builds the libraries shared (scripts/package.sh), checks that install
# and the Debian packages (tests/packaging/); SGFX_SKIP_PACKAGING=1 skips it.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
bash scripts/install-deps.sh
jobs=$(nproc)

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"
(cd build && ctest --output-on-failure -j "$jobs")

if [ "${SGFX_SKIP_PACKAGING:-0}" != 1 ]; then
  # Shared libraries with hidden symbols, their install, and libsgfx0/libsgfx-dev/sgfx-tools.
  # On a fresh CI machine (root) the packages are also really installed, used and purged.
  bash scripts/package.sh build-package
  bash tests/packaging/check_install.sh build-package build-package/check_install
  if [ "${CI:-}" = true ] && [ "$(id -u)" = 0 ]; then export SGFX_TEST_SYSTEM_INSTALL=1; fi
  bash tests/packaging/check_deb.sh build-package build-package/check_deb
fi

if [ "${SGFX_SKIP_SANITIZERS:-0}" != 1 ]; then
  # The OSG peer is third-party code and the package consumer links without the sanitizer
  # runtime; neither is part of this stage. This stage is also the build without OpenSceneGraph
  # (SGFX_WITH_OSG=OFF): everything else builds and passes without it, and loadModel says how to
  # get the bridge (tests/osg_loader_test.cpp). The bridge itself runs under ASan in the fuzz stage.
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSGFX_SANITIZE=ON -DSGFX_BUILD_BENCH=OFF \
    -DSGFX_WITH_OSG=OFF
  cmake --build build-asan -j "$jobs"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:check_initialization_order=1
  export LSAN_OPTIONS=suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  (cd build-asan && ctest --output-on-failure -j "$jobs" -E 'package_consumer')
fi

if [ "${SGFX_SKIP_TSAN:-0}" != 1 ]; then
  # ThreadSanitizer over the scene queries: two threads query while the viewer draws
  # (tests/query_threads_test.cpp). Only Mesa's own threads are suppressed (tests/sanitizers/tsan.supp).
  cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSGFX_TSAN=ON -DSGFX_BUILD_BENCH=OFF
  cmake --build build-tsan -j "$jobs" --target test_query_threads test_query test_auto_lod
  export TSAN_OPTIONS=halt_on_error=1:suppressions=$root/tests/sanitizers/tsan.supp
  build-tsan/tests/test_query_threads
  build-tsan/tests/test_query
  # addAutoLods on four threads (loaders/src/ParallelFor.h): the same LODs as on one.
  build-tsan/tests/test_auto_lod --gtest_filter='AutoLod.ThreadsMakeTheSameLods:AutoLod.ParallelFor*'
fi

if [ "${SGFX_SKIP_FUZZ:-0}" != 1 ]; then
  SGFX_JOBS=$jobs bash scripts/fuzz.sh
fi
