#!/usr/bin/env bash
# Two builds of compile_bench side by side, for a change to the compiler:
#   bench/compile_compare.sh OLD_BENCH NEW_BENCH [ROUNDS] [FILTER]
# e.g. OLD_BENCH from `git worktree add /tmp/old <commit>` built like build-rel
# (docs/performance.md, "Compiler"). Short runs of the two binaries alternate, pinned to one
# CPU, so that what the machine's neighbours do to the shared cache hits both alike: on this
# VM the same binary's 10k-pass median moves by a quarter from minute to minute, so only
# interleaved runs compare. Prints, per benchmark and binary, the median, quartiles and
# minimum of the CPU times, the new/old ratio of the medians, and the median (and quartiles)
# of each round's own new/old ratio, which the drift between rounds does not reach.
set -euo pipefail
old=$1 new=$2 rounds=${3:-25} filter=${4:-'BM_Compile/1000$|BM_Compile/10000$'}
cpu=$(($(nproc) - 1))
for round in $(seq "$rounds"); do
    for bin in "$old" "$new"; do
        taskset -c "$cpu" "$bin" --benchmark_filter="$filter" --benchmark_min_time=0.1 \
            --benchmark_format=csv 2>/dev/null | grep '^"' | awk -F, -v b="$bin" -v r="$round" '{print r, b, $1, $4}'
    done
done | python3 -c '
import collections, statistics, sys
old, new = sys.argv[1:3]
times = collections.defaultdict(list)
byRound = collections.defaultdict(dict)  # (name, round) -> {binary: time}
for line in sys.stdin:
    rnd, binary, name, cpu_us = line.split()  # the benchmarks report microseconds
    times[(name.strip("\""), binary)].append(float(cpu_us))
    byRound[(name.strip("\""), rnd)][binary] = float(cpu_us)
for name in sorted({n for n, _ in times}):
    for binary, label in ((old, "old"), (new, "new")):
        t = sorted(times[(name, binary)])
        q = statistics.quantiles(t, n=4)
        print(f"{name:22} {label}  median {statistics.median(t):9.3f} us  q1 {q[0]:9.3f}  q3 {q[2]:9.3f}"
              f"  min {t[0]:9.3f}  n={len(t)}")
    ratio = statistics.median(times[(name, new)]) / statistics.median(times[(name, old)])
    # The two runs of a round were seconds apart: their ratio cancels the drift between rounds.
    paired = sorted(r[new] / r[old] for (n, _), r in byRound.items() if n == name and len(r) == 2)
    pq = statistics.quantiles(paired, n=4)
    print(f"{name:22} new/old median {ratio:.2f}; per round {statistics.median(paired):.3f}"
          f" (q1 {pq[0]:.3f}, q3 {pq[2]:.3f})")
' "$old" "$new"
