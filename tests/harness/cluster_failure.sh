#!/bin/sh
# Runs a sgfx-cluster command whose test hook stalls or kills a rank, and prints its output, its
# exit status and how long the run went on after the hook fired ("after_failure=S s") with a
# verdict: "stopped_within_10s=yes" when under 10 s (the bound). The run's start (MPI,
# the scene, frame 0's shader compiles) does not count: it is slow under the sanitizers.
# usage: cluster_failure.sh COMMAND...
out=$("$@" 2>&1)
status=$?
end=$(date +%s.%N)
echo "$out"
echo "exit=$status"
fired=$(echo "$out" | sed -n 's/.*test hook: .* t=\([0-9.]*\)$/\1/p' | head -n 1)
if [ -z "$fired" ]; then
  echo "cluster_failure: the test hook never fired"
  exit 1
fi
echo "$fired $end" | awk '{ d = $2 - $1; printf "after_failure=%.2f s stopped_within_10s=%s\n", d, (d < 10 ? "yes" : "no") }'
