#!/usr/bin/env bash
# `skygraph view` end to end on a virtual X server of its own (xvfb-run -a, 24-bit screen).
#
# Usage: view_test.sh CASE SKYGRAPH ROOT WORKDIR
#   frames       120 frames with validation + synchronization validation: no message
#   resize       the same, the window resized twice mid-run (xdotool windowsize)
#   mailbox      the same with --present-mode mailbox
#   in_flight_K  the same with K frames in flight (1, 2, 3)
#   pixels       a screenshot of the window (xwd) equals `skygraph render` of the same graph,
#                scene and size within one code per channel; Escape then closes it, exit 0
#   close        the window's close button (WM_DELETE_WINDOW) ends it with exit 0
#   signal       SIGTERM ends it with exit 0
#   no_display   without an X server: exit 1 and one line that suggests `skygraph render`
set -euo pipefail
case_name="$1" skygraph="$2" root="$3" work="$4"
mkdir -p "$work"
cd "$work"

fail() { echo "FAIL ($case_name): $*" >&2; for f in view.out view.err; do [ -f "$f" ] && sed "s/^/  $f: /" "$f" >&2; done; exit 1; }

if [ "$case_name" = no_display ]; then
    for display in unset ":97531"; do
        set +e
        if [ "$display" = unset ]; then
            env -u DISPLAY -u WAYLAND_DISPLAY "$skygraph" view --frames 1 >view.out 2>view.err
        else
            env -u WAYLAND_DISPLAY DISPLAY="$display" "$skygraph" view --frames 1 >view.out 2>view.err
        fi
        status=$?
        set -e
        [ "$status" -ne 0 ] || fail "exit 0 without a display ($display)"
        [ "$(wc -l <view.err)" -eq 1 ] || fail "expected one line on stderr ($display)"
        grep -q "no display" view.err || fail "the line does not say there is no display ($display)"
        grep -q "skygraph render" view.err || fail "the line does not suggest skygraph render ($display)"
    done
    echo "no display: $(cat view.err)"
    exit 0
fi

# Everything else runs on an X server of its own: this script again, under xvfb-run.
if [ -z "${SKYGRAPH_VIEW_TEST_INNER:-}" ]; then
    export SKYGRAPH_VIEW_TEST_INNER=1
    exec xvfb-run -a -s "-screen 0 1024x768x24" "$0" "$@"
fi

# The window of the view process, once it is mapped (60 s at most).
window_of() {
    local w
    w="$(timeout 60 xdotool search --sync --onlyvisible --name "^skygraph view" | head -1)" || true
    [ -n "$w" ] || fail "no window appeared"
    echo "$w"
}

# Waits for the view process ($1) to end and checks exit 0, N frames, no validation message.
expect_clean_end() {
    local pid="$1" frames="$2" status=0
    wait "$pid" || status=$?
    [ "$status" -eq 0 ] || fail "exit status $status"
    [ -z "$frames" ] || grep -q "^skygraph view: $frames frames presented" view.out || fail "not $frames frames"
    grep -q "validation: 0 message(s)" view.out || fail "validation messages"
}

# Waits (up to 60 s) until the log names a swapchain of $1 (WxH).
wait_for_swapchain() {
    for _ in $(seq 600); do
        grep -q "swapchain: .* at $1," view.err && return 0
        kill -0 "$pid" 2>/dev/null || fail "ended before the swapchain was $1"
        sleep 0.1
    done
    fail "no swapchain of $1"
}

