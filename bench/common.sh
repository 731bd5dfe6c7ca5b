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
