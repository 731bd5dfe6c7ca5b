#!/bin/sh
# Runs one test command and writes its exit status where CTest can see it. CTest ignores the exit
# code of a test that has PASS_REGULAR_EXPRESSION, and LeakSanitizer reports at exit, after the
# success line, with a non-zero code; so a non-zero exit is printed, and FAIL_REGULAR_EXPRESSION
# (set on every test by tests/CMakeLists.txt) fails the test on that line.
"$@"
status=$?
if [ "$status" -ne 0 ]; then
  echo "sgfx-test: '$1' exited with status $status"
fi
exit "$status"
