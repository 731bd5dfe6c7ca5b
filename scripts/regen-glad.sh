#!/usr/bin/env bash
# Regenerates third_party/glad from python3-glad's bundled (offline) Khronos XML.
set -euo pipefail
cd "$(dirname "$0")/.."
/usr/bin/python3 -m glad --quiet --reproducible --api gl:core=4.5 \
  --extensions GL_KHR_debug,GL_EXT_texture_filter_anisotropic,GL_ARB_texture_filter_anisotropic \
  --out-path third_party/glad c
