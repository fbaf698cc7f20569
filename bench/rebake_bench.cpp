// The longest frame while the environment changes: graphs/raster.json with a scene that has an
// environment file (scenes/studio.json), rendered headless with two frames in flight, gets a
// new environment (the same HDRI at half or double brightness, so every size stays) at frame
// --change-at, re-baked by an EnvironmentBaker (two renderers of graphs/ibl.json made once,
// taking turns) one of three ways:
//
//   sync    the passes on the graphics queue; start() renders the bake and waits for it
//   async   the passes on the compute queue, a background frame beside the frames, swapped in
//           by swapInWhenFinished between frames (docs/queues.md, "Background frames"), the
//           equirect's upload on the transfer queue; start() copies the new pixels from the
//           host into a staging buffer on the frame's thread
//   staged  async, with the pixels copied into a StagingBuffer by a loader thread of the
//           application while the frames before the change render; start() only submits
//
// Each frame's time is the wall-clock time between two renderFrame() returns (with two in
// flight, renderFrame waits for the frame before last: the pace the GPU sets). Per run it
// reports the median frame before the change, the worst frame from the change on, and
// start()'s time on the calling thread (staging from the host and the submits; sync: the bake
// too); runs rotate the three modes, --reps of each, and the summary gives the medians over
// runs and their ratios to sync.
//
//   rebake_bench [--scene FILE] [--size WxH] [--frames N] [--change-at K] [--reps R] [--csv FILE]
//
// Environment: SKYGRAPH_BENCH_DEVICE picks the device, SKYGRAPH_VALIDATION=1 runs under
// validation; the exit status is 1 when a validation message was counted.
#include "app/environment_bake.hpp"
#include "app/render.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/staging_buffer.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace skygraph::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct RunResult {
    std::string mode;
    double steadyMs = 0.0;  ///< median frame before the change
    double worstMs = 0.0;   ///< longest frame from the change on
    /// Longest frame of the change itself: from start() to the frame after the swap. Later
    /// frames' worst is the frames' own jitter, which the worst frame before the change shows.
    double changeWorstMs = 0.0;
    double worstBeforeMs = 0.0;  ///< longest frame before the change
    double setupMs = 0.0;   ///< EnvironmentBaker::start() on this thread
    uint32_t framesToSwap = 0;
    uint32_t worstAt = 0;  ///< frames after the change at which the worst frame came
    double swapMs = 0.0;   ///< the swapInWhenFinished() call that swapped the products in
};

HdrImage scaled(const HdrImage& image, float factor) {
    HdrImage out = image;
    for (size_t i = 0; i < out.rgba.size(); ++i)
        if (i % 4 != 3) out.rgba[i] *= factor;
    return out;
}

enum class Mode { Sync, Async, Staged };
constexpr const char* kModeNames[] = {"sync", "async", "staged"};

class Bench {
public:
    Bench(Device& device, const app::RenderOptions& options) : device_(device) {
        app::FrameInputs inputs = app::loadFrameInputs(options);
        if (!inputs.environment) throw std::runtime_error("the scene has no environment file: nothing to re-bake");
        equirect_ = *inputs.environment;
        CompileOptions co = inputs.compile;
        co.presentReplacement = ExternalState::TransferSrc;
        CompiledGraph compiled(inputs.graph, co);
        environment_ = app::bakeFrameEnvironment(device, compiled.plan(), inputs, options);
        if (!environment_.graph) throw std::runtime_error("the frame samples no environment product");
        RendererOptions ro;
        ro.framesInFlight = 2;
        ro.passes = inputs.passes;
        frame_ = std::make_unique<Renderer>(device, std::move(compiled), ro);
        app::attachFrameInputs(*frame_, inputs, environment_);
        for (bool background : {false, true})
            bakers_[background] = std::make_unique<app::EnvironmentBaker>(
                device, *environment_.graph, equirect_.width, equirect_.height, environment_.products, inputs.passes,
                background);
    }

