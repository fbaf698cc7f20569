// Loading glTF scene objects (loadGltf: tinygltf's parse and image decoding, the checks, the
// flattening to world space), on Debian's assimp-testmodels. Counters: what the loaded mesh
// holds in memory (vertices and indices as the forward pass uploads them).
#include <skygraph/triangle_mesh.hpp>

#include <benchmark/benchmark.h>

#include <stdexcept>

namespace {

const std::filesystem::path kModels = "/usr/share/assimp/models/glTF2";

void loadModel(benchmark::State& state, const std::filesystem::path& file) {
    size_t vertices = 0, indices = 0, primitives = 0;
    for (auto _ : state) {
        skygraph::Diagnostics diagnostics;
        auto mesh = skygraph::loadGltf(kModels / file, {}, diagnostics);
        if (!mesh) {
            state.SkipWithError("the model did not load");
            return;
        }
        vertices = mesh->vertices.size();
        indices = mesh->indices.size();
        primitives = mesh->primitives.size();
        benchmark::DoNotOptimize(mesh);
    }
    state.counters["vertices"] = double(vertices);
    state.counters["triangles"] = double(indices / 3);
    state.counters["primitives"] = double(primitives);
    state.counters["mesh_MiB"] =
        double(vertices * sizeof(skygraph::MeshVertex) + indices * sizeof(uint32_t)) / (1024.0 * 1024.0);
    state.counters["file_MiB"] = double(std::filesystem::file_size(kModels / file)) / (1024.0 * 1024.0);
}

void BM_Load2CylinderEngine(benchmark::State& state) {
    loadModel(state, "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
}
void BM_LoadClearCoatTest(benchmark::State& state) { loadModel(state, "ClearCoat-glTF/ClearCoatTest.gltf"); }
void BM_LoadBoxTexturedGlb(benchmark::State& state) { loadModel(state, "BoxTextured-glTF-Binary/BoxTextured.glb"); }

BENCHMARK(BM_Load2CylinderEngine)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadClearCoatTest)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadBoxTexturedGlb)->Unit(benchmark::kMillisecond);

}  // namespace
