// The plan verifier's cost as graphs grow, and on the shipped deferred frame:
//
//   build-rel/bench/verifier_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// BM_VerifyChain/N: N Generic passes in a line, each reading the image the one before wrote and
// writing its own, all of one size, so that aliasing puts every image in one of two places and
// each image shares memory with half the others: the shape that makes the pairwise checks work
// hardest across aliases. docs/verifier.md ("Cost") records the figures.
#include <skygraph/compiler.hpp>
#include <skygraph/verifier.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace {

using namespace skygraph;

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

std::string chainGraph(int passes) {
    std::string resources, uses;
    const auto image = [](const std::string& name) {
        return "\"" + name + "\": {\"type\": \"image2d\", \"format\": \"R8G8B8A8_UNORM\", \"extent\": [64, 64]";
    };
    for (int i = 0; i < passes; ++i) {
        const std::string r = "r" + std::to_string(i);
        resources += image(r) + "},\n";
        const std::string reads = i == 0 ? "" : "\"r" + std::to_string(i - 1) + "\": \"Read@Compute\", ";
        uses += "{\"name\": \"p" + std::to_string(i) + "\", \"type\": \"Generic\", \"uses\": {" + reads + "\"" + r +
                "\": \"Write@Compute\"}},\n";
    }
    resources += image("out") + ", \"external\": true, \"final\": \"TransferSrc\"}";
    uses += "{\"name\": \"last\", \"type\": \"Generic\", \"uses\": {\"r" + std::to_string(passes - 1) +
            "\": \"Read@Fragment\", \"out\": \"Write@ColorAttachment\"}}";
    return "{\"version\": 1, \"name\": \"chain\", \"resources\": {" + resources + "}, \"passes\": [" + uses + "]}";
}

void verify(benchmark::State& state, const GraphDesc& graph) {
    const Plan plan = compile(graph, CompileOptions{});
    size_t pairs = 0;
    for (auto _ : state) {
        const verifier::VerificationReport report = verifier::verifyPlan(plan, graph);
        if (!report.ok()) throw std::logic_error("verifier_bench: findings in a compiled plan: " + report.summary());
        pairs = report.pairsChecked;
        benchmark::DoNotOptimize(report);
    }
    state.counters["passes"] = static_cast<double>(plan.passes().size());
    state.counters["pairs"] = static_cast<double>(pairs);
}

void BM_VerifyChain(benchmark::State& state) {
    const GraphDesc graph = parseGraph(chainGraph(static_cast<int>(state.range(0))), "chain.json", registry());
    verify(state, graph);
}
BENCHMARK(BM_VerifyChain)->Arg(100)->Arg(200)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

void BM_VerifyDeferred(benchmark::State& state) {
    const GraphDesc graph =
        loadGraphFile(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "deferred.json", registry());
    verify(state, graph);
}
BENCHMARK(BM_VerifyDeferred)->Unit(benchmark::kMillisecond);

}  // namespace
