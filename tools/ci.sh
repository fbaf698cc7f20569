#!/usr/bin/env bash
# Builds and runs every test: the README's test command runs this after tools/install-deps.sh.
# Each stage is a function so that later stages (sanitizers, the installed-package example,
# the fuzzing time box) read as one list. Runs on a clean clone, 2 cores, no network.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${SKYGRAPH_CI_JOBS:-2}"

stage() { printf '\n=== %s (%s)\n' "$1" "$(date -u +%H:%M:%S)"; }

main_suite() {
    stage "build and test (RelWithDebInfo)"
    cmake -S . -B build -G Ninja
    cmake --build build -j "$JOBS"
    ctest --test-dir build --output-on-failure -j "$JOBS"
}

# Reuses the main build: installs it to a temporary prefix, builds examples/embed against the
# installed package only (its own pass type, its own graph, validation on), and renders with
# the installed `skygraph`, which must find the installed shaders.
installed_package() {
    stage "install; examples/embed and skygraph render from the install tree"
    local prefix
    prefix="$(mktemp -d)"
    cmake --install build --prefix "$prefix" >/dev/null
    cmake -S examples/embed -B build/embed-example -G Ninja -DCMAKE_PREFIX_PATH="$prefix"
    cmake --build build/embed-example -j "$JOBS"
    ctest --test-dir build/embed-example --output-on-failure
    "$prefix/bin/skygraph" -v render --width 32 --height 32 --frames 2 --validate \
        -o "$prefix/installed.png" 2>&1 | tee "$prefix/render.log"
    grep -q "shaders from $prefix/share/skygraph/shaders" "$prefix/render.log"
    rm -rf "$prefix"
}

main_suite
installed_package
stage "all stages passed"
