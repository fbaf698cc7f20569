#!/usr/bin/env bash
# `skygraph view` end to end on a virtual X server of its own (xvfb-run -a, 24-bit screen).
#
# Usage: view_test.sh CASE SKYGRAPH ROOT WORKDIR
#   frames       120 frames with validation + synchronization validation: no message; each
#                culled pass is logged once
#   resize       the same, the window resized twice mid-run (xdotool windowsize)
#   mailbox      the same with --present-mode mailbox
#   in_flight_K  the same with K frames in flight (1, 2, 3)
#   pixels       with --no-ui, a screenshot of the window (xwd) equals `skygraph render` of the
#                same graph, scene and size within one code per channel; Escape closes it, exit 0
#   compute_pixels  the same with the compute tonemap writing the swapchain as a storage image
#   compute_ui   60 frames with the overlay drawn after the compute tonemap: no message
#   ui_pixels    with the overlay: outside its rectangle the window equals `skygraph render`
#                within one code, inside it most pixels differ
#   click        a click on the overlay's skybox checkbox culls the skybox (the log says why)
#                and the sky's pixels become the clear colour
#   hot_reload   a broken graph edit keeps the last good frame and shows the message (the
#                overlay's layout moves down for it); the fixed edit (no skybox pass) renders
#   shader_reload  a broken shader keeps the last good frame and shows glslang's message, also
#                through two resizes and a checkbox's rebuild; the fixed one clears it
#   graph_shader_reload  a graph saved while a shader is broken does not build; fixing the
#                shader brings in the saved graph (no skybox pass), not the old graph's pipelines
#   feature_removed  a feature the overlay set, then removed from the saved graph, is dropped:
#                the save builds
#   screenshot   F12 writes a PNG equal to the window's pixels (xwd) within one code, twice
#   close        the window's close button (WM_DELETE_WINDOW) ends it with exit 0
#   signal       SIGTERM ends it with exit 0
#   unpresentable  a graph presenting a format the surface lacks, or an image of a fixed size
#                other than the window's: exit 1, the error named at the resource's declaration
#   no_display   without an X server: exit 1 and one line that suggests `skygraph render`;
#                a graph file that is missing is named first
set -euo pipefail
case_name="$1" skygraph="$2" root="$3" work="$4"
# Nothing from an earlier run may stand in for this one's captures and comparisons.
rm -rf "$work"
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
    # What is wrong with the inputs is said first, not hidden behind "no display":
    # refused WHAT EXPECTED_LINE VIEW_ARGS...
    refused() {
        local what="$1" expected="$2"
        shift 2
        set +e
        env -u DISPLAY -u WAYLAND_DISPLAY "$skygraph" view "$@" --frames 1 >view.out 2>view.err
        status=$?
        set -e
        [ "$status" -eq 1 ] || fail "$what without a display exited $status"
        grep -q "$expected" view.err || fail "$what is not named"
        ! grep -q "no display" view.err || fail "'no display' hid $what"
    }
    refused "a missing graph file" "no_such_graph.json: cannot open the file" "$work/no_such_graph.json"
    refused "a missing scene file" "no_such_scene.json" --scene "$work/no_such_scene.json"
    refused "an unknown feature" "unknown feature 'no_such_feature'" --feature no_such_feature=on
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

# The window's pixels as raw RGB in $2.
capture() { xwd -silent -id "$1" | convert xwd:- -alpha off -depth 8 "rgb:$2" 2>/dev/null; }

# compare.py A.rgb B.rgb WIDTH [X Y W H]: the largest difference outside the rectangle (the
# whole image without one), and the fraction of pixels inside it that differ by more than 8,
# into compare.txt.
cat >compare.py <<'EOF'
import sys
a, b = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
width = int(sys.argv[3])
rect = [int(v) for v in sys.argv[4:8]] if len(sys.argv) > 4 else None
if len(a) != len(b):
    print("sizes differ")
    sys.exit(2)
