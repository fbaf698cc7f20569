// What an environment sequence costs per frame and in memory, at a given equirect size: the
// streaming sky of `skygraph view` without the window. It writes a time-lapse of the
// procedural sky (writeProceduralSkySequence) and plays it through the pieces LiveGraph uses:
// a SequenceStream decodes ahead on its thread; an EnvironmentBaker of three renderers bakes
// each frame beside a headless frame renderer of graphs/raster.json (environment_sequence on,
// the sky fading from the previous frame's cube), its upload on the transfer queue, and swaps
// it in. It plays the sequence twice, side by side: with the frames staged on the stream's
// thread (what `skygraph view` does), and with the pixels handed over on the host and copied
// to a staging buffer by start() on the calling thread. Per frame it reports
//
//   decode   reading, decoding (and staging) the EXR on the stream's thread
//   start    EnvironmentBaker::start() on the calling thread: staging and the submits
//   bake     from start() to the swap, while the frame renderer keeps rendering
//
// as medians over the frames, and the memory the renderers hold (Device::allocatedBytes,
// staging buffers included): the frame renderer with its first environment, then with the
// baker, which stays the same however many frames play. Host memory: the stream's frames. Where
// the frames are baked smaller than the files (sequenceEquirectWidth), it also bakes one
// frame's cube at both sizes (bakeAndReadBack, on a device of its own) and reports the
// difference.
//
//   sequence_bench [--width W] [--frames N] [--size WxH] [--dir DIR]
//
// Environment: SKYGRAPH_BENCH_DEVICE picks the device, SKYGRAPH_VALIDATION=1 runs under
// validation; the exit status is 1 when a validation message was counted.
#include "app/environment_bake.hpp"
#include "app/equirect_resample.hpp"
#include "app/procedural_environment.hpp"
#include "app/render.hpp"
#include "app/sequence_stream.hpp"

#include "shipped_names.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace skygraph::bench {
namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
double mib(uint64_t bytes) { return double(bytes) / (1024.0 * 1024.0); }

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// The frames at `width`, written once into `dir` (kept for the next run of the same size).
EnvironmentSequence writeFrames(const std::filesystem::path& dir, uint32_t width, uint32_t frames) {
    EnvironmentSequence s;
    s.pattern = (dir / ("sky_" + std::to_string(width) + "_%03d.exr")).string();
    s.count = frames;
    s.fps = 24.0;
    if (!std::filesystem::exists(s.frame(frames - 1))) app::writeProceduralSkySequence(s.pattern, frames, width);
    return s;
}

}  // namespace
}  // namespace skygraph::bench

