#!/usr/bin/env bash
# Renders docs/images/*.svg from the shipped graphs with `skygraph compile --format dot`.
# Usage: tools/render-doc-images.sh [path/to/skygraph]
set -euo pipefail
cd "$(dirname "$0")/.."
skygraph=${1:-build/tools/skygraph}
mkdir -p docs/images
"$skygraph" compile graphs/raster.json --format dot | dot -Tsvg -o docs/images/raster.svg
"$skygraph" compile graphs/raster.json --feature geometry=off --format dot | dot -Tsvg -o docs/images/raster-no-geometry.svg
"$skygraph" compile graphs/ibl.json --format dot | dot -Tsvg -o docs/images/ibl.svg
"$skygraph" compile graphs/pathtrace.json --format dot | dot -Tsvg -o docs/images/pathtrace.svg
