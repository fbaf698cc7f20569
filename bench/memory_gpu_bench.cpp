// Transient memory on a device (docs/performance.md, "Transient memory"): what the executor
// allocates, what aliasing costs in frame time, and whether aliasing with clobbering changes a
// rendered byte. Every pass runs as Generic, which performs exactly its declared accesses.
//
//   memory_gpu_bench [--device D] memory [--size WxH]... GRAPH...
//       per graph (default features) and size: heap bytes per copy with each placement
//       strategy from the device's requirements, beside the transients laid end to end
//       (unaliased), the most of them live at once (peak live) and the estimate's figure
//   memory_gpu_bench [--device D] time --size WxH [--frames N] [--rounds R] GRAPH
//       the graph headless with 2 frames in flight, as placed three ways: without aliasing,
//       aliased with heaps per frame in flight, aliased in heaps the frames share. Per way,
//       interleaved over R rounds: the GPU time of a frame waited for alone, and the wall
//       time per frame of N frames submitted back to back (the frames overlap unless a
//       barrier orders them); medians. With --layouts, two ways instead, both aliased in shared
//       heaps: runs of reads in one layout (fewest barriers) and in each reader's optimal one
//   memory_gpu_bench [--device D] compare [--size WxH] [--seeds N] GRAPH...
//       every feature combination of each graph, and N random Generic graphs whose read-back
//       depends on chains of transients: the read-back of 3 frames rendered with aliasing and
//       clobbering (frames sharing the heaps for odd combinations) against one rendered
//       without aliasing, byte for byte
#include "generic_passes.hpp"
#include "headless_options.hpp"
#include "random_graph_generator.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/renderer.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using namespace skygraph;
using Clock = std::chrono::steady_clock;

struct Size {
    uint32_t width = 0, height = 0;
};

/// "1920x1080" as a Size, or why not (for CLI11's check).
std::string sizeProblem(const std::string& text) {
    Size s;
    if (std::sscanf(text.c_str(), "%ux%u", &s.width, &s.height) != 2 || s.width == 0 || s.height == 0)
        return "'" + text + "' is not a size like 1920x1080";
    return {};
}

Size parseSize(const std::string& text) {
    Size s;
    std::sscanf(text.c_str(), "%ux%u", &s.width, &s.height);
    return s;
}

