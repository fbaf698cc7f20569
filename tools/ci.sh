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

main_suite
stage "all stages passed"
