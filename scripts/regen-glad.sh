#!/usr/bin/env bash
# Regenerates third_party/glad with Debian's python3-glad (2.0.2, offline: its bundled Khronos
# XML), then prefixes every glad symbol and macro with sgfx_/SGFX_ and moves the headers under
# sgfx_glad/: sgfx's loader is private (never installed) and cannot clash with an application's
# own glad, whose glad_glClear, gladLoadGL and <glad/gl.h> stay free (tests/consumer proves it).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 -m glad --quiet --reproducible --api gl:core=4.5 \
  --extensions GL_KHR_debug,GL_EXT_texture_filter_anisotropic,GL_ARB_texture_filter_anisotropic \
  --out-path "$tmp" c
prefix() {
  # Identifiers only: the generator's comment block keeps its names. khrplatform.h keeps its guard:
  # EGL's headers include the system's copy of the same Khronos header, and one of them must win.
  perl -pe 's#<KHR/khrplatform.h>#<sgfx_glad/khrplatform.h>#g; next if m#^\s*(/\*\*|\*\s|\*/|\*$)#;
            s/\bglad/sgfx_glad/g; s/\bGLAD/SGFX_GLAD/g' "$1" > "$2"
}
rm -rf third_party/glad/include third_party/glad/src
mkdir -p third_party/glad/include/sgfx_glad third_party/glad/src
prefix "$tmp/include/glad/gl.h" third_party/glad/include/sgfx_glad/gl.h
prefix "$tmp/include/KHR/khrplatform.h" third_party/glad/include/sgfx_glad/khrplatform.h
prefix "$tmp/src/gl.c" third_party/glad/src/gl.c