double mib(uint64_t bytes) { return static_cast<double>(bytes) / double(1 << 20); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

/// How a graph's transients are placed for a run.
struct Placement {
    const char* name;
    MemoryStrategy strategy;
    bool aliasing;
    bool shareFrames;
};
constexpr Placement kUnaliased{"unaliased", MemoryStrategy::Unaliased, false, false};
constexpr Placement kPerFrame{"aliased, heaps per frame", MemoryStrategy::BestFitBySize, true, false};
constexpr Placement kShared{"aliased, heaps shared", MemoryStrategy::BestFitBySize, true, true};

CompileOptions options(const Device& device, const GraphDesc& graph, Size size, const Placement& p,
                       bool clobber = false, const FeatureValues& features = {}) {
    CompileOptions o = test::sizedOptions(size.width, size.height);
    o.features = features;
    o.memory = device.memoryModel();
    o.placement = p.strategy;
    o.aliasing = p.aliasing;
    o.shareTransientsAcrossFrames = p.shareFrames;
    o.clobberTransients = clobber;
    return test::headless(graph, o);
}

void reportMemory(const Device& device, const std::vector<std::string>& graphs, const std::vector<Size>& sizes) {
    std::printf("| graph | output | transients | best fit (MiB) | first use (MiB) | unaliased (MiB) | peak live (MiB) | "
                "best fit / peak | best fit, estimate (MiB) |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for (const std::string& file : graphs) {
        const GraphDesc graph = loadGraphFile(file, PassRegistry::withBuiltins());
        for (const Size size : sizes) {
            try {
                const Plan best = compile(graph, options(device, graph, size, kPerFrame));
                Placement firstUse = kPerFrame;
                firstUse.strategy = MemoryStrategy::FirstUseOrder;
                const Plan first = compile(graph, options(device, graph, size, firstUse));
                CompileOptions estimated = options(device, graph, size, kPerFrame);
                estimated.memory = estimatedMemory();
                const Plan estimate = compile(graph, estimated);
                const MemoryLayout& m = best.memory();
                const double peak = mib(m.peakLiveBytes);
                std::printf("| %s | %ux%u | %zu | %.2f | %.2f | %.2f | %.2f | %.3f | %.2f |\n", graph.name.c_str(),
                            size.width, size.height, m.placements.size(), mib(m.heapBytes()),
                            mib(first.memory().heapBytes()), mib(m.unaliasedBytes), peak,
                            peak > 0 ? mib(m.heapBytes()) / peak : 1.0, mib(estimate.memory().heapBytes()));
            } catch (const std::exception& e) {
                std::printf("| %s | %ux%u | %s |\n", graph.name.c_str(), size.width, size.height, e.what());
            }
        }
    }
}

/// One way to compile the graph for `time`: a placement, and how runs of reads are laid out.
struct Way {
    std::string name;
    Placement placement;
    LayoutPolicy layouts = LayoutPolicy::FewestBarriers;
};

size_t barrierCount(const Plan& plan) {
    size_t n = plan.finalBarriers().size() + plan.inPassBarriers().size();
    for (const PlannedPass& p : plan.passes()) n += p.barriers.size();
    return n;
}

void reportTime(Device& device, const std::string& file, Size size, uint32_t frames, uint32_t rounds, bool layouts) {
    const GraphDesc graph = loadGraphFile(file, PassRegistry::withBuiltins());
    std::vector<Way> ways;
    if (layouts) {
        ways = {{"fewest barriers", kShared, LayoutPolicy::FewestBarriers},
                {"optimal layouts", kShared, LayoutPolicy::Optimal}};
    } else {
        for (const Placement& p : {kUnaliased, kPerFrame, kShared}) ways.push_back({p.name, p});
    }
    std::vector<std::unique_ptr<Renderer>> renderers;
    for (const Way& w : ways) {
        CompileOptions o = options(device, graph, size, w.placement);
        o.layouts = w.layouts;
        renderers.push_back(std::make_unique<Renderer>(device, CompiledGraph(graph, o), test::genericOptions(2)));
        for (int i = 0; i < 5; ++i) renderers.back()->renderFrame();  // pipelines and caches warm
        renderers.back()->waitIdle();
    }
    std::vector<std::vector<double>> gpu(ways.size()), wall(ways.size());
    for (uint32_t round = 0; round < rounds; ++round)
        for (size_t w = 0; w < ways.size(); ++w) {
            Renderer& r = *renderers[w];
            r.renderFrame();
            r.waitIdle();
            double sum = 0.0;
            for (const PassTiming& t : r.lastTimings()) sum += t.milliseconds;
            gpu[w].push_back(sum);
            const auto start = Clock::now();
            for (uint32_t i = 0; i < frames; ++i) r.renderFrame();
            r.waitIdle();
            wall[w].push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count() / frames);
        }
    std::printf("%s at %ux%u on %s, 2 frames in flight, every pass as Generic; medians of %u rounds:\n",
                graph.name.c_str(), size.width, size.height, device.name().c_str(), rounds);
    for (size_t w = 0; w < ways.size(); ++w) {
        const MemoryLayout& m = renderers[w]->plan().memory();
        const uint64_t allocated = m.heapBytes() * (m.sharedAcrossFrames ? 1 : 2);
        std::printf("  %-26s %3zu barriers, transients %8.2f MiB allocated: frame alone %8.3f ms (GPU, passes), "
                    "%u back to back %8.3f ms per frame (wall)\n",
                    ways[w].name.c_str(), barrierCount(renderers[w]->plan()), mib(allocated), median(gpu[w]), frames,
                    median(wall[w]));
    }
}

/// The read-back after 3 frames, or the error.
std::vector<float> render(Device& device, const GraphDesc& graph, const CompileOptions& o, std::string& error) {
    try {
        Renderer r(device, CompiledGraph(graph, o), test::genericOptions(2));
        for (int i = 0; i < 3; ++i) r.renderFrame();
        return r.readback(*o.readbacks.begin()).rgba;
    } catch (const std::exception& e) {
        error = e.what();
        return {};
    }
}

/// Whether `graph` under `features` renders the same aliased and clobbered as unaliased.
bool same(Device& device, const GraphDesc& graph, const FeatureValues& features, Size size, bool shareFrames,
          std::string& detail) {
    const CompileOptions a = options(device, graph, size, shareFrames ? kShared : kPerFrame, true, features);
    const CompileOptions u = options(device, graph, size, kUnaliased, false, features);
    if (a.readbacks.empty()) {
        detail = "no read-back";
        return true;
    }
    std::string error;
    const std::vector<float> x = render(device, graph, a, error), y = render(device, graph, u, error);
    if (!error.empty()) {
        detail = error;
        return false;
    }
    if (x.size() != y.size()) {
        detail = "sizes differ";
        return false;
    }
    // Bytes, not values: NaN poison that leaked would compare unequal to itself anyway.
    size_t differing = 0;
    for (size_t i = 0; i < x.size(); ++i) differing += std::memcmp(&x[i], &y[i], sizeof(float)) != 0;
    detail = std::to_string(differing) + " of " + std::to_string(x.size()) + " values differ";
    return differing == 0;
}

