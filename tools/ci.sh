#!/usr/bin/env bash
# Builds and runs every test: the README's test command runs this after tools/install-deps.sh.
# Each stage is a function so that later stages (sanitizers, the installed-package example,
# the fuzzing time box) read as one list. Runs on a clean clone, 2 cores, no network.
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS="${SKYGRAPH_CI_JOBS:-2}"

stage() { printf '\n=== %s (%s)\n' "$1" "$(date -u +%H:%M:%S)"; }

# Both builds keep line tables only (-g1: every backtrace and sanitizer report still names
# file and line): full debug information made compiling a quarter slower, on a 2-core machine
# that CI gives 45 minutes. Test sources compile at a lower level still (tests/CMakeLists.txt).
# The main build links with gold (the sanitizer build's links would warn for every binary
# that gold cannot export ASan's local symbols).
CI_FLAGS=(-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
GOLD=(-DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=gold -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=gold
    -DCMAKE_MODULE_LINKER_FLAGS=-fuse-ld=gold)

main_suite() {
    stage "build and test (RelWithDebInfo)"
    cmake -S . -B build -G Ninja "${CI_FLAGS[@]}" "${GOLD[@]}"
    cmake --build build -j "$JOBS"
    ctest --test-dir build --output-on-failure -j "$JOBS"
}

# Reuses the main build: installs it to a temporary prefix, builds examples/embed and
# examples/window against the installed package only (their own pass types, their own graphs,
# validation on; the window one presents on a virtual X server and checks screenshots), and
# renders with the installed `skygraph`, which must find the installed shaders.
installed_package() {
    stage "install; examples/embed, examples/window and skygraph render from the install tree"
    local prefix
    prefix="$(mktemp -d)"
    cmake --install build --prefix "$prefix" >/dev/null
    cmake -S examples/embed -B build/embed-example -G Ninja -DCMAKE_PREFIX_PATH="$prefix"
    cmake --build build/embed-example -j "$JOBS"
    ctest --test-dir build/embed-example --output-on-failure
    cmake -S examples/window -B build/window-example -G Ninja -DCMAKE_PREFIX_PATH="$prefix"
    cmake --build build/window-example -j "$JOBS"
    ctest --test-dir build/window-example --output-on-failure
    "$prefix/bin/skygraph" -v render --width 32 --height 32 --frames 2 --validate \
        -o "$prefix/installed.png" 2>&1 | tee "$prefix/render.log"
    grep -q "shaders from $prefix/share/skygraph/shaders" "$prefix/render.log"
    rm -rf "$prefix"
}

# Reliability (docs/reliability.md): clang ASan + UBSan (+ libFuzzer's coverage hooks in the
# libraries the fuzzers run, so the same build links them) of every test ctest knows but
# three kinds the main suite runs in full, run under the sanitizers on lavapipe with validation
# (shipped graphs under pairwise feature combinations), then the fuzzers' 30 s time boxes on
# that build. A test target missing from SANITIZED_TARGETS shows up as a failing *_NOT_BUILT test.
# Leaks: ctest runs everything with leak detection off, because the Vulkan loader unloads the
# driver and layers at vkDestroyInstance and their lifetime allocations can then be neither
# attributed nor suppressed; the binaries that make no Vulkan device are run again directly
# with leak detection on (seconds).
SANITIZED_TARGETS=(compiler_tests plan_verifier_tests cli_tests skygraph fuzz_corpus_tests graph_fuzzer math_tests
    files_tests file_watcher_tests image_tests scene_tests executor_tests recording_tests reliability_tests pass_tests ibl_tests
    cubemap_command_tests extremes_tests path_trace_tests present_tests testing_kit_tests)
LEAK_CHECKED_TESTS=(compiler/compiler_tests verifier/plan_verifier_tests fuzz/fuzz_corpus_tests math/math_tests
    scene/scene_tests image/image_tests executor/recording_tests files/files_tests compiler/file_watcher_tests)
sanitizers_and_fuzz() {
    stage "sanitizers: clang ASan + UBSan build of every test (build-fuzz)"
    local flags="-fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
    cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKYGRAPH_FUZZ=ON "${CI_FLAGS[@]}" \
        -DCMAKE_CXX_COMPILER="$(command -v clang++-14 || command -v clang++)" -DSKYGRAPH_BUILD_BENCH=ON \
        -DSKYGRAPH_PAIRWISE_RENDER_CASES=ON "-DCMAKE_CXX_FLAGS=$flags"
    cmake --build build-fuzz -j "$JOBS" --target "${SANITIZED_TARGETS[@]}" leak_control skygraph_keep_loaded
    stage "sanitizers: every test under ASan + UBSan on lavapipe"
    local lvp=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
    (
        export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" SKYGRAPH_TEST_QUIET=1
        export LSAN_OPTIONS="suppressions=$PWD/tests/reliability/lsan.supp:print_suppressions=0"
        export VK_ICD_FILENAMES="$lvp" VK_DRIVER_FILES="$lvp"
        # Each ran in the main suite: the minimality oracle renders each graph up to 175 times,
        # the schema check is Python, with no code of ours to sanitize, and the benchmarks'
        # smoke runs (not built here) test the benchmarks' own code over paths the tests cover.
        ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-fuzz --output-on-failure -j "$JOBS" \
            -E 'BarrierMinimality|^schema_validation$|_bench_lavapipe_|^study_lavapipe_'
        for t in "${LEAK_CHECKED_TESTS[@]}"; do
            ASAN_OPTIONS=detect_leaks=1 "build-fuzz/tests/$t" --gtest_brief=1
        done
    )
    stage "sanitizers: skygraph view closed mid-frame, leak detection on (and its negative control)"
    tests/reliability/view_leak_check.sh build-fuzz
    stage "fuzz the graph loader and compiler, and the glTF loader, for ${SKYGRAPH_FUZZ_SECONDS:-30} s each"
    tools/fuzz.sh "${SKYGRAPH_FUZZ_SECONDS:-30}"
}

# tools/ci.sh [STAGE...] runs only the named stages (e.g. sanitizers_and_fuzz); all by default.
if (($#)); then
    for s in "$@"; do "$s"; done
    stage "stages $* passed"
    exit 0
fi
main_suite
installed_package
sanitizers_and_fuzz
stage "all stages passed"
