// Every shipped graph (graphs/*.json) under every feature combination: the cases that the
// shipped-graph suites run, each named for gtest.
#pragma once

#include <skygraph/compiler.hpp>
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

/// In file order, then by feature mask; a file that does not load is one case, labelled
/// "<stem>_unloadable", so that the suites fail on it.
inline std::vector<GraphCase> shippedCases() {
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
        for (uint64_t mask = 0; mask < (uint64_t(1) << n); ++mask) {
            GraphCase c{f.string(), {}, f.stem().string()};
            for (size_t i = 0; i < n; ++i) {
                const bool on = (mask >> i) & 1u;
                c.features[g.features[i].name] = on;
                c.label += "_" + g.features[i].name + (on ? "On" : "Off");
            }
            std::replace_if(c.label.begin(), c.label.end(),
                            [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)) && ch != '_'; },
                            '_');
            cases.push_back(std::move(c));
        }
    }
    return cases;
}

}  // namespace skygraph::test
