#!/usr/bin/env bash
# What runs on the GPU machine (docs/performance.md, "NVIDIA H100"): unpack the bundle from
# tools/device/bundle.sh, configure and build the benchmark targets against it, run the
# measurements on the NVIDIA device, and leave logs, CSV and JSON in $OUT (default:
# /tmp/skygraph-gpu-out).
#
#   tools/device/run-gpu-bench.sh [RUN...]
#
# RUN: GRAPH[:SCENE][@VARIANT] for gpu_frame_bench. Default: graphs/raster.json with
# scenes/default.json as it is, with a B8G8R8A8_UNORM swapchain (@unorm-swapchain: the
# TonemappingPass encodes sRGB in the shader), and with raster.json's feature compute_tonemap
# on (@compute-tonemap: the built-in TonemappingComputePass); scenes/studio.json (an HDRI: baked IBL,
# forward_ibl, equirect skybox) as it is and @compute-tonemap; then graphs/ibl.json. Before
# timing, the default scene's last two pictures are compared with the first (pngdiff.py).
# Environment: FRAMES (200), SIZES ("1920x1080 3840x2160"), DEVICE (nvidia), JOBS (16),
# SKIP_EXECUTOR_BENCH=1 to skip executor_bench, EXECUTOR_REPS (5) its repetitions (run in
# random interleaving when more than 5), SKIP_FRAME_BENCH=1 to run executor_bench alone,
# MEMORY_BENCH=1 to run memory_gpu_bench (MEMORY_FRAMES, MEMORY_ROUNDS, MEMORY_SEEDS,
# MEMORY_COMPARE_SIZE), LAYOUTS_BENCH=1 to time the layouts knob on graphs/deferred.json,
# QUEUES_BENCH=1 to run graphs/async.json and rebake_bench under validation, then timed with
# separate queues against one (REBAKE_FRAMES, REBAKE_REPS), SKIP_IMGUI_BENCH=1 to skip imgui_bench (the ImGui pass at IMGUI_SIZE, 1920x1080; IMGUI_REPS
# (5) repetitions, interleaved when more than 5), GLTF_CHECK=1 to render the glTF reference
# scenes raster and path traced under validation (models from .devbundle/data/gltf/),
# SEQUENCE_BENCH=1 to run sequence_bench at 2K and 6K (SEQUENCE_FRAMES), TARGETS the targets
# built (default: all four).
# graphs/ibl.json's external "equirect" is
# filled with gpu_frame_bench's procedural HDR sky (--procedural equirect) when a run has it.
#
# Builds .devbundle/source.tar.gz (a committed snapshot, see bundle.sh --source) when it is
# there, else the working tree it runs in. Never writes outside /tmp and $OUT: the carried
# libraries are used through LD_LIBRARY_PATH, not unpacked into the system.
set -uo pipefail
here=$(pwd)
out=${OUT:-/tmp/skygraph-gpu-out}
mkdir -p "$out"
log=$out/run.log
exec > >(tee -a "$log") 2>&1

