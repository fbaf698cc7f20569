#!/usr/bin/env bash
# `skygraph view` with a device that cannot be used: exit 1 and one line on stderr that names
# the device and says why.
#
# Usage: view_device_test.sh CASE SKYGRAPH WORKDIR
#   no_such_device  --device names no device: the line names the filter and lists the devices
#   cannot_present  a window on an 8-bit PseudoColor screen (Xvfb), which Mesa's X11
#                   presentation does not support: the line names lavapipe (index and name) and
#                   says it cannot present to the surface; with --device by name, by index and
#                   without --device
set -euo pipefail
case_name="$1" skygraph="$2" work="$3"
self="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
mkdir -p "$work"
cd "$work"

fail() { echo "FAIL ($case_name): $*" >&2; for f in view.out view.err; do [ -f "$f" ] && sed "s/^/  $f: /" "$f" >&2; done; exit 1; }

# Runs `skygraph view --frames 1 ARGS...` and expects exit 1 and, after the log's info lines,
# one line on stderr: the error, last.
expect_one_line_error() {
    local status=0
    "$skygraph" view --frames 1 "$@" >view.out 2>view.err || status=$?
    [ "$status" -eq 1 ] || fail "exit status $status with $*, not 1"
    [ "$(grep -vc '^info: ' view.err)" -eq 1 ] || fail "expected one line besides the log's info lines with $*"
    tail -1 view.err | grep -q "^skygraph view: " || fail "the last line is not the command's error"
}

case "$case_name" in
    no_such_device)
        if [ -z "${SKYGRAPH_VIEW_TEST_INNER:-}" ]; then
            export SKYGRAPH_VIEW_TEST_INNER=1
            exec xvfb-run -a -s "-screen 0 1024x768x24" "$self" "$@"
        fi
        expect_one_line_error --device no-such-gpu-9000
        grep -q "no Vulkan device matches --device 'no-such-gpu-9000'" view.err || fail "the filter is not named"
        grep -q "available devices: 0: llvmpipe" view.err || fail "the devices are not listed"
        ;;
    cannot_present)
        if [ -z "${SKYGRAPH_VIEW_TEST_INNER:-}" ]; then
            export SKYGRAPH_VIEW_TEST_INNER=1
            exec xvfb-run -a -s "-screen 0 1024x768x8" "$self" "$@"
        fi
        for device in llvmpipe 0 ""; do
            if [ -n "$device" ]; then expect_one_line_error --validate --device "$device"
            else expect_one_line_error --validate; fi
            grep -Eq "Vulkan device,? 0 'llvmpipe" view.err || fail "the device is not named (--device '$device')"
            grep -q "cannot present to the surface" view.err || fail "no reason (--device '$device')"
        done
        ;;
    *)
        echo "unknown case $case_name" >&2
        exit 2
        ;;
esac
echo "$case_name: $(tail -1 view.err)"