int main(int argc, char** argv) {
    using namespace skygraph;
    using namespace skygraph::bench;
    CLI::App cli{"An environment sequence's cost per frame and its memory, at one equirect size"};
    uint32_t width = 2048, frames = 8;
    std::string size = "640x360", dir = (std::filesystem::temp_directory_path() / "skygraph-sequence-bench").string();
    cli.add_option("--width", width, "Equirect width (the height is half): 2048 for 2K, 6144 for 6K")
        ->check(CLI::Range(16u, 16384u));
    cli.add_option("--frames", frames, "Frames in the sequence, each played once")->check(CLI::Range(3u, 1000u));
    cli.add_option("--size", size, "The frame renderer's output WIDTHxHEIGHT");
    cli.add_option("--dir", dir, "Where the frames are written (and kept)");
    CLI11_PARSE(cli, argc, argv);
    uint32_t outWidth = 0, outHeight = 0;
    if (std::sscanf(size.c_str(), "%ux%u", &outWidth, &outHeight) != 2 || outWidth == 0 || outHeight == 0) {
        std::fprintf(stderr, "sequence_bench: --size wants WxH\n");
        return 2;
    }
    try {
        const EnvironmentSequence sequence = writeFrames(dir, width, frames);
        static const PassLibrary library = PassLibrary::withBuiltins();
        DeviceOptions dopts;
        if (const char* d = std::getenv("SKYGRAPH_BENCH_DEVICE")) dopts.device = d;
        auto device = Device::create(dopts);
        std::printf("device: %s; equirect %ux%u, %u frames\n", device->name().c_str(), width, width / 2, frames);

        // The frame, as `skygraph view` builds it for a scene whose environment is the sequence.
        const std::filesystem::path scene = std::filesystem::path(dir) / "sequence_scene.json";
        std::ofstream(scene) << R"({"environment": {"sequence": ")" << sequence.pattern << R"(", "fps": 24}})";
        app::RenderOptions options;
        options.graph = std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/raster.json";
        options.scene = scene;
        options.width = outWidth;
        options.height = outHeight;
        options.framesInFlight = 2;
        options.passes = &library;
        app::FrameInputs inputs = app::loadFrameInputs(options);
        CompileOptions co = inputs.compile;
        co.presentReplacement = ExternalState::TransferSrc;
        CompiledGraph compiled(inputs.graph, co);
        app::FrameEnvironment environment = app::bakeFrameEnvironment(*device, compiled.plan(), inputs, options);
        RendererOptions ro;
        ro.framesInFlight = 2;
        ro.passes = inputs.passes;
        Renderer frame(*device, std::move(compiled), ro);
        app::attachFrameInputs(frame, inputs, environment);
        frame.renderFrame();
        frame.waitIdle();
        const uint64_t frameBytes = device->allocatedBytes();

        const auto extent = frame.graph().findResource(shipped::kEquirect)->extent.resolve(outWidth, outHeight);
        SharedImage shown = environment.renderer->shareImage(std::string(shipped::kEnvironment));
        double hostMib = 0.0;
        struct Playback {
            double startMs = 0.0;
            uint64_t mostBytes = 0;
        };
        // One playback of the sequence; `staged`: the stream stages the frames on its thread.
        const auto play = [&](bool staged) {
            uint64_t mostBytes = 0;
            app::EnvironmentBaker baker(*device, *environment.graph, extent[0], extent[1], environment.products,
                                        inputs.passes, true, 3);
            app::SequenceStream stream(sequence, extent[0], extent[1], 1, 2, staged ? device.get() : nullptr);
            std::vector<double> decode, start, bake;
            std::vector<uint32_t> framesPerBake;
            for (uint32_t i = 1; i < frames; ++i) {
                std::optional<app::SequenceFrame> next;
                while (!(next = stream.takeNewest(i, 1))) std::this_thread::sleep_for(std::chrono::milliseconds(1));
                if (!next->error.empty()) throw std::runtime_error(next->error);
                decode.push_back(next->decodeMs);
                const auto begin = Clock::now();
                const bool started = staged ? baker.start(std::move(next->staged)) : baker.start(next->pixels);
                if (!started) throw std::runtime_error("the previous bake is still pending");
                next.reset();  // as LiveGraph does: only the bake holds the frame now
                start.push_back(baker.lastStartMs());
                uint32_t rendered = 0;
                while (!baker.swapInWhenFinished(frame)) {
                    frame.renderFrame();
                    ++rendered;
                }
                bake.push_back(ms(Clock::now() - begin));
                framesPerBake.push_back(rendered);
                // As LiveGraph does: the sky fades from the cube shown until now.
                frame.importImage(std::string(shipped::kEnvironmentPrevious), shown);
                shown = baker.swappedIn(std::string(shipped::kEnvironment));
                frame.frameData().set(SkyFade{0.5});
                frame.renderFrame();
                mostBytes = std::max(mostBytes, device->allocatedBytes());
            }
            frame.waitIdle();
            std::printf("%s (median of %zu): decode %.1f ms, start %.1f ms, bake %.1f ms (%u frames rendered "
                        "meanwhile); memory %.1f MiB%s\n",
                        staged ? "staged on the stream's thread" : "staged by start()  ", decode.size(), median(decode),
                        median(start), median(bake),
                        uint32_t(median(std::vector<double>(framesPerBake.begin(), framesPerBake.end()))),
                        mib(mostBytes),
                        staged ? (", " + std::to_string(stream.stagingBuffers()) + " staging buffer(s)").c_str() : "");
            if (!staged) hostMib = mib(uint64_t(stream.mostFramesHeld()) * extent[0] * extent[1] * 16);
            return Playback{median(start), mostBytes};
        };
        const Playback onStream = play(true), onHost = play(false);
        std::printf("start on the calling thread: staged on the stream's thread / by start() = %.3f\n",
                    onHost.startMs > 0 ? onStream.startMs / onHost.startMs : 0.0);
        const double frameMib = mib(frameBytes), allMib = mib(onStream.mostBytes);
        std::printf("memory (Device::allocatedBytes, staging included): frame renderer %.1f MiB; with the baker's 3 "
                    "renderers and the stream's staging buffers %.1f MiB (the sequence's share %.1f MiB), the same for "
                    "any length; host, unstaged: decoded frames waiting %.1f MiB\n",
                    frameMib, allMib, allMib - frameMib, hostMib);
        const double seedMib = 120.0 * double(width) * (width / 2) * 4 / (1024.0 * 1024.0);
        std::printf("120 frames at this size: every frame resident as 4 bytes a texel %.0f MiB, ours %.0f MiB (%.3fx)\n",
                    seedMib, allMib, allMib / seedMib);
        if (extent[0] < width) {
            // What baking the smaller frames costs in accuracy: frame 1's environment cube baked
            // from the file as it is and from the size the frames are baked at.
            const HdrImage full = loadHdrImage(sequence.frame(1));
            app::BakeOptions o;
            std::ifstream ibl(std::string(SKYGRAPH_SOURCE_DIR) + "/graphs/ibl.json");
            o.graphText.assign(std::istreambuf_iterator<char>(ibl), {});
            o.size = environment.graph->findResource(std::string(shipped::kEnvironment))->extent.width;
            o.products = {};
            o.device = dopts.device;
            const auto cube = [&](const HdrImage& equirect) {
                auto levels = app::bakeAndReadBack(equirect, o).products.at(std::string(shipped::kEnvironment));
                levels.resize(6);  // mip 0's faces
                return levels;
            };
            const auto reference = cube(full), baked = cube(app::resampleEquirect(full, extent[0], extent[1]));
            double sum = 0.0, sumRef = 0.0;
            std::vector<double> relative;
            for (size_t f = 0; f < 6; ++f)
                for (size_t i = 0; i < reference[f].rgba.size(); ++i) {
                    if (i % 4 == 3) continue;
                    const double a = reference[f].rgba[i], b = baked[f].rgba[i];
                    sum += std::abs(a - b);
                    sumRef += std::abs(a);
                    relative.push_back(std::abs(a - b) / std::max(std::abs(a), 1e-3));
                }
            std::sort(relative.begin(), relative.end());
            std::printf("the %u^2 cube baked from %ux%u instead of %ux%u: mean difference %.2e of the mean, relative "
                        "difference 99th percentile %.2e, 99.9th %.2e, largest %.2e\n",
                        o.size, extent[0], extent[1], width, width / 2, sumRef > 0 ? sum / sumRef : 0.0,
                        relative[relative.size() * 99 / 100], relative[relative.size() * 999 / 1000], relative.back());
        } else {
            std::printf("the frames are baked at their own size (%ux%u)\n", width, width / 2);
        }
        const uint32_t messages = device->messageCount();
        std::printf("sequence_bench: validation: %u message(s)\n", messages);
        return messages == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sequence_bench: %s\n", e.what());
        return 1;
    }
}