outside, inside, changed = 0, 0, 0
for i in range(0, len(a), 3):
    x, y = (i // 3) % width, (i // 3) // width
    d = max(abs(a[i + c] - b[i + c]) for c in range(3))
    if rect and rect[0] <= x < rect[0] + rect[2] and rect[1] <= y < rect[1] + rect[3]:
        inside += 1
        changed += d > 8
    else:
        outside = max(outside, d)
print(f"outside: {outside} codes at most; inside: {changed} of {inside} pixels differ")
print(outside, changed / inside if inside else 0.0, file=open("compare.txt", "w"))
EOF

# "R G B" of pixel ($3, $4) of the raw image $1 of width $2.
pixel() { python3 -c "d = open('$1', 'rb').read(); i = 3 * ($4 * $2 + $3); print(*d[i:i + 3])"; }

# Waits (up to 60 s) until the log matches $1.
wait_for_log() {
    for _ in $(seq 600); do
        grep -q -- "$1" view.err && return 0
        kill -0 "$pid" 2>/dev/null || fail "ended before the log said '$1'"
        sleep 0.1
    done
    fail "the log never said '$1'"
}

# The sky pixel (630, 10) of 640-wide window $1, captured into $2 until it is the clear colour
# (30 s at most); prints the last value.
sky_until_clear() {
    local sky=""
    for _ in $(seq 60); do
        capture "$1" "$2"
        sky="$(pixel "$2" 640 630 10)"
        [ "$sky" = "0 0 0" ] && break
        sleep 0.5
    done
    echo "$sky"
}

# Waits (30 s at most) until the skybox checkbox's logged y compares to $2 by test operator $1
# (-gt: the controls moved down for a message, -eq: back); prints the last y.
checkbox_y_until() {
    local y=""
    for _ in $(seq 60); do
        read -r _ y <<<"$(checkbox_of skybox)"
        [ "$y" "$1" "$2" ] && break
        sleep 0.5
    done
    echo "$y"
}

# The overlay's last logged rectangle as "X Y W H".
overlay_rect() { grep "overlay: window at" view.err | tail -1 | sed -E 's/.* at ([0-9]+),([0-9]+) ([0-9]+)x([0-9]+).*/\1 \2 \3 \4/'; }
# The centre of feature $1's checkbox, as last logged, as "X Y".
checkbox_of() { grep "overlay: feature checkboxes" view.err | tail -1 | tr ' ' '\n' | grep "^$1=" | sed -E 's/.*=([0-9]+),([0-9]+)/\1 \2/'; }

# Saves graph.json as graphs/raster.json without its skybox pass, by a rename as editors do.
save_raster_without_skybox() {
    python3 - "$root/graphs/raster.json" <<'EOF'
import json, sys
g = json.load(open(sys.argv[1]))
g["passes"] = [p for p in g["passes"] if p["type"] != "SkyboxPass"]
json.dump(g, open("graph.json.tmp", "w"), indent=1)
EOF
    mv graph.json.tmp graph.json
}

case "$case_name" in
    frames)
        view --validate --frames 120
        expect_clean_end "$pid" 120
        # One plan, so each of its culled passes is logged once, when it is built.
        grep -q "^info: culled " view.err || fail "the plan's culled passes are not logged"
        twice="$(grep "^info: culled " view.err | sort | uniq -d || true)"
        [ -z "$twice" ] || fail "culled passes logged more than once: $twice"
        ;;
    compute_ui)
        view --validate --frames 60 --feature compute_tonemap=on
        expect_clean_end "$pid" 60
        grep -q "pass ui_compute" view.err || fail "the overlay did not run after the compute tonemap"
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
    pixels | compute_pixels)
        features=()
        [ "$case_name" = pixels ] || features=(--feature compute_tonemap=on)
        "$skygraph" render --validate "${features[@]}" --width 256 --height 256 -o render.png >render.log 2>&1 ||
            fail "skygraph render failed"
        convert render.png -alpha off -depth 8 rgb:render.rgb
        view --validate --no-ui "${features[@]}" --width 256 --height 256
        w="$(window_of)"
        # Frames before the first present show nothing yet: retry until one is on screen.
        matched=""
        for _ in $(seq 120); do
            rm -f view.rgb
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
    ui_pixels)
        "$skygraph" render --validate --width 640 --height 480 -o render.png >render.log 2>&1 || fail "skygraph render failed"
        convert render.png -alpha off -depth 8 rgb:render.rgb
        view --validate --width 640 --height 480
        w="$(window_of)"
        wait_for_log "overlay: window at"
        matched=""
        for _ in $(seq 120); do
            rm -f view.rgb compare.txt
            capture "$w" view.rgb || true
            # shellcheck disable=SC2046
            python3 compare.py render.rgb view.rgb 640 $(overlay_rect) || true
            outside="" inside=""
            read -r outside inside <compare.txt || true
            if [ "${outside:-99}" -le 1 ] && python3 -c "import sys; sys.exit(0 if ${inside:-0} > 0.5 else 1)"; then
                matched=1
                break
            fi
            sleep 0.5
        done
        convert -size 640x480 -depth 8 rgb:view.rgb view.png 2>/dev/null || true
        [ -n "$matched" ] || fail "outside the overlay ($(overlay_rect)) the window is not the render, or no overlay (see $work/view.png)"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        ;;
    click)
        view --validate --width 640 --height 480
        w="$(window_of)"
        wait_for_log "overlay: feature checkboxes"
        sleep 2
        capture "$w" before.rgb
        sky_before="$(pixel before.rgb 640 630 10)"
        [ "$sky_before" != "0 0 0" ] || fail "no sky before the click"
        read -r x y <<<"$(checkbox_of skybox)"
        [ -n "$x" ] || fail "the overlay logged no skybox checkbox"
        xdotool mousemove --window "$w" "$x" "$y" click 1
        wait_for_log "culled skybox: "
        sky="$(sky_until_clear "$w" after.rgb)"
        [ "$sky" = "0 0 0" ] || fail "the sky pixel is $sky after the click, not the clear colour (was $sky_before)"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        grep -q "culled skybox: condition 'skybox && !environment_file' is false (skybox=off" view.err ||
            fail "the log does not say why the skybox was culled"
        echo "click: sky $sky_before -> $sky"
        ;;
    hot_reload)
        cp "$root/graphs/raster.json" graph.json
        view --validate --width 640 --height 480 graph.json --scene "$root/scenes/default.json"
        w="$(window_of)"
        wait_for_log "overlay: feature checkboxes"
        sleep 2
        capture "$w" good.rgb
        sky_good="$(pixel good.rgb 640 630 10)"
        read -r _ y_good <<<"$(checkbox_of skybox)"
        printf '{ "version": 1, "passes": [ ' >graph.json  # a save cut short
        y_broken="$(checkbox_y_until -gt "$y_good")"
        [ "$y_broken" -gt "$y_good" ] || fail "the overlay shows no message (its controls did not move down)"
        grep -q "warning: .*graph.json" view.err || fail "the log has no message naming graph.json"
        capture "$w" broken.rgb
        [ "$(pixel broken.rgb 640 630 10)" = "$sky_good" ] || fail "the last good frame is not on screen"
        save_raster_without_skybox
        wait_for_log "reload: first frame of the new plan presented"
        sky="$(sky_until_clear "$w" fixed.rgb)"
        [ "$sky" = "0 0 0" ] || fail "the fixed graph (no skybox pass) does not render: sky $sky"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        grep -q " 1 reload(s)" view.out || fail "not one reload"
        grep "reload: first frame" view.err
        ;;
    shader_reload)
        cp -r "$root/shaders" shaders
        SKYGRAPH_SHADER_DIR="$PWD/shaders" view --validate --width 640 --height 480
        w="$(window_of)"
        wait_for_log "overlay: feature checkboxes"
        sleep 2
        capture "$w" good.rgb
        sky_good="$(pixel good.rgb 640 630 10)"
        read -r _ y_good <<<"$(checkbox_of skybox)"
        cp shaders/passes/tonemap.frag tonemap.frag.good
        echo "this is not GLSL" >>shaders/passes/tonemap.frag
        y_broken="$(checkbox_y_until -gt "$y_good")"
        [ "$y_broken" -gt "$y_good" ] || fail "the overlay shows no message for the broken shader"
        grep -q "tonemap.frag. does not compile" view.err || fail "the log has no glslang message naming tonemap.frag"
        capture "$w" broken.rgb
        [ "$(pixel broken.rgb 640 630 10)" = "$sky_good" ] || fail "the last good frame is not on screen"
        # Resized meanwhile: the new swapchain's pipelines come from the sources that ran.
        xdotool windowsize "$w" 600 440
        wait_for_swapchain 600x440
        xdotool windowsize "$w" 640 480
        wait_for_swapchain 640x480
        # A checkbox meanwhile rebuilds from the sources that ran too: the sky goes, glslang is
        # not run on the broken file again, and its message stays.
        read -r x y <<<"$(checkbox_of skybox)"
        xdotool mousemove --window "$w" "$x" "$y" click 1
        wait_for_log "culled skybox: "
        [ "$(sky_until_clear "$w" unchecked.rgb)" = "0 0 0" ] || fail "the click did not take the sky away"
        [ "$(grep -c "tonemap.frag. does not compile" view.err)" -eq 1 ] || fail "the click's rebuild read the broken shader"
        read -r _ y_clicked <<<"$(checkbox_of skybox)"
        [ "$y_clicked" -eq "$y_broken" ] || fail "the shader's message went with the click's rebuild"
        # Restored the way editors save, by a rename: a copy in place passes through an empty
        # file, and a poll that hashes it then compiles the whole one a moment later and
        # reloads again when it hashes that.
        cp tonemap.frag.good tonemap.frag.restored
        mv tonemap.frag.restored shaders/passes/tonemap.frag
        y_fixed="$(checkbox_y_until -eq "$y_good")"
        [ "$y_fixed" -eq "$y_good" ] || fail "the message stays after the shader was fixed"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        grep -q " 2 reload(s)" view.out || fail "not two reloads (the click's and the fixed shader's)"
        ;;
    graph_shader_reload)
        cp -r "$root/shaders" shaders
        cp "$root/graphs/raster.json" graph.json
        SKYGRAPH_SHADER_DIR="$PWD/shaders" view --validate --width 640 --height 480 graph.json \
            --scene "$root/scenes/default.json"
        w="$(window_of)"
        wait_for_log "overlay: feature checkboxes"
        sleep 2
        capture "$w" good.rgb
        sky_good="$(pixel good.rgb 640 630 10)"
        cp shaders/passes/tonemap.frag tonemap.frag.good
        echo "this is not GLSL" >>shaders/passes/tonemap.frag
        wait_for_log "tonemap.frag. does not compile"
        save_raster_without_skybox
        # The save's build fails on the shader too: a second message.
        for _ in $(seq 600); do
            [ "$(grep -c "tonemap.frag. does not compile" view.err)" -ge 2 ] && break
            sleep 0.1
        done
        [ "$(grep -c "tonemap.frag. does not compile" view.err)" -ge 2 ] || fail "the saved graph was not built"
        capture "$w" broken.rgb
        [ "$(pixel broken.rgb 640 630 10)" = "$sky_good" ] || fail "the last good frame is not on screen"
        cp tonemap.frag.good tonemap.frag.restored
        mv tonemap.frag.restored shaders/passes/tonemap.frag
        sky="$(sky_until_clear "$w" fixed.rgb)"
        [ "$sky" = "0 0 0" ] || fail "the fixed shader did not bring in the graph saved beside it (no skybox pass): sky $sky"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        ;;
    feature_removed)
        cp "$root/graphs/raster.json" graph.json
        view --validate --width 640 --height 480 graph.json
        w="$(window_of)"
        wait_for_log "overlay: feature checkboxes"
        sleep 2
        read -r x y <<<"$(checkbox_of skybox)"
        [ -n "$x" ] || fail "the overlay logged no skybox checkbox"
        xdotool mousemove --window "$w" "$x" "$y" click 1
        wait_for_log "culled skybox: "
        # Saved without the feature the click set: the save builds, the feature is dropped.
        python3 - "$root/graphs/raster.json" <<'EOF'
