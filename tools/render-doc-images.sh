#!/usr/bin/env bash
# Renders docs/images/*.svg from the shipped graphs with `skygraph compile --format dot`, and
# the gallery PNGs (docs/gallery.md) with `skygraph render`.
# Usage: tools/render-doc-images.sh [path/to/skygraph [path/to/embed_vignette]]
set -euo pipefail
cd "$(dirname "$0")/.."
skygraph=${1:-build/tools/skygraph}
mkdir -p docs/images
"$skygraph" compile graphs/raster.json --format dot | dot -Tsvg -o docs/images/raster.svg
"$skygraph" compile graphs/raster.json --feature geometry=off --format dot | dot -Tsvg -o docs/images/raster-no-geometry.svg
"$skygraph" compile graphs/ibl.json --format dot | dot -Tsvg -o docs/images/ibl.svg
"$skygraph" compile graphs/pathtrace.json --format dot | dot -Tsvg -o docs/images/pathtrace.svg

# Gallery (docs/gallery.md): small renders of the shipped scenes on lavapipe under validation
# with synchronization validation (any message fails the script). A few hundred KB in all.
# An optional second argument, the examples/embed binary, adds its VignettePass render.
gallery() { "$skygraph" -q render "$@" --width 240 --height 150 --frames 2 --validate; }
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
# A variant of scenes/default.json with one key changed, for the debug views and tone curves.
variant() {
    python3 - "$1" "$2" "$scratch/$1-$2.json" <<'PY'
import json, sys
scene = json.load(open("scenes/default.json"))
scene[sys.argv[1]] = sys.argv[2]
json.dump(scene, open(sys.argv[3], "w"))
PY
    echo "$scratch/$1-$2.json"
}
gallery -o docs/images/gallery-default.png
gallery graphs/raster.json --scene scenes/default.json --feature skybox=off -o docs/images/gallery-no-skybox.png
gallery graphs/raster.json --scene scenes/sky_only.json -o docs/images/gallery-sky-only.png
gallery graphs/raster.json --scene scenes/studio.json -o docs/images/gallery-studio.png
gallery graphs/raster.json --scene scenes/engine.json -o docs/images/gallery-engine.png
for view in normal roughness; do
    gallery graphs/raster.json --scene "$(variant debug_view "$view")" -o "docs/images/gallery-debug-$view.png"
done
for curve in khronos_pbr_neutral passthrough; do
    gallery graphs/raster.json --scene "$(variant tonemapper "$curve")" -o "docs/images/gallery-tone-$curve.png"
done
if [ -n "${2:-}" ]; then
    "$2" docs/images/gallery-embed-vignette.png
fi
