// The path tracer's geometry of a loaded glTF model (passes/path_trace/trace_geometry.cpp):
// its BVH (binned SAH) and the arrays the shader reads, built on the CPU whenever the scene's
// set of models changes. Counters: BVH nodes and depth, and the bytes the shader reads.
#include "path_trace/trace_geometry.hpp"

#include <skygraph/triangle_mesh.hpp>

#include <benchmark/benchmark.h>

namespace {

const std::filesystem::path kModels = "/usr/share/assimp/models/glTF2";

void traceModel(benchmark::State& state, const std::filesystem::path& file) {
    skygraph::Diagnostics diagnostics;
    auto mesh = skygraph::loadGltf(kModels / file, {}, diagnostics);
    if (!mesh) {
        state.SkipWithError("the model did not load");
        return;
    }
    const auto shared = std::make_shared<const skygraph::TriangleMesh>(std::move(*mesh));
    skygraph::passes::TraceGeometry g;
    for (auto _ : state) {
        g = skygraph::passes::buildTraceGeometry({shared});
        benchmark::DoNotOptimize(g);
    }
    state.counters["nodes"] = double(g.nodes.size());
    state.counters["depth"] = double(g.bvhDepth);
    state.counters["geometry_MiB"] =
        double(g.nodes.size() * sizeof(g.nodes[0]) + g.triangles.size() * 4 + g.vertices.size() * sizeof(g.vertices[0]) +
               g.materials.size() * sizeof(g.materials[0]) + g.texels.size() * 4) /
        (1024.0 * 1024.0);
}

void BM_TraceGeometry2CylinderEngine(benchmark::State& state) {
    traceModel(state, "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
}
void BM_TraceGeometryClearCoatTest(benchmark::State& state) { traceModel(state, "ClearCoat-glTF/ClearCoatTest.gltf"); }

BENCHMARK(BM_TraceGeometry2CylinderEngine)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TraceGeometryClearCoatTest)->Unit(benchmark::kMillisecond);

}  // namespace
