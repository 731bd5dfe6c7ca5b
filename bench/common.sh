# Shared by the bench/*_table.sh scripts (sourced): the malloc pin and the helpers that read
# `polygon --bench` output.
# llvmpipe timings swing with malloc history: pin it for every program a table compares.
# The mmap threshold fixes where big blocks come from; the trim threshold stops glibc from
# returning the top of the heap after every large free: Mesa's per-draw vertex buffers otherwise
# make it shrink and regrow the heap ~60 times a frame (strace -e brk), page faults and TLB
# flushes included, in whichever program's heap layout happens to put them at the top.
export MALLOC_MMAP_THRESHOLD_=131072
export MALLOC_TRIM_THRESHOLD_=268435456
# field NAME: the number after "NAME=" on standard input.
field() { sed -n "s/.*[ ^]$1=\([0-9.]*\).*/\1/p"; }
# median X...: the median of the arguments.
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
# ratios A B: the per-round ratios A[i]/B[i] of two arrays of equal length (names), one a line.
ratios() { local -n _a=$1 _b=$2; local i; for i in "${!_a[@]}"; do awk -v a="${_a[$i]}" -v b="${_b[$i]}" 'BEGIN { print a / b }'; done; }
# median_ratio A B: the median of the per-round ratios A[i]/B[i] (drift between rounds cancels).
median_ratio() { median $(ratios "$1" "$2"); }
# stamp BUILD_DIR [polygon flags, e.g. --egl]: the line every table starts with: when (UTC), the
# source's git revision (+dirty) and the GL renderer polygon gets, the CPU count.
stamp() {
  local build=$1; shift
  local src; src=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  local rev; rev=$(git -C "$src" rev-parse --short HEAD 2>/dev/null || echo unknown)
  [ -n "$(git -C "$src" status --porcelain --untracked-files=no 2>/dev/null)" ] && rev="$rev+dirty"
  local png; png=$(mktemp --suffix=.png)
  local gl; gl=$("$build/demos/polygon" --size 16x16 --scale 0.05 --fog off --out "$png" "$@" 2>/dev/null |
    sed -n 's/^frame: .* culled (\(.*\))$/\1/p') || true # no polygon: an unknown renderer
  rm -f "$png"
  echo "Measured $(date -u '+%F %H:%M') UTC at git $rev on ${gl:-an unknown renderer}, $(nproc) CPU cores."
}
