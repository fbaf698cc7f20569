// Compiler throughput on synthetic Generic graphs of 10 to 100,000 passes with about four
// usages each. Parsing (parseGraph) and compiling (compile) are measured separately.
//
//   build/bench/compile_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// The counter `time_per_usage` is the time per usage (e.g. "25n" = 25 ns); docs/performance.md
// records the table. Target: 10,000 passes compile in under 5 ms, scaling linearly; graphs load
// at over 100 MB/s of text, whatever their size.
#include <skygraph/compiler.hpp>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <map>
#include <string>

namespace {

using namespace skygraph;

#if defined(__GLIBC__)
// glibc gives the top of its heap back to the system whenever a free leaves more than a
// threshold there, and moves that threshold after large frees. Whether an iteration finds its
// memory mapped or faults it in again (a page fault can cost as much as loading tens of KiB of
// graph text) then depends on what earlier benchmarks and iterations allocated and freed: the
// graph parsed before BM_Compile can make every compile of it fault its plan in, or none.
// Fixed thresholds keep the figures the compiler's; `page_faults` shows what is left.
const bool kFixedHeapThresholds = [] {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);  // the largest glibc allows
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    return true;
}();
#endif

/// A frame-like chain of N passes. Every pass renders its own target c<i> and samples the
/// previous one, so nothing is culled and every resource is read a bounded number of times.
/// Per group of four passes:
///   i%4 == 0: compute samples mip 0 of m<k-1> and writes mip 1 (mip generation);
///             every 16th pass also ReadWrites a storage buffer (accumulation);
///   i%4 == 1: writes depth d<k> (cleared by the load op) and reads c<i-3> in the vertex stage;
///   i%4 == 2: depth test against d<k> (read-only attachment), compute samples c<i-2>;
///   i%4 == 3: samples d<k> in the fragment shader (layout change) and writes mip 0 of m<k>.
/// That is 4 usages per pass, 4.06 on average with the buffers.
std::string syntheticGraph(int n) {
    std::string res, passes;
    auto addRes = [&](const std::string& name, const std::string& body) {
        res += (res.empty() ? "" : ",\n") + std::string("    \"") + name + "\": " + body;
    };
    auto c = [](int i) { return "c" + std::to_string(i); };
    for (int i = 0; i < n; ++i) {
        const int k = i / 4;
        std::string body = R"({ "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output/2")";
        if (i == n - 1) body += R"(, "external": true, "final": "ShaderRead")";
        else if (i % 16 == 0) body += R"(, "clear": { "color": [0, 0, 0, 0] })";
        addRes(c(i), body + " }");
        if (i % 4 == 0) {
            addRes("d" + std::to_string(k),
                   R"({ "type": "image2d", "format": "D32_SFLOAT", "extent": "output/2", "clear": { "depth": 0.0 } })");
            addRes("m" + std::to_string(k),
                   R"({ "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [128, 128], "mips": 2 })");
        }
        if (i % 16 == 0)
            addRes("b" + std::to_string(i / 16), R"({ "type": "buffer", "size": 65536, "external": true })");
    }
    for (int i = 0; i < n; ++i) {
        const int k = i / 4;
        std::string u;
        auto use = [&](const std::string& r, const char* access, const char* stage,
                       const std::string& extra = "") {
            u += (u.empty() ? "" : ", ") + std::string(R"({ "resource": ")") + r + R"(", "access": ")" +
                 access + R"(", "stage": ")" + stage + "\"" + extra + " }";
        };
        use(c(i), "Write", "ColorAttachment");
        if (i >= 1) use(c(i - 1), "Read", "Fragment");
        switch (i % 4) {
            case 0:
                if (k >= 1) {
                    const std::string m = "m" + std::to_string(k - 1);
                    use(m, "Read", "Compute", R"(, "mips": [0, 1])");
                    use(m, "Write", "Compute", R"(, "mips": [1, 1])");
                }
                if (i % 16 == 0) use("b" + std::to_string(i / 16), "ReadWrite", "Compute");
                break;
            case 1:
                use("d" + std::to_string(k), "Write", "DepthAttachment");
                if (i >= 3) use(c(i - 3), "Read", "Vertex");
                break;
            case 2:
                use("d" + std::to_string(k), "Read", "DepthAttachment");
                use(c(i - 2), "Read", "Compute");
                break;
            case 3:
                use("d" + std::to_string(k), "Read", "Fragment");
                use("m" + std::to_string(k), "Write", "Compute", R"(, "mips": [0, 1])");
                break;
        }
        passes += (passes.empty() ? "" : ",\n") + std::string(R"(    { "name": "p)") + std::to_string(i) +
                  R"(", "type": "Generic", "uses": [ )" + u + " ] }";
    }
    return "{\n  \"version\": 1,\n  \"name\": \"synthetic" + std::to_string(n) +
           "\",\n  \"features\": {},\n  \"resources\": {\n" + res + "\n  },\n  \"passes\": [\n" + passes +
           "\n  ]\n}\n";
}

