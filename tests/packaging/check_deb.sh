#!/usr/bin/env bash
# Makes the Debian packages from a shared build configured for /usr (scripts/package.sh) and checks
# them as a Debian 12 system would meet them:
#  1. CPack makes libsgfxN (runtime), libsgfx-dev and sgfx-tools;
#  2. every header is under /usr/include/sgfx/, the libraries carry their SONAME links, and no file
#     of any package is owned by an installed package (libgl-dev's KHR/khrplatform.h among them);
#  3. dpkg-shlibdeps computed the runtime dependencies (libstdc++6, libosmesa6, libglfw3...);
#  4. apt accepts all three beside what is installed (a simulated install: no conflict, no removal);
#  5. with SGFX_TEST_SYSTEM_INSTALL=1 (scripts/test.sh sets it under CI=true, as root on a fresh
#     machine) they are really installed, a consumer builds against /usr through CMake and pkg-config
#     and runs, sgfx-view renders, and the packages are purged again.
# Usage: check_deb.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
work=$2
src=$(cd "$(dirname "$0")/../.." && pwd)
fail() { echo "check_deb: FAIL: $*" >&2; exit 1; }
rm -rf "$work"
mkdir -p "$work"
work=$(cd "$work" && pwd) # absolute: CMake reads a relative prefix from its own build folder
(cd "$build" && cpack -G DEB -B "$work/debs" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
mapfile -t debs < <(find "$work/debs" -maxdepth 1 -name '*.deb' | sort)
((${#debs[@]} == 3)) || fail "expected 3 packages, cpack made: ${debs[*]}"
declare -A names
for deb in "${debs[@]}"; do
  name=$(dpkg-deb -f "$deb" Package)
  names[$name]=$deb
  echo "check_deb: $(basename "$deb"): $(du -k "$deb" | cut -f1) KiB, Depends: $(dpkg-deb -f "$deb" Depends)"
done
runtime=$(printf '%s\n' "${!names[@]}" | grep -E '^libsgfx[0-9]+$') || fail "no runtime package libsgfxN: ${!names[*]}"
[ -n "${names[libsgfx-dev]:-}" ] || fail "no libsgfx-dev package"
[ -n "${names[sgfx-tools]:-}" ] || fail "no sgfx-tools package"

# 2. Contents.
files() { dpkg-deb --fsys-tarfile "$1" | tar -t | sed 's#^\./#/#' | grep -v '/$'; }
for deb in "${debs[@]}"; do
  while read -r f; do
    case "$f" in
      /usr/include/sgfx/*) ;;
      /usr/include/*) fail "$(basename "$deb") installs $f outside /usr/include/sgfx/" ;;
    esac
    if owner=$(dpkg -S "$f" 2>/dev/null); then
      owner=${owner%%:*}
      # An earlier install of sgfx's own packages is an upgrade, not a conflict.
      case "$owner" in libsgfx[0-9]* | libsgfx-dev | sgfx-tools) ;; *) fail "$(basename "$deb") would overwrite $f, owned by $owner" ;; esac
    fi
  done < <(files "$deb")
done
# Listed once each (grep -q on a pipe could end it early: SIGPIPE under pipefail).
runtimeFiles=$(files "${names[$runtime]}")
devFiles=$(files "${names[libsgfx-dev]}")
toolFiles=$(files "${names[sgfx-tools]}")
grep -qE '/libsgfx_scenegraph\.so\.[0-9]+$' <<<"$runtimeFiles" || fail "$runtime lacks libsgfx_scenegraph.so.N"
grep -q '/usr/include/sgfx/Viewer.h' <<<"$devFiles" || fail "libsgfx-dev lacks the headers"
grep -q '/cmake/sgfx/sgfxConfig.cmake' <<<"$devFiles" || fail "libsgfx-dev lacks the CMake config"
grep -q '/pkgconfig/sgfx.pc' <<<"$devFiles" || fail "libsgfx-dev lacks sgfx.pc"
grep -q '^/usr/bin/sgfx-view$' <<<"$toolFiles" || fail "sgfx-tools lacks /usr/bin/sgfx-view"
[ -e /usr/include/KHR/khrplatform.h ] || fail "libgl-dev is not installed: the conflict check needs it (apt-get install libgl-dev)"
echo "check_deb: $(for d in "${debs[@]}"; do files "$d"; done | wc -l) files, none owned by an installed package (libgl-dev present)"

# 3. Computed dependencies.
deps=$(dpkg-deb -f "${names[$runtime]}" Depends)
for need in libc6 libstdc++6 libosmesa6 libglfw3; do
  grep -q "$need" <<<"$deps" || fail "$runtime does not depend on $need (dpkg-shlibdeps): $deps"
done

# Every pkg-config module sgfx.pc requires must come from a package libsgfx-dev depends on (else
# `pkg-config sgfx` fails on a system with only libsgfx-dev installed).
mkdir -p "$work/dev"
dpkg-deb -x "${names[libsgfx-dev]}" "$work/dev"
pc=$(find "$work/dev" -name sgfx.pc)
devDepends=$(dpkg-deb -f "${names[libsgfx-dev]}" Depends)
for module in $(sed -n 's/^Requires\(\.private\)\?: *//p' "$pc" | tr ',' ' '); do
  modulePc=$(pkg-config --path "$module") || fail "sgfx.pc requires $module, which pkg-config cannot find here"
  provider=$(dpkg -S "$modulePc" | cut -d: -f1)
  grep -qE "(^|, )$provider( |,|$)" <<<"$devDepends" ||
    fail "sgfx.pc requires $module ($provider), which libsgfx-dev does not depend on: $devDepends"
done
echo "check_deb: sgfx.pc requires $(sed -n 's/^Requires.*: *//p' "$pc" | tr '\n' ' ')- each provided by a libsgfx-dev dependency"

# 4. apt's view: installable together, nothing removed.
sim=$(apt-get install --simulate --no-install-recommends "${debs[@]}" 2>&1) || { echo "$sim"; fail "apt refuses the packages"; }
if grep -q '^Remv' <<<"$sim"; then echo "$sim"; fail "installing the packages would remove others"; fi
echo "check_deb: apt would install them beside the installed packages (no conflict, no removal)"

# 5. A real install on this machine (opt-in: it changes /usr).
if [ "${SGFX_TEST_SYSTEM_INSTALL:-0}" = 1 ]; then
  purge() { apt-get purge -y -qq sgfx-tools libsgfx-dev "$runtime" >/dev/null 2>&1 || true; }
  trap purge EXIT
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${debs[@]}" >"$work/apt.log" 2>&1 ||
    { cat "$work/apt.log"; fail "apt-get install of the packages failed"; }
  cmake -S "$src/tests/consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release >"$work/consumer.log" 2>&1 &&
    cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 || { cat "$work/consumer.log"; fail "consumer against /usr"; }
  "$work/consumer/consumer" || fail "the consumer against the installed packages rendered the wrong pixel"
  # shellcheck disable=SC2046
  c++ -std=c++20 -o "$work/pc_consumer" "$src/tests/consumer/main.cpp" $(pkg-config --cflags --libs sgfx) ||
    fail "pkg-config build against the installed packages"
  "$work/pc_consumer" || fail "the pkg-config consumer against the installed packages"
  sgfx-view --out "$work/view.png" --size 64x48 "$src/../shared/assets/gltf/Box/glTF/Box.gltf" >/dev/null ||
    fail "the installed sgfx-view failed"
  purge
  trap - EXIT
  dpkg -s "$runtime" >/dev/null 2>&1 && fail "purging the packages left $runtime installed"
  echo "check_deb: installed on this system beside libgl-dev, consumer and sgfx-view ran, purged again"
fi
echo "check_deb: PASS"