import json, re, sys
g = json.load(open(sys.argv[1]))
del g["features"]["skybox"]
for p in g["passes"]:
    if "if" in p:
        p["if"] = re.sub(r"\bskybox\b", "false", p["if"])
json.dump(g, open("graph.json.tmp", "w"), indent=1)
EOF
        mv graph.json.tmp graph.json
        wait_for_log "reload: first frame of the new plan presented"
        grep -q "feature 'skybox' is not declared by the graph any more: dropped" view.err ||
            fail "the log does not say the feature was dropped"
        ! grep -q "unknown feature" view.err || fail "the save was refused for the feature the click set"
        xdotool key --window "$w" Escape
        expect_clean_end "$pid" ""
        grep -q " 2 reload(s)" view.out || fail "not two reloads (the click's and the save's)"
        ;;
    screenshot)
        view --validate --no-ui --width 320 --height 240
        w="$(window_of)"
        wait_for_swapchain 320x240
        sleep 2
        xdotool key --window "$w" F12
        wait_for_log "screenshot: skygraph-view-1.png"
        capture "$w" window.rgb
        convert skygraph-view-1.png -alpha off -depth 8 rgb:shot.rgb
        python3 compare.py window.rgb shot.rgb 320
        read -r outside _ <compare.txt
        [ "$outside" -le 1 ] || fail "the screenshot differs from the window by $outside codes"
        # The plan is compiled back after the first: a second screenshot works the same.
        xdotool key --window "$w" F12
        wait_for_log "screenshot: skygraph-view-2.png"
        convert skygraph-view-2.png -alpha off -depth 8 rgb:shot2.rgb
        python3 compare.py window.rgb shot2.rgb 320
        read -r outside _ <compare.txt
        [ "$outside" -le 1 ] || fail "the second screenshot differs from the window by $outside codes"
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
    unpresentable)
        # refused_at_declaration FILE SED_EDIT GREP_CHECK EXPECTED WHAT: raster.json edited by
        # SED_EDIT into FILE exits 1 with the error named at the resource's declaration.
        refused_at_declaration() {
            local file="$1" edit="$2" applied="$3" expected="$4" what="$5"
            sed "$edit" "$root/graphs/raster.json" >"$file"
            grep -q "$applied" "$file" || fail "the edit for $what did not apply"
            view "$file" --frames 1
            status=0
            wait "$pid" || status=$?
            [ "$status" -eq 1 ] || fail "$what: exit status $status"
            grep -q "$expected" view.err || fail "$what is not named at its declaration"
        }
        declared='"swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB"'
        # A format the window's surface lacks.
        refused_at_declaration f16.json "s/$declared/\"swapchain\": { \"type\": \"image2d\", \"format\": \"R16G16B16A16_SFLOAT\"/" \
            R16G16B16A16_SFLOAT "^error: f16.json: resources.swapchain: the surface cannot present R16G16B16A16_SFLOAT" \
            "an unpresentable format"
        # A fixed size other than the window's, with what to write instead.
        refused_at_declaration fixed.json "s/$declared, \"extent\": \"output\"/$declared, \"extent\": [50, 40]/" \
            '"extent": \[50, 40\]' \
            "^error: fixed.json: resources.swapchain: present resource 'swapchain': the plan's is 50x40, .*give it \"extent\": \"output\"" \
            "a fixed-size presented image"
        ;;
    *)
        echo "unknown case $case_name" >&2
        exit 2
        ;;
esac
echo "$case_name: $(head -1 view.out)"
