#!/usr/bin/env bash
# window_example end to end on a virtual X server of its own (xvfb-run -a, 24-bit screen), on
# the first Vulkan device (lavapipe without a GPU), under validation with synchronization
# validation.
#
# Usage: window_test.sh CASE EXAMPLE SOURCE_DIR WORKDIR
#   pixels         skygraph's swapchain: screenshots of the window (xwd) show window.json's
#                  checkerboard at 320x240, and again after a resize to 400x300; the same check
#                  with the two colours swapped fails; Escape ends it: exit 0, no message
#   own_pixels     the same with --own-swapchain (the application's VkSwapchainKHR)
#   frames         --frames 60: exit 0, "60 frames presented", no validation message
#   own_frames     the same with --own-swapchain
#   bad_graph      --graph of a file that does not exist: exit 1, stderr names the file
set -euo pipefail
case_name="$1" example="$2" source_dir="$3" work="$4"
mkdir -p "$work"
cd "$work"
rm -f out.txt err.txt shot.ppm

fail() {
    echo "FAIL ($case_name): $*" >&2
    for f in out.txt err.txt; do [ -f "$f" ] && sed "s/^/  $f: /" "$f" >&2; done
    exit 1
}

if [ -z "${WINDOW_TEST_INNER:-}" ]; then
    export WINDOW_TEST_INNER=1
    exec xvfb-run -a -s "-screen 0 1024x768x24" "$0" "$@"
fi

start() { "$example" "$@" >out.txt 2>err.txt & pid=$!; }

# Waits for the example to end; checks exit 0, no validation message, and the line given.
expect_clean_end() {
    local status=0
    wait "$pid" || status=$?
    [ "$status" -eq 0 ] || fail "exit status $status"
    grep -q "validation: 0 message(s)" out.txt || fail "validation messages, or validation off"
    [ -z "$1" ] || grep -q "$1" out.txt || fail "no '$1' in the output"
}

# The example's window once it is mapped (60 s at most).
window_of() {
    local w
    w="$(timeout 60 xdotool search --sync --onlyvisible --name "^skygraph window example$" | head -1)" || true
    [ -n "$w" ] || fail "no window appeared"
    echo "$w"
}

# Screenshots window $1 until it is $2 (WxH) and shows the checkerboard (60 s at most): frames
# before the first present, or from before a resize, show something else.
expect_checkerboard() {
    local w="$1" size="$2" deadline=$((SECONDS + 60))
    while ((SECONDS < deadline)); do
        kill -0 "$pid" 2>/dev/null || fail "ended while waiting for the checkerboard at $size"
        if xwd -silent -id "$w" | convert xwd:- -alpha off -depth 8 ppm:shot.ppm 2>/dev/null &&
            python3 "$source_dir/check_pixels.py" shot.ppm "$source_dir/window.json" --size "$size" >check.txt; then
            cat check.txt
            # Negative control: the same screenshot against the colours the wrong way round.
            if python3 "$source_dir/check_pixels.py" shot.ppm "$source_dir/window.json" --size "$size" --swapped; then
                fail "the pixel check accepts the swapped colours too: it checks nothing"
            fi
            return 0
        fi
        sleep 0.5
    done
    cat check.txt >&2 2>/dev/null || true
    fail "the window never showed window.json's checkerboard at $size (last screenshot: $work/shot.ppm)"
}

case "$case_name" in
    pixels | own_pixels)
        flags=(--validate --size 320x240)
        [ "$case_name" = own_pixels ] && flags+=(--own-swapchain)
        start "${flags[@]}"
        w="$(window_of)"
        expect_checkerboard "$w" 320x240
        xdotool windowsize "$w" 400 300
        expect_checkerboard "$w" 400x300
        xdotool key --window "$w" Escape
        expect_clean_end "last at 400x300"
        ;;
    frames | own_frames)
        flags=(--validate --frames 60)
        [ "$case_name" = own_frames ] && flags+=(--own-swapchain)
        start "${flags[@]}"
        expect_clean_end "^window_example: 60 frames presented"
        ;;
    bad_graph)
        status=0
        "$example" --validate --graph "$work/no_such_graph.json" >out.txt 2>err.txt || status=$?
        [ "$status" -eq 1 ] || fail "exit status $status, expected 1"
        grep -q "no_such_graph.json.*cannot open the file" err.txt || fail "stderr does not name the file"
        ;;
    *)
        echo "unknown case $case_name" >&2
        exit 2
        ;;
esac
echo "$case_name: $(grep -h -e '^window_example:' -e 'cannot open' out.txt err.txt | head -1)"
