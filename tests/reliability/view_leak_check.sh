#!/usr/bin/env bash
# Leak check of `skygraph view` closed mid-frame, on the ASan build (tools/ci.sh runs it in the
# sanitizer stage; docs/reliability.md, Sanitizers). LeakSanitizer is on, with
# tests/reliability/lsan.supp (third-party libraries by name) and the LD_PRELOAD
# libskygraph_keep_loaded.so, without which the libraries the Vulkan loader and GLFW unload
# could be neither named nor suppressed.
#   1. The negative control: leak_control leak-object and leak-device must each fail with a
#      LeakSanitizer report from leak_control.cpp; leak_control clean must pass.
#   2. tests/present/view_test.sh close: the window closed during `skygraph view --validate`
#      must end with exit 0, no validation message and no leak report.
#
# Usage: view_leak_check.sh BUILD_DIR   (an ASan build with skygraph, leak_control and
#                                        skygraph_keep_loaded built)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "$1" && pwd)"
work="$build/view-leak-check"
rm -rf "$work"
mkdir -p "$work"
keep="$build/tests/reliability/libskygraph_keep_loaded.so"
control="$build/tests/reliability/leak_control"
skygraph="$build/tools/skygraph"
for f in "$keep" "$control" "$skygraph"; do [ -e "$f" ] || { echo "view_leak_check: $f is not built" >&2; exit 1; }; done
lvp=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
[ -e "$lvp" ] && export VK_ICD_FILENAMES="$lvp" VK_DRIVER_FILES="$lvp"
export ASAN_OPTIONS="detect_leaks=1"
export LSAN_OPTIONS="suppressions=$root/tests/reliability/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"

fail() { echo "FAIL (view_leak_check): $*" >&2; exit 1; }

for mode in leak-object leak-device; do
    status=0
    LD_PRELOAD="$keep" "$control" "$mode" >"$work/$mode.out" 2>"$work/$mode.err" || status=$?
    [ "$status" -ne 0 ] || fail "leak_control $mode: exit 0, the leak was not reported (see $work/$mode.err)"
    grep -q "ERROR: LeakSanitizer: detected memory leaks" "$work/$mode.err" || fail "leak_control $mode: no LeakSanitizer report"
    grep -q "leak_control.cpp" "$work/$mode.err" || fail "leak_control $mode: the report does not reach leak_control.cpp"
    echo "negative control $mode: $(grep -m1 -E '^(Direct|Indirect) leak' "$work/$mode.err"); $(grep -m1 '^SUMMARY' "$work/$mode.err")"
done
LD_PRELOAD="$keep" "$control" clean >"$work/clean.out" 2>"$work/clean.err" || { cat "$work/clean.err" >&2; fail "leak_control clean reported a leak or failed"; }
echo "control clean: no leak"

# view_test.sh runs "$skygraph" view; this wrapper preloads the library into it alone.
cat >"$work/skygraph" <<WRAPPER
#!/bin/sh
LD_PRELOAD="$keep" exec "$skygraph" "\$@"
WRAPPER
chmod +x "$work/skygraph"
"$root/tests/present/view_test.sh" close "$work/skygraph" "$root" "$work/close" ||
    fail "skygraph view closed mid-frame: not exit 0 without leaks (see $work/close/view.err)"
if grep -q "LeakSanitizer" "$work/close/view.err"; then fail "a LeakSanitizer report in $work/close/view.err"; fi
echo "skygraph view closed mid-frame: exit 0, no leak"
