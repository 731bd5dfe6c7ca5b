# Shared by the bench/*_table.sh scripts (sourced): the malloc pin and the helpers that read
# `polygon --bench` output.
# llvmpipe timings swing with malloc history: pin it for every program a table compares.
export MALLOC_MMAP_THRESHOLD_=131072
# field NAME: the number after "NAME=" on standard input.
field() { sed -n "s/.*[ ^]$1=\([0-9.]*\).*/\1/p"; }
# median X...: the median of the arguments.
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2}'; }