frames=${FRAMES:-200}
sizes=${SIZES:-"1920x1080 3840x2160"}
device=${DEVICE:-nvidia}
jobs=${JOBS:-16}
runs=("$@")
raster=graphs/raster.json:scenes/default.json
# scenes/studio.json with its HDRI carried in .devbundle/data/ (the scene names Debian's path).
studio=graphs/raster.json:/tmp/studio.json
[ ${#runs[@]} -gt 0 ] || runs=("$raster" "$raster@unorm-swapchain" "$raster@compute-tonemap" "$studio"
                               "$studio@compute-tonemap" graphs/ibl.json)

step() { echo; echo "=== $(date -u +%H:%M:%S) $*"; }

step "machine"
uname -srm; nproc
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv 2>&1 | head -3
gcc --version | head -1; cmake --version | head -1; ninja --version 2>/dev/null

step "unpack the bundle"
deps=/tmp/skygraph-deps
rm -rf "$deps" && mkdir -p "$deps" && tar -xJf .devbundle/deps.tar.xz -C "$deps" || { echo "no usable .devbundle/deps.tar.xz"; exit 1; }
cat .devbundle/MANIFEST
prefix=$deps/usr
libdir=$prefix/lib/x86_64-linux-gnu
export LD_LIBRARY_PATH=$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export LIBRARY_PATH=$libdir  # glslang's CMake files name SPIRV-Tools-opt etc. as plain -l libraries
# Debian's .pc files say prefix=/usr: the sysroot moves them under the bundle (lcms2 for bench/study).
export PKG_CONFIG_SYSROOT_DIR=$deps PKG_CONFIG_LIBDIR=$libdir/pkgconfig
command -v pkg-config >/dev/null || echo "note: no pkg-config on this machine; targets that need it will not configure"
src=$here
if [ -f .devbundle/source.tar.gz ]; then
  rm -rf /tmp/skygraph-src && mkdir -p /tmp/skygraph-src && tar -xzf .devbundle/source.tar.gz -C /tmp/skygraph-src
  src=/tmp/skygraph-src/src
  echo "source: commit $(cat .devbundle/SOURCE_COMMIT) (bundle.sh --source)"
else
  echo "source: the carried working tree"
fi
export SKYGRAPH_SHADER_DIR=$src/shaders
sed "s|/usr/share/blender/datafiles/studiolights/world/studio.exr|$here/.devbundle/data/studio.exr|" \
  "$src/scenes/studio.json" > /tmp/studio.json

step "Vulkan driver"
icd=""
for f in /usr/share/vulkan/icd.d/nvidia_icd*.json /etc/vulkan/icd.d/nvidia_icd*.json \
         /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd*.json; do
  [ -f "$f" ] && { icd=$f; break; }
done
[ -n "$icd" ] || icd=$(find / -xdev -name 'nvidia_icd*.json' 2>/dev/null | head -1)
if [ -n "$icd" ]; then
  echo "NVIDIA ICD: $icd"; cat "$icd"
  export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd
else
  echo "no nvidia_icd.json found; the loader's default search applies"
fi

if [ -f .devbundle/layer.tar.xz ]; then
  rm -rf /tmp/skygraph-layer && mkdir -p /tmp/skygraph-layer && tar -xJf .devbundle/layer.tar.xz -C /tmp/skygraph-layer
  # Debian's manifest names the library bare (found through the library path); a path with a
  # slash is taken relative to the manifest.
  sed -i 's|"library_path": "libVkLayer|"library_path": "./libVkLayer|' /tmp/skygraph-layer/*.json
  export VK_LAYER_PATH=/tmp/skygraph-layer
  echo "validation layer: $(grep -o '"api_version": "[^"]*"' /tmp/skygraph-layer/*.json)"
fi

targets=${TARGETS:-"gpu_frame_bench executor_bench skygraph imgui_bench"}
step "configure and build (-j$jobs): $targets"
build=/tmp/skygraph-build
t0=$(date +%s)
cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSKYGRAPH_BUILD_TESTS=OFF \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_POLICY_VERSION_MINIMUM=3.5 > "$out/configure.log" 2>&1 \
  && cmake --build "$build" -j"$jobs" --target $targets -- -k 0 > "$out/build.log" 2>&1
rc=$?
t1=$(date +%s)
echo "build rc=$rc in $((t1 - t0)) s"
if [ $rc -ne 0 ]; then
  tail -40 "$out/configure.log"; grep -B2 -A12 -m3 "error" "$out/build.log" | head -80
fi
bin_bench=$build/bench/gpu_frame_bench
bin_exec=$build/framework/executor/executor_bench
bin_cli=$build/tools/skygraph
bin_imgui=$build/bench/imgui_bench
bin_rebake=$build/bench/rebake_bench
bin_sequence=$build/bench/sequence_bench
# A target that failed to build is reported and skipped; the others still run.
ran() { [ -x "$1" ] || { echo "not built: $1"; return 1; }; }

if [ "${SKIP_FRAME_BENCH:-0}" != 1 ]; then
step "render check on $device: skygraph render at 960x540, and with --feature compute_tonemap=on"
ran "$bin_cli" && (cd "$src" && "$bin_cli" render --device "$device" --scene scenes/default.json --width 960 --height 540 \
  --frames 3 -o "/tmp/render-$device.png" \
  && "$bin_cli" render --device "$device" --scene scenes/default.json --width 960 --height 540 \
  --frames 3 --feature compute_tonemap=on -o "/tmp/render-$device-compute.png") \
  && python3 "$src/tools/device/pngdiff.py" "/tmp/render-$device.png" "/tmp/render-$device-compute.png"

step "same pictures: raster.json as it is, @unorm-swapchain, @compute-tonemap at 960x540"
rm -rf /tmp/gpu-png && mkdir -p /tmp/gpu-png
ran "$bin_bench" && (cd "$src" && "$bin_bench" --device "$device" --run "$raster" --run "$raster@unorm-swapchain" \
  --run "$raster@compute-tonemap" --size 960x540 --frames 2 --warmup 1 --bandwidth-mib 0 --no-probes \
  --png-dir /tmp/gpu-png > /tmp/gpu-png/log.txt) \
  && python3 "$src/tools/device/pngdiff.py" /tmp/gpu-png/raster-default-960x540.png \
       /tmp/gpu-png/raster-default-unorm-swapchain-960x540.png /tmp/gpu-png/raster-default-compute-tonemap-960x540.png

step "gpu_frame_bench: ${runs[*]} at $sizes, $frames frames"
args=()
for r in "${runs[@]}"; do args+=(--run "$r"); done
for s in $sizes; do args+=(--size "$s"); done
ran "$bin_bench" && (cd "$src" && "$bin_bench" --device "$device" "${args[@]}" --procedural equirect --frames "$frames" --csv "$out/gpu_frame_bench.csv") \
  | tee "$out/gpu_frame_bench.txt"

fi  # SKIP_FRAME_BENCH

if [ "${SKIP_EXECUTOR_BENCH:-0}" != 1 ]; then
  reps=${EXECUTOR_REPS:-5}
  interleave=()
  [ "$reps" -gt 5 ] && interleave=(--benchmark_enable_random_interleaving=true)
  step "executor_bench on $device, $reps repetitions"
  ran "$bin_exec" && (cd "$src" && SKYGRAPH_BENCH_DEVICE=$device "$bin_exec" --benchmark_repetitions="$reps" "${interleave[@]}" \
    --benchmark_report_aggregates_only=true --benchmark_counters_tabular=true \
    --benchmark_out="$out/executor_bench.json" --benchmark_out_format=json)
fi
if [ "${SKIP_IMGUI_BENCH:-0}" != 1 ]; then
  reps=${IMGUI_REPS:-5}
  interleave=()
  [ "$reps" -gt 5 ] && interleave=(--benchmark_enable_random_interleaving=true)
  step "imgui_bench on $device at ${IMGUI_SIZE:-1920x1080}, $reps repetitions"
  ran "$bin_imgui" && (cd "$src" && SKYGRAPH_BENCH_DEVICE=$device "$bin_imgui" --size="${IMGUI_SIZE:-1920x1080}" \
    --benchmark_repetitions="$reps" "${interleave[@]}" --benchmark_report_aggregates_only=true --benchmark_counters_tabular=true \
    --benchmark_out="$out/imgui_bench.json" --benchmark_out_format=json)
fi
if [ "${MEMORY_BENCH:-0}" = 1 ]; then
  # Transient memory (docs/performance.md, "Transient memory"): the device's heap bytes, frame
  # time with and without aliasing, and aliased+clobbered images against unaliased ones.
  bin_mem=$build/bench/memory_gpu_bench
  step "memory_gpu_bench on $device"
  ran "$bin_mem" && (cd "$src" && "$bin_mem" --device "$device" memory graphs/*.json \
    && "$bin_mem" --device "$device" time --size 1920x1080 --size 3840x2160 --frames "${MEMORY_FRAMES:-40}" \
         --rounds "${MEMORY_ROUNDS:-9}" graphs/deferred.json \
    && "$bin_mem" --device "$device" compare --size "${MEMORY_COMPARE_SIZE:-256x256}" --seeds "${MEMORY_SEEDS:-64}" \
         graphs/*.json) | tee "$out/memory_gpu_bench.txt"
fi
if [ "${LAYOUTS_BENCH:-0}" = 1 ]; then
  # The layouts knob (docs/performance.md, "The layouts knob"): the deferred frame with runs of
  # reads in one layout against each reader's optimal one, barrier counts and frame time.
  bin_mem=$build/bench/memory_gpu_bench
  step "memory_gpu_bench time --layouts on $device"
  ran "$bin_mem" && (cd "$src" && "$bin_mem" --device "$device" time --layouts --size 1920x1080 --size 3840x2160 \
    --frames "${MEMORY_FRAMES:-40}" --rounds "${MEMORY_ROUNDS:-9}" graphs/deferred.json) | tee "$out/layouts_bench.txt"
fi
if [ "${QUEUES_BENCH:-0}" = 1 ]; then
  # Plans on several queues (docs/queues.md): graphs/async.json and the background re-bake
  # under validation with the device's own queue families, then timed with separate queues
  # (SKYGRAPH_SEPARATE_QUEUES=1) against every kind on the graphics queue (=0).
  step "queues under validation on $device"
  ran "$bin_cli" && (cd "$src" && "$bin_cli" render graphs/async.json --device "$device" --validate \
    --width 640 --height 360 --frames 8 -o /tmp/async.png)
  ran "$bin_rebake" && (cd "$src" && SKYGRAPH_BENCH_DEVICE=$device SKYGRAPH_VALIDATION=1 "$bin_rebake" \
    --scene /tmp/studio.json --size 640x360 --frames 16 --change-at 4 --reps 1)
  for q in 1 0; do
    step "graphs/async.json, SKYGRAPH_SEPARATE_QUEUES=$q, $frames frames"
    ran "$bin_bench" && (cd "$src" && SKYGRAPH_SEPARATE_QUEUES=$q "$bin_bench" --device "$device" --run graphs/async.json \
      --size 1920x1080 --size 3840x2160 --frames "$frames" --bandwidth-mib 0 --no-probes) | tee "$out/async-queues-$q.txt"
    step "rebake_bench, SKYGRAPH_SEPARATE_QUEUES=$q"
    ran "$bin_rebake" && (cd "$src" && SKYGRAPH_SEPARATE_QUEUES=$q SKYGRAPH_BENCH_DEVICE=$device "$bin_rebake" \
      --scene /tmp/studio.json --size 1920x1080 --frames "${REBAKE_FRAMES:-60}" --change-at 20 \
      --reps "${REBAKE_REPS:-5}" --csv "$out/rebake-queues-$q.csv") | tee "$out/rebake-queues-$q.txt"
  done
fi
if [ "${GLTF_CHECK:-0}" = 1 ]; then
  # The glTF reference scenes (their models carried in .devbundle/data/gltf/ from Debian's
  # assimp-testmodels) through raster.json and pathtrace.json under validation; the pictures
  # land in $out for a look beside lavapipe's.
  for scene in tests/passes/scenes/box_textured_glb.json tests/passes/scenes/clearcoat.json scenes/engine.json; do
    name=$(basename "$scene" .json)
    sed "s|/usr/share/assimp/models/glTF2|$here/.devbundle/data/gltf|" "$src/$scene" > "/tmp/$name.json"
    step "glTF check: $name, raster and path traced (64 spp) under validation"
    ran "$bin_cli" && (cd "$src" && "$bin_cli" render --device "$device" --validate --scene "/tmp/$name.json" \
      --width 480 --height 320 --frames 3 -o "$out/$name-raster.png" \
      && "$bin_cli" render graphs/pathtrace.json --device "$device" --validate --scene "/tmp/$name.json" \
      --width 480 --height 320 --frames 64 -o "$out/$name-pathtrace.png")
    echo "$name: rc=$?"
  done
fi
if [ "${SEQUENCE_BENCH:-0}" = 1 ]; then
  # An environment sequence per frame and in memory at 2K and 6K (bench/sequence_bench.cpp):
  # under validation at 2K with the device's queue families and with every kind on the
  # graphics queue, then timed (SEQUENCE_FRAMES frames, default 9).
  for q in 1 0; do
    step "sequence_bench under validation on $device, 2K, SKYGRAPH_SEPARATE_QUEUES=$q"
    ran "$bin_sequence" && (cd "$src" && SKYGRAPH_SEPARATE_QUEUES=$q SKYGRAPH_BENCH_DEVICE=$device SKYGRAPH_VALIDATION=1 \
      "$bin_sequence" --width 2048 --frames 4 --size 1920x1080 --dir /tmp/skygraph-sequence) \
      | tee "$out/sequence-validation-queues-$q.txt"
  done
  # The upload's own GPU time: graphs/ibl.json with its transfer-queue UploadPass, rendered
  # with scenes/studio.json's 1024x512 HDRI (8 MiB of floats), per-pass GPU times.
  step "graphs/ibl.json, streamed_equirect on, on $device: GPU time per pass"
  ran "$bin_cli" && (cd "$src" && "$bin_cli" render graphs/ibl.json --scene /tmp/studio.json \
    --feature streamed_equirect=on --device "$device" --frames 20 2>&1 | grep "pass ") | tee "$out/ibl-upload.txt"
  for width in 2048 6144; do
    step "sequence_bench on $device, equirect width $width"
    ran "$bin_sequence" && (cd "$src" && SKYGRAPH_BENCH_DEVICE=$device "$bin_sequence" --width "$width" \
      --frames "${SEQUENCE_FRAMES:-9}" --size 1920x1080 --dir /tmp/skygraph-sequence) | tee "$out/sequence-$width.txt"
  done
fi
step "done"
