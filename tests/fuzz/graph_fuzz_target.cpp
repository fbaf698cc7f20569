// The fuzz target over the loader and the compiler: any bytes must end in a plan or a
// GraphError. Anything else escaping (another exception, a crash, a sanitizer report, a
// hang) is a bug. Built two ways from this one file: with libFuzzer (tools/fuzz.sh) and,
// without it, as the corpus replay test that every build runs (fuzz_corpus_test.cpp).
#include "graph_fuzz_target.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string_view>

namespace skygraph::fuzz {
namespace {

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

/// Compiles `graph` with one set of options and prints the plan every way the CLI can,
/// since the printers walk every barrier and usage the compiler produced.
void compileAndPrint(const GraphDesc& graph, const CompileOptions& options) {
    try {
        const Plan plan = compile(graph, options);
        (void)planToText(plan);
        (void)planToJson(plan).dump();
        (void)planToDot(plan, graph);
    } catch (const GraphError& e) {
        // The documented error: it must say what is wrong.
        if (e.diagnostics().empty()) {
            std::fprintf(stderr, "GraphError without diagnostics\n");
            std::abort();
        }
    }
}

}  // namespace

void runOneInput(std::string_view text) {
    try {
        GraphDesc graph;
        try {
            graph = parseGraph(text, "<fuzz>", registry());
        } catch (const GraphError& e) {
            if (e.diagnostics().empty()) {
                std::fprintf(stderr, "GraphError without diagnostics\n");
                std::abort();
            }
            return;
        }
        CompileOptions options;
        compileAndPrint(graph, options);
        // Every feature switched the other way, one at a time (bounded: a file may declare
        // thousands), plus no culling and a tiny output that "output/N" extents clamp.
        size_t toggled = 0;
        for (const auto& f : graph.features) {
            if (++toggled > 8) break;
            CompileOptions flipped;
            flipped.features[f.name] = !f.defaultValue;
            compileAndPrint(graph, flipped);
        }
        CompileOptions other;
        other.cull = false;
        other.outputWidth = 1;
        other.outputHeight = 3;
        other.presentReplacement = ExternalState::TransferSrc;
        compileAndPrint(graph, other);
        if (!graph.resources.empty()) {
            CompileOptions exporting;
            exporting.exports[graph.resources.front().name] = ExternalState::TransferSrc;
            exporting.exports[graph.resources.back().name] = ExternalState::ShaderRead;
            compileAndPrint(graph, exporting);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "exception escaped the API: %s\n", e.what());
        std::abort();
    }
}

}  // namespace skygraph::fuzz
