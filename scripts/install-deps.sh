#!/usr/bin/env bash
# Installs the Debian 12 packages sgfx needs, only those missing. Nothing else is downloaded:
# sgfx's GL loader (glad, prefixed) is committed pre-generated under third_party/glad.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config   # toolchain
  libglm-dev libglfw3-dev libstb-dev             # math, windows, PNG
  libimgui-dev                                   # sgfx-view's panel (Dear ImGui)
  libtinygltf-dev nlohmann-json3-dev             # glTF 2.0 loading
  libopenmesh-dev                                # OBJ/OFF/PLY/STL meshes
  libmeshoptimizer-dev                           # vertex-cache/overdraw order and LODs of loaded meshes
  libosmesa6-dev                                 # software OpenGL 4.5 core (llvmpipe), headless
  libegl-dev libegl1 libegl-mesa0                # headless GPU contexts (libEGL is opened at run time)
  libgtest-dev libbenchmark-dev                  # tests and benchmarks
  clang libclang-rt-14-dev                       # the glTF loader's libFuzzer target (scripts/fuzz.sh)
  libopenscenegraph-dev                          # the OpenSceneGraph peer benchmark
  libcli11-dev                                   # every demo's options, osg_view's and the bench tools' (CLI11)
  libopenmpi-dev openmpi-bin                     # sgfx-cluster: display channels on MPI ranks
  xvfb xauth libgl1-mesa-dri libglx-mesa0        # the windowed path tested on a virtual display
  python3-matplotlib                             # sgfx-bench --plot (scripts/plot_bench.py)
  python3-glad                                   # the packaging test's "application with its own glad"
  dpkg-dev libgl-dev                             # Debian packages (dpkg-shlibdeps); the conflict check
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "sgfx: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "sgfx: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
