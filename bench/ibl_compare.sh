#!/usr/bin/env bash
# Accuracy and speed of `skygraph cubemap` beside Filament's cmgen and OpenEXR's exrenvmap,
# on one analytic environment whose truth is known everywhere (bench/ibl_accuracy.cpp):
#   bench/ibl_compare.sh [BUILD_DIR] [RUNS]
# Times are wall-clock medians of RUNS whole-process runs, the tools interleaved so load from
# elsewhere hits them alike. Errors are relative (|got - truth| / truth over RGB), RMSE and
# max, against the double-precision reference. Needs cmgen (libfilament-tools) and exrenvmap
# (openexr); results go to stdout as they come (docs/environment.md keeps a copy).
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
runs=${2:-3}
sg="$build/tools/skygraph"
acc="$build/bench/ibl_accuracy"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$acc" input sky.exr 1024  # 1024x512 equirect of tests/ibl's sunSky

seconds() { /usr/bin/time -f %e -o time.txt "$@" >/dev/null 2>&1 && cat time.txt; }
median() { sort -n | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "== wall time, median of $runs (equirect 1024x512 -> 256^2 cube, GGX 1024 samples) =="
: > t_ours; : > t_ours_equal; : > t_cmgen; : > t_exr
for _ in $(seq "$runs"); do
  seconds "$sg" -q cubemap sky.exr -o ours.ktx2 --size 256 --samples 1024 >> t_ours
  seconds "$sg" -q cubemap sky.exr -o equal.ktx2 --size 256 --prefiltered-size 256 --samples 1024 \
    --products prefiltered >> t_ours_equal
  rm -rf cm && mkdir cm
  seconds cmgen -q --no-mirror --size=256 --ibl-samples=1024 -f exr --ibl-ld=cm sky.exr >> t_cmgen
  seconds exrenvmap -li -c -w 256 sky.exr exr_cube.exr >> t_exr
done
printf '%-58s %s s\n' "skygraph cubemap (cube 256, prefiltered 128, irradiance, LUT)" "$(median < t_ours)"
printf '%-58s %s s\n' "skygraph cubemap --prefiltered-size 256 (cube + prefilter)" "$(median < t_ours_equal)"
printf '%-58s %s s\n' "cmgen --size=256 --ibl-samples=1024 --ibl-ld (prefilter)" "$(median < t_cmgen)"
printf '%-58s %s s\n' "exrenvmap -c -w 256 (cube only, 5x5 taps)" "$(median < t_exr)"

echo "== error against the analytic truth =="
"$acc" ktx2 equal
"$acc" cmgen cm/sky
"$acc" exrenvmap exr_cube.exr 1024

echo "== skygraph: cube error by face size and supersampling (time of one run) =="
for size in 64 128 256; do
  for ss in 1 2 4; do
    t=$(seconds "$sg" -q cubemap sky.exr -o s.ktx2 --size "$size" --supersample "$ss" --products prefiltered \
      --prefiltered-size 32 --samples 1)
    echo "size $size supersample $ss (${t} s): $("$acc" ktx2 s | grep environment)"
  done
done

echo "== skygraph: prefilter error by sample count (cube 256, prefiltered 128) =="
for samples in 64 256 1024; do
  t=$(seconds "$sg" -q cubemap sky.exr -o p.ktx2 --size 256 --samples "$samples" --products prefiltered)
  echo "samples $samples (${t} s):"
  "$acc" ktx2 p | grep prefiltered
done