int compareImages(Device& device, const std::vector<std::string>& graphs, Size size, uint32_t seeds) {
    uint32_t cases = 0, failures = 0;
    for (const std::string& file : graphs) {
        const GraphDesc graph = loadGraphFile(file, PassRegistry::withBuiltins());
        const size_t n = graph.features.size();
        for (size_t mask = 0; mask < (size_t(1) << n); ++mask) {
            FeatureValues features;
            for (size_t i = 0; i < n; ++i) features[graph.features[i].name] = (mask >> i & 1u) != 0;
            std::string detail;
            ++cases;
            if (!same(device, graph, features, size, mask % 2 == 1, detail)) {
                ++failures;
                std::printf("DIFFERS %s features %zu: %s\n", graph.name.c_str(), mask, detail.c_str());
            }
        }
    }
    for (uint32_t seed = 1; seed <= seeds; ++seed) {
        test::RandomGraphShape shape;
        shape.chains = 2;
        const test::RandomGraph g = test::generateRandomGraph(seed, shape);
        const GraphDesc graph = parseGraph(g.json(), "random" + std::to_string(seed) + ".json",
                                           PassRegistry::withBuiltins());
        std::string detail;
        ++cases;
        if (!same(device, graph, g.features, {shape.outputSize, shape.outputSize}, seed % 2 == 1, detail)) {
            ++failures;
            std::printf("DIFFERS random seed %u: %s\n", seed, detail.c_str());
        }
    }
    std::printf("compare on %s: %u cases, %u differ\n", device.name().c_str(), cases, failures);
    return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"memory_gpu_bench: transient memory, frame time and images with and without aliasing"};
    app.require_subcommand(1);
    DeviceOptions d;
    d.logMessages = false;
    std::vector<std::string> graphs, sizeTexts;
    uint32_t frames = 20, rounds = 9, seeds = 0;
    bool layouts = false;
    app.add_option("--device", d.device, "Physical device: index or name substring (e.g. nvidia, llvmpipe)");
    const auto addGraphs = [&](CLI::App* mode, bool one) {
        mode->add_option("GRAPH", graphs, one ? "The graph file" : "Graph files")->required()->expected(1, one ? 1 : -1);
    };
    const auto addSizes = [&](CLI::App* mode, const char* what) {
        return mode->add_option("--size", sizeTexts, what)->check(CLI::Validator(sizeProblem, "WxH"));
    };
    CLI::App* memory = app.add_subcommand("memory", "Heap bytes per copy with each placement strategy, per graph and size");
    addSizes(memory, "Output WIDTHxHEIGHT (repeatable; default 1920x1080 and 3840x2160)");
    addGraphs(memory, false);
    CLI::App* time = app.add_subcommand("time", "Frame time placed three ways, interleaved over rounds (medians)");
    addSizes(time, "Output WIDTHxHEIGHT (repeatable)")->required();
    time->add_option("--frames", frames, "Frames submitted back to back per way and round")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    time->add_option("--rounds", rounds, "Rounds")->check(CLI::PositiveNumber)->capture_default_str();
    time->add_flag("--layouts", layouts, "Compare runs of reads in one layout with each reader's optimal one instead");
    addGraphs(time, true);
    CLI::App* compare = app.add_subcommand("compare", "Read-backs aliased and clobbered against unaliased, byte for byte");
    addSizes(compare, "Output WIDTHxHEIGHT (default 64x64)")->expected(0, 1);
    compare->add_option("--seeds", seeds, "Random Generic graphs besides the files")->capture_default_str();
    addGraphs(compare, false);
    CLI11_PARSE(app, argc, argv);
    std::vector<Size> sizes;
    for (const std::string& text : sizeTexts) sizes.push_back(parseSize(text));
    try {
        auto device = Device::create(d);
        std::printf("device: %s\n", device->name().c_str());
        if (memory->parsed()) {
            if (sizes.empty()) sizes = {{1920, 1080}, {3840, 2160}};
            reportMemory(*device, graphs, sizes);
            return 0;
        }
        if (time->parsed()) {
            for (const Size s : sizes) reportTime(*device, graphs.front(), s, frames, rounds, layouts);
            return 0;
        }
        return compareImages(*device, graphs, sizes.empty() ? Size{64, 64} : sizes.front(), seeds);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "memory_gpu_bench: %s\n", e.what());
        return 1;
    }
}
