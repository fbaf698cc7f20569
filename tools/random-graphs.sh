#!/usr/bin/env bash
# Runs COUNT random graphs (default 10000) from seed FIRST (default 1) on lavapipe with
# validation and synchronization validation: each must compile and render with zero
# messages (tests/executor/random_graph_check.hpp); every fourth is also run reordered, and
# every even one also with its passes on random queues (docs/queues.md).
# The first MINIMALITY seeds (default 50) also get the barrier-minimality oracle.
#   tools/random-graphs.sh [COUNT] [FIRST] [MINIMALITY]
# Shards over SKYGRAPH_CI_JOBS processes (default 2). Builds random_graphs in
# SKYGRAPH_RANDOM_BUILD (default build-fuzz, the sanitized clang build of tools/fuzz.sh,
# so the executor also runs under ASan/UBSan). Ends with "N passed, N failed".
set -euo pipefail
cd "$(dirname "$0")/.."
COUNT="${1:-10000}"
FIRST="${2:-1}"
MINIMALITY="${3:-50}"
JOBS="${SKYGRAPH_CI_JOBS:-2}"
BUILD="${SKYGRAPH_RANDOM_BUILD:-build-fuzz}"
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  CXX_FUZZ="${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++)}"
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$CXX_FUZZ" \
    -DSKYGRAPH_FUZZ=ON -DSKYGRAPH_BUILD_BENCH=OFF \
    "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=vptr -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
    >/dev/null
fi
cmake -S . -B "$BUILD" -DSKYGRAPH_BUILD_EXECUTOR=ON >/dev/null
cmake --build "$BUILD" -j "$JOBS" --target random_graphs
lvp=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
export VK_ICD_FILENAMES="$lvp" VK_DRIVER_FILES="$lvp"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"  # the driver's leaks are not ours; see docs/reliability.md
logs="$BUILD/random-graphs"
mkdir -p "$logs"
start=$(date +%s)
per=$(( (COUNT + JOBS - 1) / JOBS ))
pids=()
for ((j = 0; j < JOBS; ++j)); do
  first=$(( FIRST + j * per ))
  n=$(( per < COUNT - j * per ? per : COUNT - j * per ))
  (( n > 0 )) || break
  mini=$(( j == 0 ? MINIMALITY : 0 ))
  "$BUILD/tests/executor/random_graphs" "$first" "$n" --minimality "$mini" >"$logs/shard$j.log" 2>"$logs/shard$j.err" &
  pids+=($!)
done
status=0
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
grep -h "^FAILED\|^UNNEEDED\|^minimality" "$logs"/shard*.log || true
passed=0; failed=0
for f in "$logs"/shard*.log; do
  read -r p q < <(sed -n 's/.*: \([0-9]*\) passed, \([0-9]*\) failed$/\1 \2/p' "$f" | tail -1) || { echo "shard $f did not finish"; status=1; continue; }
  passed=$((passed + p)); failed=$((failed + q))
done
echo "seeds $FIRST..$((FIRST + COUNT - 1)) in $(( $(date +%s) - start )) s ($JOBS processes); logs in $logs"
echo "$passed passed, $failed failed"
exit "$status"
