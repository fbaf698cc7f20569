// Shared by the verifier's tests and tools/verify-random-plans.sh's runner.
#include "verifier_test_util.hpp"

#include "random_graph_generator.hpp"

#include <skygraph/diagnostics.hpp>

#include <algorithm>
#include <exception>
#include <optional>
#include <stdexcept>

namespace skygraph::test {

namespace fs = std::filesystem;

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

std::vector<fs::path> shippedGraphs() {
    const fs::path source = SKYGRAPH_SOURCE_DIR;
    std::vector<fs::path> graphs;
    for (const auto& e : fs::directory_iterator(source / "graphs"))
        if (e.path().extension() == ".json") graphs.push_back(e.path());
    std::sort(graphs.begin(), graphs.end());
    return graphs;
}

std::vector<FeatureValues> featureCombinations(const GraphDesc& graph) {
    std::vector<FeatureValues> out;
    const size_t n = graph.features.size();
    for (size_t mask = 0; mask < (size_t(1) << n); ++mask) {
        FeatureValues v;
        for (size_t i = 0; i < n; ++i) v[graph.features[i].name] = (mask >> i & 1u) != 0;
        out.push_back(std::move(v));
    }
    return out;
}

CompileOptions headless(const GraphDesc& graph, CompileOptions co) {
    co.presentReplacement = ExternalState::TransferSrc;
    const Plan plan = compile(graph, co);
    for (const ResourceDesc& r : graph.resources)
        if (r.final == ExternalState::Present && plan.resourceIndex(r.name) >= 0) co.readbacks.insert(r.name);
    return co;
}

std::string describe(const std::vector<verifier::Finding>& findings) {
    std::string s;
    for (const verifier::Finding& f : findings) s += "  " + verifier::format(f) + "\n";
    return s;
}

namespace {

void verifyOne(uint32_t seed, const std::string& variant, const std::string& json, const FeatureValues& features,
               bool headlessRun, MemoryStrategy placement, bool clobber, RandomResult& result, bool shareFrames = true,
               std::optional<LayoutPolicy> layouts = std::nullopt,
               std::array<uint32_t, kQueueKinds> queueFamilies = CompileOptions{}.queueFamilies) {
    try {
        const GraphDesc graph = parseGraph(json, "random" + std::to_string(seed) + ".json", registry());
        CompileOptions co;
        co.features = features;
        co.outputWidth = co.outputHeight = RandomGraphShape{}.outputSize;
        co.placement = placement;
        co.clobberTransients = clobber;
        co.shareTransientsAcrossFrames = shareFrames;
        co.layouts = layouts;
        co.queueFamilies = queueFamilies;
        if (headlessRun) co = headless(graph, co);
        const Plan plan = compile(graph, co);
        const verifier::VerificationReport report = verifier::verifyPlan(plan, graph);
        ++result.plans;
        result.aliasingPlans += std::any_of(plan.memory().placements.begin(), plan.memory().placements.end(),
                                            [](const MemoryPlacement& p) { return !p.aliases.empty(); });
        result.findings += static_cast<uint32_t>(report.findings.size());
        if (!report.ok()) result.failures.push_back({seed, variant, describe(report.findings), json});
    } catch (const std::exception& e) {
        ++result.compileErrors;
        result.failures.push_back({seed, variant, std::string("does not compile: ") + e.what(), json});
    }
}

}  // namespace

void verifyRandomGraph(uint32_t seed, RandomResult& result) {
    // Chains of short-lived transients, buffers among them, make resources take over each
    // other's memory whatever the random passes do.
    RandomGraphShape chained;
    chained.chains = 1 + seed % 3;
    chained.chainBuffers = true;
    const RandomGraph c = generateRandomGraph(seed, chained);
    // Frames in flight share the heaps by default (the second frame's first uses take over
    // what the first left); even seeds give each frame heaps of its own.
    verifyOne(seed, seed % 2 ? "chains" : "chains, heaps per frame", c.json(), c.features, seed % 2 == 0,
              MemoryStrategy::BestFitBySize, seed % 3 == 0, result, seed % 2 == 1);
    const RandomGraph g = generateRandomGraph(seed);
    const bool clobber = seed % 2 == 1;
    // Odd seeds present with each reader of an image in its optimal layout.
    const bool optimal = seed % 2 == 1;
    verifyOne(seed, optimal ? "presenting, optimal layouts" : "presenting", g.json(), g.features, false,
              MemoryStrategy::BestFitBySize, false, result, true,
              optimal ? std::optional(LayoutPolicy::Optimal) : std::nullopt);
    verifyOne(seed, clobber ? "headless, first-use placement, clobbered" : "headless, first-use placement", g.json(),
              g.features, true, MemoryStrategy::FirstUseOrder, clobber, result);
    if (seed % 4 == 0)
        verifyOne(seed, "reordered", g.json(g.shuffledOrder(1)), g.features, false, MemoryStrategy::BestFitBySize,
                  false, result);
    // On several queues: the random graph's passes and the chained one's, on the queue families
    // chooseQueues picks on real devices: three (ownership transfers), one, and two, where
    // queues of one family must order ownership between them (async compute with the transfer
    // kind on its family; graphics and compute on one family beside a DMA engine).
    struct Families {
        std::array<uint32_t, kQueueKinds> families;
        const char* name;
    };
    static constexpr std::array<Families, 4> kFamilies{{{{0, 0, 0}, "one queue family"},
                                                        {{0, 1, 2}, "three queue families"},
                                                        {{0, 0, 1}, "graphics and compute on one family"},
                                                        {{0, 1, 1}, "compute and transfer on one family"}}};
    const auto& [families, familiesName] = kFamilies[seed % 4];
    // Every other run of four seeds with readers in their optimal layouts: reads of one image
    // in several layouts make transfers carry transitions.
    const bool queuesOptimal = seed / 4 % 2 == 1;
    const RandomGraph q = withRandomQueues(g);
    verifyOne(seed, std::string("queues, ") + familiesName + (queuesOptimal ? ", optimal layouts" : ""), q.json(),
              q.features, seed % 3 == 0, MemoryStrategy::BestFitBySize, false, result, true,
              queuesOptimal ? std::optional(LayoutPolicy::Optimal) : std::nullopt, families);
    const RandomGraph qc = withRandomQueues(c, 1);
    verifyOne(seed, std::string("chains on queues, ") + familiesName, qc.json(), qc.features, true,
              MemoryStrategy::BestFitBySize, seed % 3 == 0, result, seed % 2 == 1, std::nullopt, families);
}

}  // namespace skygraph::test