    RunResult run(Mode mode, uint32_t frames, uint32_t changeAt, float brightness) {
        RunResult r;
        r.mode = kModeNames[int(mode)];
        app::EnvironmentBaker& baker = *bakers_[mode != Mode::Sync];
        const HdrImage next = scaled(equirect_, brightness);
        // The application's loader thread: what it stages meanwhile costs the frames nothing. It
        // keeps its buffer for the next change, as a pool would: freeing host-visible memory
        // where the bake lets go of it (on the frame's thread, at the swap) takes milliseconds.
        std::shared_ptr<StagingBuffer> staged;
        std::exception_ptr loaderError;
        std::thread loader;
        if (mode == Mode::Staged)
            loader = std::thread([&] {
                try {
                    if (!loaderBuffer_ || loaderBuffer_.use_count() > 1)
                        loaderBuffer_ = StagingBuffer::create(device_, baker.stagingBytes());
                    staged = loaderBuffer_;
                    std::memcpy(staged->bytes().data(), next.rgba.data(), baker.stagingBytes());
                } catch (...) {
                    loaderError = std::current_exception();
                }
            });
        std::vector<double> before, after;
        auto last = Clock::now();
        for (uint32_t i = 0; i < frames; ++i) {
            if (i == changeAt) {
                if (loader.joinable()) loader.join();
                if (loaderError) std::rethrow_exception(loaderError);
                const bool started = staged ? baker.start(std::move(staged)) : baker.start(next);
                if (!started) throw std::runtime_error("the previous bake is still pending");
                r.setupMs = baker.lastStartMs();
            }
            const auto swapStart = Clock::now();
            if (baker.swapInWhenFinished(*frame_)) {
                r.framesToSwap = i - changeAt;
                r.swapMs = ms(Clock::now() - swapStart);
            }
            frame_->renderFrame();
            const auto now = Clock::now();
            (i < changeAt ? before : after).push_back(ms(now - last));
            last = now;
        }
        if (baker.pending()) {  // not finished within the run: finish it outside the figures
            frame_->waitIdle();
            while (!baker.swapInWhenFinished(*frame_)) {
            }
            r.framesToSwap = frames;
        }
        frame_->waitIdle();
        r.steadyMs = median(before);
        const auto worst = std::max_element(after.begin(), after.end());
        r.worstMs = after.empty() ? 0.0 : *worst;
        r.worstAt = static_cast<uint32_t>(worst - after.begin());
        const size_t window = std::min<size_t>(after.size(), size_t(r.framesToSwap) + 2);
        r.changeWorstMs = window ? *std::max_element(after.begin(), after.begin() + std::ptrdiff_t(window)) : 0.0;
        r.worstBeforeMs = before.empty() ? 0.0 : *std::max_element(before.begin(), before.end());
        return r;
    }

private:
    Device& device_;
    std::shared_ptr<StagingBuffer> loaderBuffer_;
    HdrImage equirect_;
    app::FrameEnvironment environment_;  // the first products, until the first swap
    std::unique_ptr<app::EnvironmentBaker> bakers_[2];  // [background]
    std::unique_ptr<Renderer> frame_;
};

}  // namespace
}  // namespace skygraph::bench

