#!/usr/bin/env bash
# Compiles COUNT random graphs (default 10000) from seed FIRST (default 1) with aliasing on and
# checks every plan with the plan verifier (docs/verifier.md): no device, seconds per thousand.
# Each seed gives three or four plans (tests/verifier/verifier_test_util.hpp, verifyRandomGraph).
#   tools/verify-random-plans.sh [COUNT] [FIRST]
# Shards over SKYGRAPH_CI_JOBS processes (default 2). Builds verify_random_plans in
# SKYGRAPH_VERIFY_BUILD (default build-verifier; configured without the executor when new).
# Prints every plan with findings, and ends with "N verified, N findings (N plans alias)", which
# it also writes to summary.txt in the log folder. Exit status 1 when any plan has a finding.
set -euo pipefail
cd "$(dirname "$0")/.."
COUNT="${1:-10000}"
FIRST="${2:-1}"
JOBS="${SKYGRAPH_CI_JOBS:-2}"
BUILD="${SKYGRAPH_VERIFY_BUILD:-build-verifier}"
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKYGRAPH_BUILD_EXECUTOR=OFF \
    -DSKYGRAPH_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$BUILD" -j "$JOBS" --target verify_random_plans
logs="$BUILD/verify-random-plans"
mkdir -p "$logs"
rm -f "$logs"/shard*.log "$logs"/shard*.err
start=$(date +%s)
per=$(( (COUNT + JOBS - 1) / JOBS ))
pids=()
for ((j = 0; j < JOBS; ++j)); do
  first=$(( FIRST + j * per ))
  n=$(( per < COUNT - j * per ? per : COUNT - j * per ))
  (( n > 0 )) || break
  "$BUILD/tests/verifier/verify_random_plans" --seeds "$first" "$n" >"$logs/shard$j.log" 2>"$logs/shard$j.err" &
  pids+=($!)
done
status=0
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
grep -h -A3 "^FINDINGS" "$logs"/shard*.log || true
verified=0; findings=0; aliasing=0
for f in "$logs"/shard*.log; do
  read -r v n a < <(sed -n 's/^\([0-9]*\) verified, \([0-9]*\) findings (\([0-9]*\) plans alias).*/\1 \2 \3/p' "$f" | tail -1) ||
    { echo "shard $f did not finish"; status=1; continue; }
  verified=$((verified + v)); findings=$((findings + n)); aliasing=$((aliasing + a))
done
echo "seeds $FIRST..$((FIRST + COUNT - 1)) in $(( $(date +%s) - start )) s ($JOBS processes); logs in $logs"
summary="$verified verified, $findings findings ($aliasing plans alias)"
echo "$summary" | tee "$logs/summary.txt"
exit "$status"