namespace skygraph::test {

Compiled compileText(const std::string& json, CompileOptions options) {
    if (options.outputWidth == CompileOptions{}.outputWidth && options.outputHeight == CompileOptions{}.outputHeight)
        options.outputWidth = options.outputHeight = 16;
    GraphDesc graph = parseGraph(json, "test.json", registry());
    Plan plan = compile(graph, options);
    return {std::move(graph), std::move(plan)};
}

Compiled compileShipped(const std::string& name, CompileOptions options) {
    GraphDesc graph = loadGraphFile(fs::path(SKYGRAPH_SOURCE_DIR) / "graphs" / name, registry());
    Plan plan = compile(graph, options);
    return {std::move(graph), std::move(plan)};
}

size_t submitOf(const Plan& plan, size_t step) {
    for (size_t k = 0; k < plan.submits().size(); ++k)
        for (uint32_t p : plan.submits()[k].passes)
            if (p == step) return k;
    throw std::out_of_range("no submit holds the step");
}

size_t stepIndex(const Plan& plan, std::string_view name) {
    for (size_t i = 0; i < plan.passes().size(); ++i)
        if (plan.passes()[i].name == name) return i;
    throw std::out_of_range("no step " + std::string(name));
}

size_t barrierOn(const Plan& plan, size_t step, std::string_view resource) {
    if (step >= plan.passes().size()) throw std::out_of_range("no step " + std::to_string(step));
    const auto barriers = plan.passes()[step].barriers;
    for (size_t i = 0; i < barriers.size(); ++i)
        if (barriers[i].kind != BarrierKind::Memory && plan.resources()[barriers[i].resource].name == resource)
            return i;
    throw std::out_of_range("no barrier on " + std::string(resource));
}

size_t usageOf(const Plan& plan, size_t step, std::string_view resource) {
    if (step >= plan.passes().size()) throw std::out_of_range("no step " + std::to_string(step));
    const auto usages = plan.passes()[step].usages;
    for (size_t i = 0; i < usages.size(); ++i)
        if (plan.resources()[usages[i].resource].name == resource) return i;
    throw std::out_of_range("no usage of " + std::string(resource));
}

bool hasFinding(const verifier::VerificationReport& report, verifier::FindingKind kind, std::string_view resource) {
    return std::any_of(report.findings.begin(), report.findings.end(), [&](const verifier::Finding& f) {
        return f.kind == kind && (resource.empty() || std::find(f.resourceNames.begin(), f.resourceNames.end(),
                                                                resource) != f.resourceNames.end());
    });
}

}  // namespace skygraph::test
