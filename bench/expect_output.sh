#!/usr/bin/env bash
# A smoke run's verdict: COMMAND must exit 0 and print a line matching PATTERN (an extended
# regular expression). ctest's PASS_REGULAR_EXPRESSION alone would ignore the exit status,
# so a run that printed the line and then failed (an exception, a sanitizer report) would pass.
#   bench/expect_output.sh PATTERN COMMAND [ARG...]
set -uo pipefail
pattern=$1
shift
out=$("$@" 2>&1)
status=$?
printf '%s\n' "$out"
if [ "$status" -ne 0 ]; then
    echo "expect_output.sh: exit status $status" >&2
    exit 1
fi
if ! printf '%s\n' "$out" | grep -Eq -- "$pattern"; then
    echo "expect_output.sh: no line matches: $pattern" >&2
    exit 1
fi
