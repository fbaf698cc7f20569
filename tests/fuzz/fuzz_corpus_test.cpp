// Replays the fuzz corpora (tests/fuzz/corpus: seeds and every input that once broke the
// compiler, with the shipped graphs; tests/fuzz/gltf_corpus with Debian's glTF test models)
// through the fuzz targets in every build, so a fixed bug
// stays fixed without libFuzzer. A failing input aborts the process, naming nothing; the
// test prints each file before running it so the log names the culprit.
#include "graph_fuzz_target.hpp"
#include "gltf_fuzz_target.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/feature_combinations.hpp>
#include <skygraph/pass_registry.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace skygraph::fuzz {
namespace {

std::vector<std::filesystem::path> inputs() {
    const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
    std::vector<std::filesystem::path> files;
    for (const auto* dir : {"tests/fuzz/corpus", "graphs"})
        for (const auto& e : std::filesystem::directory_iterator(root / dir))
            if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

/// Runs each of `files` through `target`, naming it first (a failing input aborts).
void replay(const std::vector<std::filesystem::path>& files, void (*target)(std::string_view)) {
    for (const auto& f : files) {
        std::ifstream in(f, std::ios::binary);
        std::stringstream ss;
        ss << in.rdbuf();
        std::fprintf(stderr, "replaying %s\n", f.c_str());
        const auto start = std::chrono::steady_clock::now();
        target(ss.str());
        const auto seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Each input takes milliseconds; tools/fuzz.sh calls 2 s a hang. The margin is for
        // sanitizer builds on a loaded 2-core CI machine.
        EXPECT_LT(seconds, 5.0) << f << " took " << seconds << " s";
    }
}

TEST(FuzzCorpus, EveryInputEndsInAPlanOrAGraphError) {
    const auto files = inputs();
    ASSERT_GT(files.size(), 20u) << "the corpus is missing";
    replay(files, &runOneInput);
}

// The valid seeds are what the fuzzer mutates into the sweeps past validation: a rule that
// refuses them (a compile error any GraphError would let the test above accept) leaves the
// scheduler, synchronizer and printers without a seed. They compile in every combination.
TEST(FuzzCorpus, TheValidSeedsCompileInEveryFeatureCombination) {
    const std::filesystem::path corpus = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "tests/fuzz/corpus";
    for (const char* name : {"seed_valid.json", "seed_minimal.json"}) {
        const GraphDesc graph = loadGraphFile(corpus / name, PassRegistry::withBuiltins());
        for (const FeatureValues& features : allFeatureCombinations(graph)) {
            CompileOptions o;
            o.features = features;
            EXPECT_NO_THROW((void)compile(graph, o)) << name;
        }
    }
}

/// tests/fuzz/gltf_corpus, and every .gltf and .glb of Debian's assimp-testmodels.
std::vector<std::filesystem::path> gltfInputs() {
    std::vector<std::filesystem::path> files;
    for (const char* dir : {SKYGRAPH_SOURCE_DIR "/tests/fuzz/gltf_corpus", "/usr/share/assimp/models/glTF2"})
        for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
            if (e.is_regular_file() && (e.path().extension() == ".gltf" || e.path().extension() == ".glb" ||
                                        e.path().parent_path().filename() == "gltf_corpus"))
                files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

TEST(FuzzCorpus, EveryGltfInputEndsInAMeshOrDiagnostics) {
    const auto files = gltfInputs();
    ASSERT_GE(files.size(), 50u) << "the glTF corpus or assimp-testmodels is missing";
    replay(files, &runOneGltfInput);
}

}  // namespace
}  // namespace skygraph::fuzz