int main(int argc, char** argv) {
    using namespace skygraph;
    CLI::App cli{"The longest frame during an environment change: synchronous against background re-bake"};
    std::string scene = std::string(SKYGRAPH_SOURCE_DIR) + "/scenes/studio.json";
    std::string size = "1920x1080", csv;
    uint32_t frames = 60, changeAt = 20, reps = 5;
    cli.add_option("--scene", scene, "A scene with an environment file");
    cli.add_option("--size", size, "Output WIDTHxHEIGHT");
    cli.add_option("--frames", frames, "Frames per run")->check(CLI::PositiveNumber);
    cli.add_option("--change-at", changeAt, "The frame at which the environment changes");
    cli.add_option("--reps", reps, "Runs of each mode, alternating")->check(CLI::PositiveNumber);
    cli.add_option("--csv", csv, "Write every run to this CSV file");
    CLI11_PARSE(cli, argc, argv);
    uint32_t width = 0, height = 0;
    if (std::sscanf(size.c_str(), "%ux%u", &width, &height) != 2 || width == 0 || height == 0) {
        std::fprintf(stderr, "rebake_bench: --size wants WxH\n");
        return 2;
    }
    if (changeAt >= frames) {
        std::fprintf(stderr, "rebake_bench: --change-at must be below --frames\n");
        return 2;
    }
    try {
        static const PassLibrary library = PassLibrary::withBuiltins();
        DeviceOptions dopts;
        if (const char* d = std::getenv("SKYGRAPH_BENCH_DEVICE")) dopts.device = d;
        auto device = Device::create(dopts);
        const auto families = device->queueFamilies();
        std::printf("device: %s; queue families graphics %u, compute %u, transfer %u\n", device->name().c_str(),
                    families[0], families[1], families[2]);
        app::RenderOptions options;
        options.graph = std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json";
        options.scene = scene;
        options.width = width;
        options.height = height;
        options.framesInFlight = 2;
        options.passes = &library;
        bench::Bench bench(*device, options);
        std::vector<bench::RunResult> runs;
        for (uint32_t rep = 0; rep < reps; ++rep)
            for (uint32_t k = 0; k < 3; ++k) {
                const auto mode = bench::Mode((rep + k) % 3);  // rotate which mode goes first
                runs.push_back(bench.run(mode, frames, changeAt, rep % 2 ? 2.0f : 0.5f));
                const auto& r = runs.back();
                std::printf("%-6s steady %7.3f ms  worst %8.3f ms (frame +%u)  start %8.3f ms  swap %7.3f ms after %u frames\n",
                            r.mode.c_str(), r.steadyMs, r.worstMs, r.worstAt, r.setupMs, r.swapMs, r.framesToSwap);
            }
        auto med = [&](const char* mode, double bench::RunResult::*field) {
            std::vector<double> v;
            for (const auto& r : runs)
                if (r.mode == mode) v.push_back(r.*field);
            return bench::median(v);
        };
        const double syncWorst = med("sync", &bench::RunResult::worstMs);
        std::printf("median over %u runs each at %s:\n", reps, size.c_str());
        for (const char* mode : bench::kModeNames) {
            const double worst = med(mode, &bench::RunResult::worstMs);
            std::printf("  %-6s steady %.3f ms, worst frame %.3f ms (%.3fx sync), worst of the change (start to the "
                        "frame after the swap) %.3f ms, worst before it %.3f ms, start %.3f ms\n",
                        mode, med(mode, &bench::RunResult::steadyMs), worst, syncWorst > 0 ? worst / syncWorst : 0.0,
                        med(mode, &bench::RunResult::changeWorstMs), med(mode, &bench::RunResult::worstBeforeMs),
                        med(mode, &bench::RunResult::setupMs));
        }
        if (!csv.empty()) {
            std::ofstream out(csv);
            out << "mode,steady_ms,worst_ms,worst_at,start_ms,swap_ms,frames_to_swap,change_worst_ms,worst_before_ms\n";
            for (const auto& r : runs)
                out << r.mode << ',' << r.steadyMs << ',' << r.worstMs << ',' << r.worstAt << ',' << r.setupMs << ','
                    << r.swapMs << ',' << r.framesToSwap << ',' << r.changeWorstMs << ',' << r.worstBeforeMs << '\n';
        }
        const uint32_t messages = device->messageCount();
        std::printf("rebake_bench: validation: %u message(s)\n", messages);
        return messages == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "rebake_bench: %s\n", e.what());
        return 1;
    }
}
