#!/usr/bin/env bash
# Instructions and simulated cache misses per compile() of a synthetic graph, for builds of
# compile_bench side by side (deterministic, unlike time on this shared VM):
#   bench/compile_misses.sh BENCH... [-- PASSES [BENCHMARK]]
# (PASSES: 10000 unless given; BENCHMARK: BM_Compile unless given, e.g. BM_CompileNoSharing)
# callgrind simulates a 64 KiB L1 and, as its last level, a 512 KiB L2 (this machine's
# per-core L2), so "L2 misses" counts the lines that came from L3 or memory. It has no
# prefetcher: a sequential stream counts in full. Two compiles run (the benchmark's first
# iteration and its measured one) and the counts are halved; the first also pays glibc
# consolidating the memory that parsing the graph freed (~12k read misses in _int_malloc at
# 10k passes, alike for every build).
# The totals line is picked by a filter that reads the whole report: one that stopped at it
# would end callgrind_annotate with SIGPIPE, and pipefail would end the script after one build.
set -euo pipefail
passes=10000 benchmark=BM_Compile bins=()
while (($#)); do
    if [[ $1 == -- ]]; then
        passes=$2 benchmark=${3:-$benchmark}
        break
    fi
    bins+=("$1")
    shift
done
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for bin in "${bins[@]}"; do
    valgrind --tool=callgrind --cache-sim=yes --D1=65536,8,64 --LL=524288,8,64 \
        --toggle-collect='skygraph::compile(*' --callgrind-out-file="$out" \
        "$bin" --benchmark_filter="$benchmark/$passes\$" --benchmark_min_time=0.0001 >/dev/null 2>&1
    callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ && !seen++' | python3 -c '
import sys
names = ["Ir", "Dr", "Dw", "I1mr", "D1mr", "D1mw", "ILmr", "DLmr", "DLmw"]
v = dict(zip(names, (int(x.replace(",", "")) / 2 for x in sys.stdin.read().split() if x[0].isdigit())))
print("%s: %.2fM instructions, L1 misses %.0fk read %.0fk write, L2 misses %.0fk read %.0fk write" % (
    sys.argv[1], v["Ir"] / 1e6, v["D1mr"] / 1e3, v["D1mw"] / 1e3, v["DLmr"] / 1e3, v["DLmw"] / 1e3))' "$bin"
done
