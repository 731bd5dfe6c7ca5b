#!/usr/bin/env bash
# sgfx on a machine with an NVIDIA GPU (issue 24, Must 8), in one command and under 8 minutes
# (`timeout 480` around the whole; the report is written step by step, so a run cut short still
# says how far it got):
#   1. the GPU and EGL: nvidia-smi, eglinfo when installed, and the renderer an EGL context gets;
#   2. a Release build into build-gpu (or --build DIR; an existing build is reused);
#   3. the effects table (sgfx-bench --egl: the proving ground without effects, each effect, all
#      of them) with absolute ms at 1280x720 and 1920x1080;
#   4. the frame table against OpenSceneGraph (bench/frame_table.sh with --egl for polygon;
#      osg_polygon stays on OSMesa, its column says so) at 1280x720;
#   5. the test suite with every headless viewer on EGL (SGFX_HEADLESS=egl, see
#      sgfx::Viewer::createHeadless), pass/fail counts and the failures' names, in the time left;
#   6. one Markdown report, gpu-check-DATE.md (or --out FILE).
# --no-gpu runs the same steps on Mesa (EGL on llvmpipe) at tiny sizes and on a subset of the
# tests, to check the script itself where no GPU is (a few minutes on 2 cores: not in ctest).
#
# --no-build uses the build as it is (the targets the steps need must be there).
#
# Usage: scripts/gpu-check.sh [--no-gpu] [--build DIR] [--no-build] [--out FILE] [--tests REGEX]
#                             [--jobs N]
set -uo pipefail
if [ -z "${SGFX_GPU_CHECK_TIMED:-}" ]; then
  export SGFX_GPU_CHECK_TIMED=1
  exec timeout 480 "$0" "$@"
fi
root=$(cd "$(dirname "$0")/.." && pwd)
start=$(date +%s) # the outer timeout's start, near enough
gpu=1; build=$root/build-gpu; out=; tests=; jobs=$(nproc); make=1
while [ $# -gt 0 ]; do
  case $1 in
    --no-gpu) gpu=0 ;;
    --no-build) make=0 ;;
    --build) build=$(realpath -m "$2"); shift ;;
    --out) out=$2; shift ;;
    --tests) tests=$2; shift ;;
    --jobs) jobs=$2; shift ;;
    -h | --help) sed -n '2,/^set -uo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "gpu-check: unknown option '$1' (--no-gpu, --build DIR, --no-build, --out FILE, --tests REGEX, --jobs N)" >&2; exit 2 ;;
  esac
  shift
done
if [ $gpu = 1 ]; then
  effect_sizes=1280x720,1920x1080; effect_frames=60; frame_size=1280x720; frame_rounds=3; frame_frames=30
else
  effect_sizes=160x90; effect_frames=3; frame_size=160x90; frame_rounds=1; frame_frames=3
  tests=${tests:-"Contexts|demo_view_bench|bench_osg_view_orbit|DebugTint"}
fi
out=${out:-gpu-check-$(date -u +%F).md}
log=$(mktemp -d); trap 'rm -rf "$log"' EXIT
status=0
# say TEXT...: appends a line to the report (and shows it).
say() { echo "$*" | tee -a "$out"; }
# step NAME COMMAND...: runs a step, its output to $log/NAME.txt, and reports its time and status.
step() {
  local name=$1; shift
  local t0=$SECONDS rc=0
  echo "gpu-check: $name ..." >&2
  "$@" >"$log/$name.txt" 2>&1 || rc=$?
  say "- $name: $([ $rc = 0 ] && echo ok || echo "FAILED (exit $rc)"), $((SECONDS - t0)) s"
  [ $rc = 0 ] || status=1
  return $rc
}
fence() { say '```text'; tail -n "${2:-40}" "$1" | tee -a "$out"; say '```'; }

: >"$out"
say "# sgfx GPU check, $(date -u '+%F %H:%M') UTC"
say
say "git $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)$([ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ] && echo +dirty), $(nproc) CPU cores, mode: $([ $gpu = 1 ] && echo GPU || echo '--no-gpu (Mesa llvmpipe through EGL, tiny sizes, a subset of the tests)')."
say

