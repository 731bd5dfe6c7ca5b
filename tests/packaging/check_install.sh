#!/usr/bin/env bash
# Installs a built sgfx (static or shared, as configured) into a scratch prefix and checks it as a
# downstream user would meet it:
#  1. every installed header is under include/sgfx/ (no KHR/, no glad/ beside other packages');
#  2. every public header compiles on its own; the old effect spellings still compile, with a warning;
#  3. a CMake project (find_package(sgfx)) builds and renders through it;
#  4. an application with its own glad (Debian's python3-glad) links and runs beside sgfx;
#  5. find_package honours SameMajorVersion; the program builds through pkg-config (--static for
#     static libraries);
#  6. shared: each library has its SONAME and exports nothing but sgfx's API and its prefixed loader.
# Usage: check_install.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
work=$2
src=$(cd "$(dirname "$0")/../.." && pwd)
fail() { echo "check_install: FAIL: $*" >&2; exit 1; }
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
shared=$(cache BUILD_SHARED_LIBS)
libdir=$(cache CMAKE_INSTALL_LIBDIR)
case "${shared^^}" in ON | 1 | TRUE | YES | Y) shared=1 ;; *) shared=0 ;; esac
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd) # absolute: CMake reads a relative prefix from its own build folder
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null || fail "cmake --install $build failed"
echo "check_install: installed $( ((shared)) && echo shared || echo static ) sgfx into $prefix"

# 1. Layout: headers only under include/sgfx/, and no GL loader anywhere.
stray=$(cd "$prefix/include" && find . -type f ! -path './sgfx/*')
[ -z "$stray" ] || fail "headers outside include/sgfx/: $stray"
loader=$(cd "$prefix" && find . -name 'gl.h' -o -name 'khrplatform.h' -o -path '*glad*')
[ -z "$loader" ] || fail "the private GL loader was installed: $loader"
echo "check_install: $(cd "$prefix/include" && find . -type f | wc -l) headers, all under include/sgfx/"

# 2. Each public header alone in a translation unit, with the warnings sgfx builds with.
cxxflags=(-std=c++20 -fsyntax-only -Wall -Wextra -Wpedantic -Wshadow -Werror -I"$prefix/include")
headers=$(cd "$prefix/include" && find sgfx -name '*.h' ! -path 'sgfx/compat/*' | sort)
printf '%s\n' $headers | xargs -P "$(nproc)" -I{} sh -c \
  'echo "#include <{}>" | c++ "$@" -x c++ - || { echo "check_install: FAIL: <{}> does not compile on its own" >&2; exit 255; }' \
  sh "${cxxflags[@]}"
echo "check_install: $(printf '%s\n' $headers | wc -l) public headers compile on their own"
# Through -isystem, as CMake passes an imported target's include directories.
for h in $(cd "$prefix/include/sgfx/compat" && find . -name '*.h' | sed 's#^\./##'); do
  out=$(echo "#include <$h>" | c++ -std=c++20 -fsyntax-only -isystem "$prefix/include" -isystem "$prefix/include/sgfx/compat" -x c++ - 2>&1) ||
    fail "old spelling <$h> no longer compiles: $out"
  grep -q "<$h> is deprecated" <<<"$out" || fail "old spelling <$h> compiles without its deprecation warning"
done
echo "check_install: the old effect spellings forward with a deprecation warning"

# 3 and 4. The CMake consumer, and the application with its own glad.
/usr/bin/python3 -m glad --quiet --reproducible --api gl:core=4.5 --out-path "$work/own_glad" c ||
  fail "python3-glad could not generate the application's own loader (apt-get install python3-glad)"
cmake -S "$src/tests/consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DOWN_GLAD_DIR="$work/own_glad" >"$work/consumer.log" 2>&1 ||
  { cat "$work/consumer.log"; fail "configuring the consumer against the install failed"; }
cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 ||
  { cat "$work/consumer.log"; fail "building the consumer against the install failed"; }
"$work/consumer/consumer" || fail "the CMake consumer rendered the wrong pixel"
"$work/consumer/own_glad_consumer" || fail "the application with its own glad failed beside sgfx"

# The version file: SameMajorVersion accepts this release's 0.x and refuses another major.
major=$(cache CMAKE_PROJECT_VERSION_MAJOR)
mkdir -p "$work/version"
cat >"$work/version/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(sgfx_version_probe CXX)
find_package(sgfx ${WANT} CONFIG REQUIRED)
CMAKE
cmake -S "$work/version" -B "$work/version/ok" -DWANT="$major" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null 2>&1 ||
  fail "find_package(sgfx $major) does not accept the installed $(cache CMAKE_PROJECT_VERSION)"
if out=$(cmake -S "$work/version" -B "$work/version/next" -DWANT="$((major + 1))" -DCMAKE_PREFIX_PATH="$prefix" 2>&1); then
  fail "find_package(sgfx $((major + 1))) accepted the installed $(cache CMAKE_PROJECT_VERSION)"
fi
grep -q 'considered but not accepted' <<<"$out" ||
  fail "find_package(sgfx $((major + 1))) failed, but not for the version: $out"
echo "check_install: find_package(sgfx $major) finds it, find_package(sgfx $((major + 1))) does not"

# 5. pkg-config.
export PKG_CONFIG_PATH=$prefix/$libdir/pkgconfig
static=()
((shared)) || static=(--static)
# The .pc carries the configured prefix; this staged install moved it.
flags=$(pkg-config "${static[@]}" --define-variable=prefix="$prefix" --cflags --libs sgfx) ||
  fail "pkg-config does not find sgfx.pc"
# shellcheck disable=SC2086 # the flags are words
c++ -std=c++20 -O1 -o "$work/pc_consumer" "$src/tests/consumer/main.cpp" $flags -Wl,-rpath,"$prefix/$libdir" ||
  fail "building through pkg-config failed (flags: $flags)"
"$work/pc_consumer" || fail "the pkg-config consumer rendered the wrong pixel"

# 6. Shared libraries: SONAME and exported symbols.
if ((shared)); then
  for lib in scenegraph nodes loaders; do
    so=$prefix/$libdir/libsgfx_$lib.so
    soname=$(readelf -d "$so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
    [ "$soname" = "libsgfx_$lib.so.$major" ] || fail "$so has SONAME '$soname', expected libsgfx_$lib.so.$major"
    # Strong exports only: weak ones are the standard library's template instances, which every C++
    # library exports. Allowed: the sgfx namespace (functions, vtables, typeinfo, statics) and sgfx_glad_.
    leaks=$(nm -D --defined-only "$so" | awk '$2 ~ /^[TDBRG]$/ {print $3}' |
      grep -vE '^(_Z(N|NK|TVN|TIN|TSN|GVZN|ZN)4sgfx|sgfx_glad|SGFX_GLAD_|__bss_start$|_edata$|_end$)' || true)
    [ -z "$leaks" ] || fail "$so exports symbols outside sgfx: $(echo "$leaks" | head -5 | c++filt)"
    # Internal classes (src/ only) must stay hidden: a sample that a visibility slip would expose.
    hidden=$(nm -D --defined-only "$so" | awk '{print $3}' | grep -cE '^_ZNK?4sgfx(12SubtreeIndex|2gl10StateCache|2aa)' || true)
    [ "$hidden" = 0 ] || fail "$so exports internal classes (SubtreeIndex, gl::StateCache, aa::)"
    echo "check_install: $so: SONAME $soname, $(nm -D --defined-only "$so" | awk '$2 ~ /^[TDBRG]$/' | wc -l) strong exports, all sgfx"
  done
fi
echo "check_install: PASS"