/// Like syntheticGraph, plus one buffer (scene constants) that every pass reads: one long run
/// of reads of a single resource, as real frames have.
std::string sharedReadGraph(int n) {
    std::string g = syntheticGraph(n);
    const std::string scene = R"(    "scene": { "type": "buffer", "size": 256, "external": true },
)";
    g.insert(g.find("  \"resources\": {\n") + 16, scene);
    const std::string marker = R"("type": "Generic", "uses": [ )";
    const std::string read = R"({ "resource": "scene", "access": "Read", "stage": "Vertex", "as": "uniform" }, )";
    for (size_t at = g.find(marker); at != std::string::npos; at = g.find(marker, at + 1))
        g.insert(at + marker.size(), read);
    return g;
}

/// Like syntheticGraph, plus a copy of every fourth target right after it is sampled: pass i
/// with i%4 == 1 also reads c<i-2> in the transfer stage, which pass i-1 sampled. Those runs of
/// reads want two layouts (the layouts knob, docs/barriers.md rule 4): FewestBarriers keeps
/// them in GENERAL, Optimal transitions between the sample and the copy.
std::string mixedReadGraph(int n) {
    std::string g = syntheticGraph(n);
    size_t at = 0;
    for (int i = 5; i < n; i += 4) {
        const std::string marker = "\"p" + std::to_string(i) + R"(", "type": "Generic", "uses": [ )";
        at = g.find(marker, at) + marker.size();
        g.insert(at, R"({ "resource": "c)" + std::to_string(i - 2) + R"(", "access": "Read", "stage": "Transfer" }, )");
    }
    return g;
}

/// n passes each writing a transient image and one last pass reading them all: every transient
/// lives until the end, so each meets all those placed before it (memory planning's worst
/// shape, quadratic in n: docs/performance.md).
std::string wideReadGraph(int n) {
    std::string res, passes, reads;
    for (int i = 0; i < n; ++i) {
        const std::string t = "t" + std::to_string(i);
        res += "    \"" + t + R"(": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },)" + "\n";
        passes += R"(    { "name": "w)" + std::to_string(i) + R"(", "type": "Generic", "uses": { ")" + t +
                  R"(": "Write@ColorAttachment" } },)" + "\n";
        reads += "\"" + t + R"(": "Read@Fragment", )";
    }
    return "{\n  \"version\": 1,\n  \"name\": \"wide" + std::to_string(n) + "\",\n  \"resources\": {\n" + res +
           R"(    "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true, "final": "ShaderRead" })" +
           "\n  },\n  \"passes\": [\n" + passes + R"(    { "name": "last", "type": "Generic", "uses": { )" + reads +
           R"("out": "Write@ColorAttachment" } })" + "\n  ]\n}\n";
}

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

enum class Shape { Synthetic, SharedRead, MixedReads, WideRead };

struct Case {
    std::string text;
    GraphDesc graph;
    double usages = 0;
};

/// Graphs are generated and parsed once per size and shape, outside the timed loops.
const Case& graphFor(int n, Shape shape = Shape::Synthetic) {
    static std::map<std::pair<int, Shape>, Case> cache;
    auto [it, fresh] = cache.try_emplace({n, shape});
    if (fresh) {
        it->second.text = shape == Shape::SharedRead   ? sharedReadGraph(n)
                          : shape == Shape::MixedReads ? mixedReadGraph(n)
                          : shape == Shape::WideRead   ? wideReadGraph(n)
                                                       : syntheticGraph(n);
        it->second.graph = parseGraph(it->second.text, "synthetic.json", registry());
        for (const auto& p : it->second.graph.passes) it->second.usages += static_cast<double>(p.uses.size());
    }
    return it->second;
}

/// Minor page faults so far: memory the process touches for the first time since the
/// allocator last returned it to the system.
double pageFaults() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_minflt);
}

benchmark::Counter perIteration(double total) { return {total, benchmark::Counter::kAvgIterations}; }

