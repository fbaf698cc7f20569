// Transient memory: what each placement strategy allocates against the lower bound, on the
// shipped graphs, and the compile time each costs, side by side in one run:
//
//   build-rel/bench/memory_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Per graph, output size and strategy the counters are the plan's heap bytes (MiB), the most
// bytes live in any one pass (peak_MiB, the bound no placement can beat), the sum without
// sharing (unaliased_MiB), and the ratios heap/peak and unaliased/peak. Sizes come from the
// device-free estimate (docs/memory.md, "Requirements"); docs/performance.md records the
// table, and the device's own figures where they differ.
#include <skygraph/compiler.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <string>

namespace {

using namespace skygraph;

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

const GraphDesc& shipped(const std::string& name) {
    static std::map<std::string, GraphDesc> cache;
    auto it = cache.find(name);
    if (it == cache.end())
        it = cache.emplace(name, loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / (name + ".json"),
                                               registry())).first;
    return it->second;
}

void placement(benchmark::State& state, const std::string& graph, const FeatureValues& features, uint32_t width,
               uint32_t height, MemoryStrategy strategy) {
    CompileOptions o;
    o.features = features;
    o.outputWidth = width;
    o.outputHeight = height;
    o.placement = strategy;
    const GraphDesc& g = shipped(graph);
    const MemoryLayout m = compile(g, o).memory();
    for (auto _ : state) {
        Plan plan = compile(g, o);
        benchmark::DoNotOptimize(plan);
    }
    constexpr double kMiB = 1 << 20;
    const double peak = static_cast<double>(m.peakLiveBytes);
    state.counters["transients"] = static_cast<double>(m.placements.size());
    state.counters["heap_MiB"] = static_cast<double>(m.heapBytes()) / kMiB;
    state.counters["peak_MiB"] = peak / kMiB;
    state.counters["unaliased_MiB"] = static_cast<double>(m.unaliasedBytes) / kMiB;
    state.counters["heap_per_peak"] = peak > 0 ? static_cast<double>(m.heapBytes()) / peak : 1.0;
    state.counters["unaliased_per_peak"] = peak > 0 ? static_cast<double>(m.unaliasedBytes) / peak : 1.0;
}

void registerAll() {
    struct Size {
        const char* name;
        uint32_t width, height;
    };
    const Size sizes[] = {{"1080p", 1920, 1080}, {"4k", 3840, 2160}};
    const MemoryStrategy strategies[] = {MemoryStrategy::BestFitBySize, MemoryStrategy::FirstUseOrder,
                                         MemoryStrategy::Unaliased};
    // The shipped graphs with transients: the deferred frame with every feature and with
    // none (its shortest frame), and the raster frame (whose two transients live together).
    struct Graph {
        const char* label;
        const char* file;
        FeatureValues features;
    };
    const Graph graphs[] = {
        {"deferred", "deferred", {}},
        {"deferred-minimal", "deferred", {{"ssao", false}, {"ssr", false}, {"dof", false}, {"bloom", false}}},
        {"raster", "raster", {}}};
    for (const Graph& g : graphs)
        for (const Size& size : sizes)
            for (const MemoryStrategy s : strategies)
                benchmark::RegisterBenchmark(
                    (std::string("BM_Placement/") + g.label + "/" + size.name + "/" + toString(s)).c_str(),
                    [=](benchmark::State& state) { placement(state, g.file, g.features, size.width, size.height, s); })
                    ->Unit(benchmark::kMicrosecond);
}

const bool kRegistered = (registerAll(), true);

}  // namespace