# WM_DELETE_WINDOW to window $1, as a window manager sends for the close button.
close_window() {
    python3 - "$1" <<'EOF'
import ctypes, ctypes.util, sys
x = ctypes.CDLL(ctypes.util.find_library("X11"))
x.XOpenDisplay.restype = ctypes.c_void_p
x.XInternAtom.restype = ctypes.c_ulong
x.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
x.XSendEvent.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_long, ctypes.c_void_p]
x.XFlush.argtypes = [ctypes.c_void_p]
class ClientMessage(ctypes.Structure):
    _fields_ = [("type", ctypes.c_int), ("serial", ctypes.c_ulong), ("send_event", ctypes.c_int),
                ("display", ctypes.c_void_p), ("window", ctypes.c_ulong), ("message_type", ctypes.c_ulong),
                ("format", ctypes.c_int), ("l", ctypes.c_long * 5)]
class Event(ctypes.Union):
    _fields_ = [("xclient", ClientMessage), ("pad", ctypes.c_long * 24)]
d = x.XOpenDisplay(None)
window = int(sys.argv[1])
e = Event()
e.xclient.type = 33  # ClientMessage
e.xclient.window = window
e.xclient.message_type = x.XInternAtom(d, b"WM_PROTOCOLS", 0)
e.xclient.format = 32
e.xclient.l[0] = x.XInternAtom(d, b"WM_DELETE_WINDOW", 0)
e.xclient.l[1] = 0  # CurrentTime
x.XSendEvent(d, window, 0, 0, ctypes.byref(e))
x.XFlush(d)
EOF
}

view() { "$skygraph" view "$@" >view.out 2>view.err & pid=$!; }

case "$case_name" in
    frames)
        view --validate --frames 120
        expect_clean_end "$pid" 120
        ;;
    mailbox)
        view --validate --frames 120 --present-mode mailbox
        expect_clean_end "$pid" 120
        grep -q "(mailbox)" view.out || fail "not presented with mailbox"
        ;;
    in_flight_[123])
        k="${case_name#in_flight_}"
        view --validate --frames 120 --frames-in-flight "$k"
        expect_clean_end "$pid" 120
        ;;
    resize)
        view --validate --frames 120 --width 256 --height 256
        w="$(window_of)"
        wait_for_swapchain 256x256
        xdotool windowsize "$w" 320 200
        wait_for_swapchain 320x200
        xdotool windowsize "$w" 200 300
        wait_for_swapchain 200x300
        expect_clean_end "$pid" 120
        grep -q "last at 200x300" view.out || fail "the last frames were not at 200x300"
        ;;
    pixels)
        "$skygraph" render --width 256 --height 256 -o render.png >render.log 2>&1 || fail "skygraph render failed"
        convert render.png -alpha off -depth 8 rgb:render.rgb
        view --validate --width 256 --height 256
        w="$(window_of)"
        # Frames before the first present show nothing yet: retry until one is on screen.
        matched=""
        for _ in $(seq 120); do
            xwd -silent -id "$w" | convert xwd:- -alpha off -depth 8 rgb:view.rgb 2>/dev/null || true
            if python3 - <<'EOF'
import sys
a, b = open("render.rgb", "rb").read(), open("view.rgb", "rb").read()
if len(a) != len(b):
    sys.exit(1)
worst = max(abs(x - y) for x, y in zip(a, b))
print(f"largest difference: {worst} codes over {len(a) // 3} pixels")
sys.exit(0 if worst <= 1 else 1)
EOF
            then matched=1; break; fi
            sleep 0.5
        done
        convert -size 256x256 -depth 8 rgb:view.rgb view.png 2>/dev/null || true
        [ -n "$matched" ] || fail "the window never showed what skygraph render writes (see $work/view.png, render.png)"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        ;;
    close)
        view --validate
        w="$(window_of)"
        wait_for_swapchain 256x256
        sleep 1
        close_window "$w"
        expect_clean_end "$pid" ""
        ;;
    signal)
        view --validate
        window_of >/dev/null
        wait_for_swapchain 256x256
        sleep 1
        kill -TERM "$pid"
        expect_clean_end "$pid" ""
        ;;
    *)
        echo "unknown case $case_name" >&2
        exit 2
        ;;
esac
echo "$case_name: $(head -1 view.out)"
