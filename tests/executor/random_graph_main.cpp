// random_graphs: runs generated graphs in bulk, for tools/random-graphs.sh.
//   random_graphs FIRST_SEED COUNT [--minimality N]
// Every graph is compiled and rendered under validation (random_graph_check.hpp); every
// fourth is also run with its passes reordered. With --minimality, the first N seeds are
// also generated small and every barrier weakening must be caught. Prints each failure
// with its seed, graph and messages, and ends with "N passed, N failed".
#include "random_graph_check.hpp"

#include <skygraph/compiler.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace skygraph;
using namespace skygraph::test;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s FIRST_SEED COUNT [--minimality N]\n", argv[0]);
        return 2;
    }
    const auto first = static_cast<uint32_t>(std::strtoul(argv[1], nullptr, 10));
    const auto count = static_cast<uint32_t>(std::strtoul(argv[2], nullptr, 10));
    uint32_t minimality = 0;
    if (argc >= 5 && std::string(argv[3]) == "--minimality")
        minimality = static_cast<uint32_t>(std::strtoul(argv[4], nullptr, 10));
    DeviceOptions o;
    o.validation = true;
    o.logMessages = false;
    o.device = "llvmpipe";
    auto device = Device::create(o);
    uint32_t passed = 0, failed = 0, graphs = 0;
    size_t mutations = 0, unneeded = 0;
    auto report = [&](uint32_t seed, const std::string& what, const std::string& detail, const std::string& json) {
        ++failed;
        std::printf("FAILED seed %u %s:\n%s\n%s\n", seed, what.c_str(), detail.c_str(), json.c_str());
    };
    for (uint32_t seed = first; seed < first + count; ++seed) {
        const RandomGraph g = generateRandomGraph(seed);
        const GraphRun run = runGraph(*device, g.json(), g.features, settingsForSeed(seed));
        ++graphs;
        run.passed() ? void(++passed) : report(seed, "", run.detail, g.json());
        if (seed % 4 == 0) {
            const std::string reordered = g.json(g.shuffledOrder(1));
            const GraphRun again = runGraph(*device, reordered, g.features, settingsForSeed(seed));
            ++graphs;
            again.passed() ? void(++passed) : report(seed, "reordered", again.detail, reordered);
        }
        if (seed % 2 == 0) {
            const RandomGraph q = withRandomQueues(g);
            const GraphRun onQueues = runGraph(*device, q.json(), q.features, settingsForSeed(seed));
            ++graphs;
            onQueues.passed() ? void(++passed) : report(seed, "on queues", onQueues.detail, q.json());
        }
        if (seed - first < minimality) {
            RandomGraphShape small;
            small.maxPasses = 3;
            small.maxResources = 2;
            small.maxUsagesPerPass = 2;
            const RandomGraph s = generateRandomGraph(seed, small);
            const GraphRun base = runGraph(*device, s.json(), s.features);
            if (!base.passed()) {
                report(seed, "small", base.detail, s.json());
                continue;
            }
            const MinimalityReport m = checkMinimality(*device, *base.compiled);
            mutations += m.mutations;
            unneeded += m.unneeded.size();
            for (const auto& u : m.unneeded)
                std::printf("UNNEEDED seed %u: %s%s\n", seed, u.description.c_str(),
                            u.verifierFinds ? " (the plan verifier finds it)" : "");
        }
        if ((seed - first + 1) % 100 == 0) std::fprintf(stderr, "%u graphs, %u failed\n", graphs, failed);
    }
    if (minimality)
        std::printf("minimality: %zu weakenings of %u small graphs, %zu unnoticed\n", mutations, minimality, unneeded);
    std::printf("%u graphs: %u passed, %u failed\n", graphs, passed, failed);
    return failed == 0 && unneeded == 0 ? 0 : 1;
}
