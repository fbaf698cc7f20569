// Every shipped graph (graphs/*.json) under every feature combination: the cases that the
// shipped-graph suites run, each named for gtest.
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/feature_combinations.hpp>
#include <skygraph/pass_registry.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace skygraph::test {

struct GraphCase {
    std::string file;
    FeatureValues features;
    std::string label;  ///< e.g. raster_geometryOn_skyboxOff, a valid gtest name
};

inline void PrintTo(const GraphCase& c, std::ostream* os) { *os << c.label; }

#ifdef SKYGRAPH_PAIRWISE_RENDER_CASES
inline constexpr bool kPairwiseRenderCases = true;
#else
inline constexpr bool kPairwiseRenderCases = false;
#endif

/// In file order, then by feature mask; a file that does not load is one case, labelled
/// "<stem>_unloadable", so that the suites fail on it. `pairwise`: each graph under a pairwise
/// covering set of its feature combinations (pairwiseFeatureCombinations) instead of all:
/// what the sanitizer build renders (SKYGRAPH_PAIRWISE_RENDER_CASES, docs/reliability.md).
inline std::vector<GraphCase> shippedCases(bool pairwise = kPairwiseRenderCases) {
    std::vector<GraphCase> cases;
    const std::filesystem::path dir = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs";
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    const auto registry = PassRegistry::withBuiltins();
    for (const auto& f : files) {
        GraphDesc g;
        try {
            g = loadGraphFile(f, registry);
        } catch (const std::exception&) {
            cases.push_back({f.string(), {}, f.stem().string() + "_unloadable"});
            continue;
        }
        const size_t n = g.features.size();
        std::vector<FeatureValues> combinations;
        if (pairwise) {
            combinations = pairwiseFeatureCombinations(g);
        } else {
            for (uint64_t mask = 0; mask < (uint64_t(1) << n); ++mask) {
                FeatureValues& values = combinations.emplace_back();
                for (size_t i = 0; i < n; ++i) values[g.features[i].name] = (mask >> i) & 1u;
            }
        }
        for (const FeatureValues& values : combinations) {
            GraphCase c{f.string(), values, f.stem().string()};
            for (const FeatureDecl& feature : g.features)
                c.label += "_" + feature.name + (values.at(feature.name) ? "On" : "Off");
            std::replace_if(c.label.begin(), c.label.end(),
                            [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)) && ch != '_'; },
                            '_');
            cases.push_back(std::move(c));
        }
    }
    return cases;
}

}  // namespace skygraph::test
