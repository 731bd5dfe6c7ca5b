#!/usr/bin/env bash
# Builds the glTF loader's libFuzzer target with clang (ASan + UBSan, build-fuzz/, the rest of the
# project keeps its own compiler) and runs it for SGFX_FUZZ_SECONDS (60) from a seed corpus made
# of the shared models: .glb files as they are, .gltf files with their buffers (and small images)
# embedded as data: URIs, since the fuzzer's input is one file with no directory around it.
# Fails on any crash, leak, sanitizer report, timeout or out-of-memory; the input that did it is
# left in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=${SGFX_JOBS:-$(nproc)}
seconds=${SGFX_FUZZ_SECONDS:-60}
out=$root/build-fuzz

CC=clang CXX=clang++ cmake -S . -B "$out" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSGFX_FUZZ=ON \
  -DSGFX_BUILD_TESTS=OFF -DSGFX_BUILD_DEMOS=OFF -DSGFX_BUILD_BENCH=OFF >/dev/null
cmake --build "$out" -j "$jobs" --target gltf_fuzzer

seeds=$out/seeds
rm -rf "$seeds" "$out/artifacts"
mkdir -p "$seeds" "$out/corpus" "$out/artifacts"
assets=$root/../shared/assets/gltf
if [ -d "$assets" ]; then
  find "$assets" -name '*.glb' -size -1024k -exec cp {} "$seeds/" \;
  if command -v python3 >/dev/null; then
    python3 - "$assets" "$seeds" <<'PY'
import base64, json, pathlib, struct, sys, zlib
assets, seeds = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
def png2x2():
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    raw = b"".join(b"\0" + bytes([255, 0, 0, 255, 0, 255, 0, 255]) for _ in range(2))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
tiny = "data:image/png;base64," + base64.b64encode(png2x2()).decode()
for path in sorted(assets.rglob("*.gltf")):
    doc = json.loads(path.read_text())
    for b in doc.get("buffers", []):
        if "uri" in b and not b["uri"].startswith("data:"):
            b["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
                (path.parent / b["uri"]).read_bytes()).decode()
    for im in doc.get("images", []):
        if "uri" in im and not im["uri"].startswith("data:"):
            f = path.parent / im["uri"]
            im["uri"] = (("data:image/png;base64," + base64.b64encode(f.read_bytes()).decode())
                         if f.suffix == ".png" and f.stat().st_size < 20000 else tiny)
    text = json.dumps(doc, separators=(",", ":"))
    if len(text) < 256 * 1024:  # big seeds slow every mutation down
        (seeds / (path.stem + ".gltf")).write_text(text)
PY
  else
    find "$assets" -name '*.gltf' -size -256k -exec cp {} "$seeds/" \;
  fi
fi
# Hand-made malformed documents (fuzz/corpus/: animations, skins, morph targets, each breaking one
# element; tests/GltfAnimDoc.h makes them) reach the loader's deeper checks sooner.
cp "$root"/fuzz/corpus/* "$seeds/"
echo "sgfx fuzz: $(ls "$seeds" | wc -l) seeds, ${seconds} s"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:check_initialization_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# New inputs go to corpus/ (kept between runs); libFuzzer exits non-zero on the first finding.
"$out/fuzz/gltf_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
  -artifact_prefix="$out/artifacts/" "$out/corpus" "$seeds"
echo "sgfx fuzz: no crash, leak or sanitizer error in ${seconds} s"

# The display descriptions' reader: a small JSON parser, so a shorter run (SGFX_FUZZ_DISPLAY_SECONDS,
# 20) from the example configs, with the format's keys as a dictionary.
display_seconds=${SGFX_FUZZ_DISPLAY_SECONDS:-20}
cmake --build "$out" -j "$jobs" --target display_fuzzer
display_seeds=$out/seeds-display
rm -rf "$display_seeds"
mkdir -p "$display_seeds" "$out/corpus-display"
cp "$root"/demos/cluster/configs/*.json "$display_seeds/"
echo "sgfx fuzz (display): $(ls "$display_seeds" | wc -l) seeds, ${display_seconds} s"
"$out/fuzz/display_fuzzer" -max_total_time="$display_seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
  -dict="$root/fuzz/display.dict" -artifact_prefix="$out/artifacts/" "$out/corpus-display" "$display_seeds"
echo "sgfx fuzz (display): no crash, leak or sanitizer error in ${display_seconds} s"

# The OpenSceneGraph bridge's target (built when OSG is found): the first byte of an input picks the
# format, the seeds are OSG's small sample files as .osgt. osgDB's own readers crash on corrupt
# files; loadOsg reads each in a child process first, so a finding here is the bridge's bug (or a
# reader that hangs past OsgOptions::readTimeout in the parent too).
if grep -q "osg_fuzzer" "$out/build.ninja"; then
  cmake --build "$out" -j "$jobs" --target osg_fuzzer
  osg_seeds=$out/seeds-osg
  rm -rf "$osg_seeds"
  mkdir -p "$osg_seeds" "$out/corpus-osg"
  osg_assets=$root/../shared/assets/osg
  if [ -d "$osg_assets" ]; then
    for f in "$osg_assets"/*.osgt; do
      if [ "$(stat -c %s "$f")" -lt 65536 ]; then
        { printf '\000'; cat "$f"; } > "$osg_seeds/$(basename "$f")"
      fi
    done
  fi
  # Ours (fuzz/corpus-osg/, made with osgDB from a small graph): one file per format, each cut in
  # half, garbage per format, and every input a past run found (kept as regressions).
  cp "$root"/fuzz/corpus-osg/* "$osg_seeds/"
  echo "sgfx fuzz (OSG): $(ls "$osg_seeds" | wc -l) seeds, ${seconds} s"
  LSAN_OPTIONS=suppressions=$root/fuzz/lsan-osg.supp:print_suppressions=0 \
  "$out/fuzz/osg_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=20 -print_final_stats=1 \
    -artifact_prefix="$out/artifacts/" "$out/corpus-osg" "$osg_seeds"
  echo "sgfx fuzz (OSG): no crash, leak or sanitizer error in ${seconds} s"
fi