void setCounters(benchmark::State& state, const Case& c) {
    state.counters["passes"] = static_cast<double>(c.graph.passes.size());
    state.counters["usages"] = c.usages;
    state.counters["time_per_usage"] =
        benchmark::Counter(c.usages, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void compileBench(benchmark::State& state, Shape shape, const CompileOptions& options = {}) {
    const Case& c = graphFor(static_cast<int>(state.range(0)), shape);
    {
        const Plan plan = compile(c.graph, options);
        if (!plan.culled().empty() || plan.passes().size() < c.graph.passes.size()) {
            state.SkipWithError("the synthetic graph lost passes to culling");
            return;
        }
        size_t barriers = plan.finalBarriers().size();
        for (const auto& p : plan.passes()) barriers += p.barriers.size();
        state.counters["barriers"] = static_cast<double>(barriers);
    }
    for (auto _ : state) {
        Plan plan = compile(c.graph, options);
        benchmark::DoNotOptimize(plan);
    }
    setCounters(state, c);
}

void BM_Compile(benchmark::State& state) { compileBench(state, Shape::Synthetic); }

// The memory planning knob (docs/memory.md, "Placement"), side by side with BM_Compile's
// default (best fit by size): the online first-use allocator, and no sharing at all.
CompileOptions placedBy(MemoryStrategy s) {
    CompileOptions o;
    o.placement = s;
    return o;
}
void BM_CompileFirstUse(benchmark::State& state) { compileBench(state, Shape::Synthetic, placedBy(MemoryStrategy::FirstUseOrder)); }
void BM_CompileUnaliased(benchmark::State& state) { compileBench(state, Shape::Synthetic, placedBy(MemoryStrategy::Unaliased)); }
// Heaps per frame in flight (CompileOptions::shareTransientsAcrossFrames off): no placement
// names what the previous frame left in its bytes.
void BM_CompileHeapsPerFrame(benchmark::State& state) {
    CompileOptions o;
    o.shareTransientsAcrossFrames = false;
    compileBench(state, Shape::Synthetic, o);
}
// The cheapest memory plan: no aliasing and heaps per frame in flight, so no transient takes
// over another's bytes. What it costs beyond a compile without memory planning is what
// gathering requirements and writing placements cost, with no search and no aliasing barrier.
void BM_CompileNoSharing(benchmark::State& state) {
    CompileOptions o = placedBy(MemoryStrategy::Unaliased);
    o.shareTransientsAcrossFrames = false;
    compileBench(state, Shape::Synthetic, o);
}

// The layouts knob (docs/barriers.md, rule 4) on reads that want different layouts: the
// second argument is 0 for FewestBarriers, 1 for Optimal; `barriers` shows what each costs the
// frame, the time what it costs the compiler.
void BM_CompileMixedReads(benchmark::State& state) {
    CompileOptions o;
    o.layouts = state.range(1) ? LayoutPolicy::Optimal : LayoutPolicy::FewestBarriers;
    compileBench(state, Shape::MixedReads, o);
}

// The floor under compile(): copying the finished plan allocates and writes what compile()
// must produce (per pass its name and type, the plan's one usage array and one barrier array,
// each pass's spans rebased onto the copy), with none of the work.
void BM_CopyPlan(benchmark::State& state) {
    const Case& c = graphFor(static_cast<int>(state.range(0)));
    const Plan plan = compile(c.graph);
    for (auto _ : state) {
        Plan copy = plan;
        benchmark::DoNotOptimize(copy);
    }
    setCounters(state, c);
}
void BM_CompileSharedRead(benchmark::State& state) { compileBench(state, Shape::SharedRead); }
void BM_CompileWideRead(benchmark::State& state) { compileBench(state, Shape::WideRead); }

// `bytes_per_second`: MB/s of graph text; `page_faults`: per load.
void BM_Parse(benchmark::State& state) {
    const Case& c = graphFor(static_cast<int>(state.range(0)));
    const double faultsBefore = pageFaults();
    for (auto _ : state) {
        GraphDesc g = parseGraph(c.text, "synthetic.json", registry());
        benchmark::DoNotOptimize(g);
    }
    state.counters["page_faults"] = perIteration(pageFaults() - faultsBefore);
    setCounters(state, c);
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(c.text.size()));
}

// The floor under parseGraph()'s reading: nlohmann's SAX parser over the same text, its events
// dropped (the loader reads through the same parser, and builds its document from the events).
struct DroppedEvents : nlohmann::json_sax<nlohmann::json> {
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return true; }
    bool key(string_t&) override { return true; }
    bool end_object() override { return true; }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

void BM_JsonSax(benchmark::State& state) {
    const Case& c = graphFor(static_cast<int>(state.range(0)));
    for (auto _ : state) {
        DroppedEvents events;
        const bool ok = nlohmann::json::sax_parse(c.text, &events);
        benchmark::DoNotOptimize(ok);
    }
    setCounters(state, c);
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(c.text.size()));
}

// The floor under parseGraph(), as BM_CopyPlan is under compile(): copying the loaded graph
// allocates and writes what loading must produce (every pass, usage array and resource).
void BM_CopyGraph(benchmark::State& state) {
    const Case& c = graphFor(static_cast<int>(state.range(0)));
    const double faultsBefore = pageFaults();
    for (auto _ : state) {
        GraphDesc copy = c.graph;
        benchmark::DoNotOptimize(copy);
    }
    state.counters["page_faults"] = perIteration(pageFaults() - faultsBefore);
    setCounters(state, c);
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(c.text.size()));
}

BENCHMARK(BM_Compile)->RangeMultiplier(10)->Range(10, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileFirstUse)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileUnaliased)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileHeapsPerFrame)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileNoSharing)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileMixedReads)->ArgsProduct({{1000, 10000}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CopyPlan)->RangeMultiplier(10)->Range(10, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Parse)->RangeMultiplier(10)->Range(10, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_JsonSax)->RangeMultiplier(10)->Range(10, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CopyGraph)->RangeMultiplier(10)->Range(10, 100000)->Unit(benchmark::kMicrosecond);
// Up to 10k passes: one read run as long as the frame, linear like BM_Compile (docs/performance.md).
BENCHMARK(BM_CompileSharedRead)->RangeMultiplier(10)->Range(10, 10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CompileWideRead)->Arg(1000)->Arg(4000)->Arg(16000)->Unit(benchmark::kMillisecond);

}  // namespace
