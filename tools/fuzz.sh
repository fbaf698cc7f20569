#!/usr/bin/env bash
# Fuzzes with libFuzzer for a time box each: the graph loader + compiler
# (tests/fuzz/graph_fuzz_target.cpp, seeds from tests/fuzz/corpus and graphs/) and the glTF
# loader (tests/fuzz/gltf_fuzz_target.cpp, seeds from tests/fuzz/gltf_corpus and Debian's
# assimp-testmodels). tools/fuzz.sh [SECONDS] [graph|gltf|all] (default 60 s, all).
# Builds build-fuzz with clang, ASan and UBSan and keeps what it learns in build-fuzz/corpus
# and build-fuzz/gltf_corpus. Exit status 0: no input crashed, hung, leaked or let an
# exception escape (other than GraphError for graphs; glTF errors are diagnostics). Otherwise
# the reproducer is build-fuzz/crash-* (or leak-*/timeout-*): copy it into the target's
# corpus with the fix (crash_<what>.json or .gltf), so every build replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_BOX="${1:-60}"
BUILD="${SKYGRAPH_FUZZ_BUILD:-build-fuzz}"
JOBS="${SKYGRAPH_CI_JOBS:-2}"
CXX_FUZZ="${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}"

cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$CXX_FUZZ" -DSKYGRAPH_FUZZ=ON \
  "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  >/dev/null
WHICH="${2:-all}"
case "$WHICH" in graph) targets=(graph_fuzzer) ;; gltf) targets=(gltf_fuzzer) ;; *) targets=(graph_fuzzer gltf_fuzzer) ;; esac
cmake --build "$BUILD" -j "$JOBS" --target "${targets[@]}"

# One process (CI has 2 shared cores); each input gets 2 s (a hang) and 512 MiB (a runaway allocation).
# detect_leaks: leaks count as failures; neither target links third-party code that leaks.
status=0
run() {  # NAME CORPUS SEED_DIR... [-- LIBFUZZER_FLAGS...]
    local name=$1 corpus=$2
    shift 2
    mkdir -p "$corpus"
    # Not under errexit: a failing fuzzer must reach the report below, not end the script.
    set +e
    ASAN_OPTIONS="detect_leaks=1:abort_on_error=0" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    "$BUILD/tests/fuzz/$name" "$corpus" "$@" -max_total_time="$SECONDS_BOX" -timeout=2 -rss_limit_mb=1024 \
      -malloc_limit_mb=512 -artifact_prefix="$BUILD/" -print_final_stats=1 \
      2>&1 | tee "$BUILD/$name.log" | grep -E "^#|ERROR|SUMMARY|crash|leak|timeout|Done" | tail -40
    local fuzzer_status=${PIPESTATUS[0]}
    set -e
    if [ "$fuzzer_status" -ne 0 ]; then
        status=1
        # The whole report and the input, so that a failure on a CI machine can be replayed here.
        sed -n '/^==[0-9]*== \?ERROR\|runtime error\|exception escaped\|GraphError without/,/^SUMMARY/p' "$BUILD/$name.log" | head -80
        for f in "$BUILD"/crash-* "$BUILD"/leak-* "$BUILD"/timeout-* "$BUILD"/oom-*; do
            [ -f "$f" ] && { echo "reproducer $f, base64:"; base64 -w 0 "$f"; echo; }
        done
    fi
}
for t in "${targets[@]}"; do
    case $t in
        graph_fuzzer) run graph_fuzzer "$BUILD/corpus" tests/fuzz/corpus graphs -dict=tests/fuzz/graph.dict -max_len=16384 ;;
        gltf_fuzzer) run gltf_fuzzer "$BUILD/gltf_corpus" tests/fuzz/gltf_corpus /usr/share/assimp/models/glTF2 -max_len=65536 ;;
    esac
done
ls "$BUILD"/crash-* "$BUILD"/leak-* "$BUILD"/timeout-* "$BUILD"/oom-* 2>/dev/null && status=1
exit "$status"