# ---- 1. the GPU and EGL
say "## 1. GPU and EGL"
say
if [ $gpu = 1 ]; then
  if ! command -v nvidia-smi >/dev/null; then
    say "nvidia-smi not found: no NVIDIA driver here (use --no-gpu to check the script on Mesa)."
    exit 1
  fi
  step nvidia-smi nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader || exit 1
  fence "$log/nvidia-smi.txt" 4
fi
if command -v eglinfo >/dev/null; then
  step eglinfo sh -c 'eglinfo -B 2>&1 || eglinfo 2>&1' || true
  say; grep -iE "platform|renderer|version string" "$log/eglinfo.txt" | head -12 >"$log/eglinfo.short" || true
  fence "$log/eglinfo.short" 12
else
  say "eglinfo not installed (mesa-utils-bin): the renderer line below comes from sgfx's own EGL context."
fi
say

# ---- 2. the build
say "## 2. Release build ($build)"
say
configure=(cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release)
command -v ccache >/dev/null && configure+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
if [ $make = 1 ]; then
  if [ ! -f "$build/CMakeCache.txt" ]; then step configure "${configure[@]}" || { fence "$log/configure.txt"; exit 1; }; fi
  step build ninja -C "$build" -j "$jobs" || { fence "$log/build.txt"; exit 1; }
else
  say "- build: skipped (--no-build)"
fi
step renderer "$build/demos/polygon" --egl --size 16x16 --scale 0.05 --fog off --out "$log/still.png" || true
renderer=$(sed -n 's/^frame: .* culled (\(.*\))$/\1/p' "$log/renderer.txt")
say
say "EGL renderer: ${renderer:-unknown (see above)}"
if [ $gpu = 1 ] && [[ $renderer != *NVIDIA* ]]; then
  say "WARNING: EGL did not give the NVIDIA GPU (llvmpipe or another device): the figures below are not the GPU's."
  status=1
fi
say

# ---- 3. the effects table, absolute ms
say "## 3. Effects (sgfx-bench --egl, $effect_frames frames, $effect_sizes)"
say
if step effects env PATH=/usr/bin:$PATH "$build/demos/sgfx-bench" --sizes "$effect_sizes" --frames "$effect_frames" \
    --warmup 5 --egl; then
  say; grep '^|' "$log/effects.txt" | tee -a "$out"
else
  fence "$log/effects.txt"
fi
say

# ---- 4. the frame table against OpenSceneGraph
say "## 4. Frame time against OpenSceneGraph (bench/frame_table.sh, sgfx on EGL, OSG on OSMesa)"
say
if [ -x "$build/bench/osg_polygon" ]; then
  if step frame_table "$root/bench/frame_table.sh" "$build" "$frame_rounds" "$frame_frames" "$frame_size" --egl; then
    say; grep -v '^  \|^round ' "$log/frame_table.txt" | tee -a "$out"
  else
    fence "$log/frame_table.txt"
  fi
else
  say "osg_polygon not built (no OpenSceneGraph): no frame table."
fi
say
# ---- 5. the test suite on EGL, last: it gets the time left (ctest --stop-time), so a slow
# suite cannot cut the tables short
say "## 5. Test suite on EGL (SGFX_HEADLESS=egl${tests:+, tests matching $tests})"
say
ctest_args=(--test-dir "$build" -j "$jobs" --timeout 60 --output-on-failure)
[ -n "$tests" ] && ctest_args+=(-R "$tests")
# Tests still queued 20 s before the outer timeout are not started (ctest lists them as not run).
ctest_args+=(--stop-time "$(date -d "@$((start + 460))" +%H:%M:%S)")
step ctest env SGFX_HEADLESS=egl SGFX_GL_ERRORS=throw ctest "${ctest_args[@]}" || true
say
grep -E "tests passed|tests failed out of" "$log/ctest.txt" | tail -1 | sed 's/^/Result: /' | tee -a "$out"
if grep -q "The following tests FAILED" "$log/ctest.txt"; then
  say
  say "Failed:"
  sed -n '/The following tests FAILED/,/^Errors while/p' "$log/ctest.txt" | grep -E '^\s+[0-9]+ - ' | tee -a "$out"
fi
say

say "Overall: $([ $status = 0 ] && echo 'every step passed' || echo 'some step FAILED (see above)')."
echo "gpu-check: wrote $out" >&2
exit $status
