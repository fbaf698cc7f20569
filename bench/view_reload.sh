#!/usr/bin/env bash
# The time from saving a graph file to the first frame of its new plan on screen in
# `skygraph view` (docs/performance.md, "Presenting"): N saves of graphs/raster.json's copy,
# one every 1.5 s, each waiting for view's "reload:" line; prints each and the medians.
#
# Usage: bench/view_reload.sh SKYGRAPH [N=15] [WIDTHxHEIGHT=640x480] [view options...]
# Runs on a virtual X server of its own (xvfb-run -a), lavapipe when it is installed.
set -euo pipefail
skygraph="$(realpath "$1")"
n="${2:-15}"
size="${3:-640x480}"
shift $(($# < 3 ? $# : 3))
root="$(cd "$(dirname "$0")/.." && pwd)"
lvp=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
[ -f "$lvp" ] && export VK_ICD_FILENAMES="$lvp" VK_DRIVER_FILES="$lvp"
if [ -z "${SKYGRAPH_RELOAD_BENCH_INNER:-}" ]; then
    export SKYGRAPH_RELOAD_BENCH_INNER=1
    exec xvfb-run -a -s "-screen 0 1920x1200x24" "$0" "$skygraph" "$n" "$size" "$@"
fi
work="$(mktemp -d)"
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
cd "$work"
cp "$root/graphs/raster.json" graph.json
"$skygraph" view graph.json --scene "$root/scenes/default.json" --width "${size%x*}" --height "${size#*x}" "$@" \
    >view.out 2>view.err &
pid=$!
for _ in $(seq 600); do grep -q "swapchain: " view.err && break; sleep 0.1; done
sleep 2
for i in $(seq "$n"); do
    # Each save changes the text (the tonemap's exposure param), so the watcher sees it.
    sed -i -E "0,/\"exposure_ev\": [-0-9.]+/s//\"exposure_ev\": 0.$i/" graph.json
    for _ in $(seq 100); do [ "$(grep -c "reload: first frame" view.err)" -ge "$i" ] && break; sleep 0.05; done
    sleep 1.5
done
kill -TERM "$pid"
wait "$pid" || true
grep "reload: first frame" view.err | sed 's/^info: //'
grep "reload: first frame" view.err | python3 -c '
import re, statistics, sys
rows = [[float(v) for v in re.findall(r"([0-9.]+) ms", line)] for line in sys.stdin]
if not rows:
    sys.exit("no reload was presented")
names = ["save to first frame", "save noticed", "rebuild", "first frame"]
print(f"{len(rows)} reloads, medians: " + ", ".join(f"{n} {statistics.median(c):.1f} ms" for n, c in zip(names, zip(*rows))))
'
