#!/usr/bin/env bash
# Fuzzes the loader + compiler (tests/fuzz/graph_fuzz_target.cpp) with libFuzzer for a time
# box: tools/fuzz.sh [SECONDS] (default 60). Builds build-fuzz with clang, ASan and UBSan,
# seeds from tests/fuzz/corpus and graphs/, and keeps what it learns in build-fuzz/corpus.
# Exit status 0: no input crashed, hung, leaked or let an exception other than GraphError
# escape. Otherwise the reproducer is build-fuzz/crash-* (or leak-*/timeout-*): copy it into
# tests/fuzz/corpus/ as crash_<what>.json with the fix, so every build replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_BOX="${1:-60}"
BUILD="${SKYGRAPH_FUZZ_BUILD:-build-fuzz}"
JOBS="${SKYGRAPH_CI_JOBS:-2}"
CXX_FUZZ="${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}"

cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$CXX_FUZZ" -DSKYGRAPH_FUZZ=ON \
  "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target graph_fuzzer

mkdir -p "$BUILD/corpus"
# One process (CI has 2 shared cores); each input gets 2 s (a hang) and 512 MiB (a runaway allocation).
# detect_leaks: leaks count as failures; the compiler links no third-party code that leaks.
ASAN_OPTIONS="detect_leaks=1:abort_on_error=0" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
"$BUILD/tests/fuzz/graph_fuzzer" "$BUILD/corpus" tests/fuzz/corpus graphs \
  -dict=tests/fuzz/graph.dict -max_total_time="$SECONDS_BOX" -timeout=2 -rss_limit_mb=1024 \
  -malloc_limit_mb=512 -max_len=16384 -artifact_prefix="$BUILD/" -print_final_stats=1 \
  2>&1 | tee "$BUILD/fuzz.log" | grep -E "^#|ERROR|SUMMARY|crash|leak|timeout|Done" | tail -40
status=${PIPESTATUS[0]}
ls "$BUILD"/crash-* "$BUILD"/leak-* "$BUILD"/timeout-* "$BUILD"/oom-* 2>/dev/null && status=1
exit "$status"
