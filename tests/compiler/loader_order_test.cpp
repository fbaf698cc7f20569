// The loader loads `features` and `resources` as the reader reaches them, and then each pass
// as it is read, so that a large file's passes never sit in memory all at once. A file whose
// root keys come in another order, or repeat, still loads as the same graph, with the same
// diagnostics in the same order.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace skygraph {
namespace {

using Json = nlohmann::ordered_json;

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

/// Passes that depend on the features (their `if`) and on the resources (their uses); with
/// `broken`, a problem in each part of the file.
Json partsGraph(bool broken) {
    Json g = Json::parse(R"({
      "version": 1,
      "name": "parts",
      "features": { "geo": true, "sky": false },
      "resources": {
        "color": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" },
        "out":   { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
                   "external": true, "final": "Present" }
      },
      "passes": [
        { "name": "draw", "type": "Generic", "if": "geo", "uses": { "color": "Write@ColorAttachment" } },
        { "name": "sky", "type": "Generic", "if": "sky", "uses": { "color": "ReadWrite@ColorAttachment" } },
        { "name": "present", "type": "Generic",
          "uses": { "color": "Read@Fragment", "out": "Write@ColorAttachment" } }
      ]
    })");
    if (broken) {
        g["features"]["bad feature!"] = 1;
        g["resources"]["volume"] = Json{{"type", "image3d"}};
        g["passes"].push_back(
            Json{{"name", "x"}, {"type", "Generic"}, {"if", "fog"}, {"uses", {{"ghost", "Read@Fragment"}}}});
        g["passes"].push_back(Json{{"name", "draw"}, {"type", "Generic"}, {"uses", Json::array()}, {"params", {1}}});
        g["extra"] = true;
    }
    return g;
}

/// What loading and compiling `text` gives: the plan, or the diagnostics.
std::string outcome(const std::string& text) {
    try {
        return planToText(compile(parseGraph(text, "t.json", registry())));
    } catch (const GraphError& e) {
        return e.what();
    }
}

TEST(LoaderOrder, TheRootKeysInAnyOrderLoadTheSameGraph) {
    for (const bool broken : {false, true}) {
        const Json g = partsGraph(broken);
        const std::string expected = outcome(g.dump(1));
        EXPECT_EQ(expected.find("t.json:") != std::string::npos, broken) << expected;
        std::vector<std::string> keys;
        for (const auto& [key, value] : g.items()) keys.push_back(key);
        std::sort(keys.begin(), keys.end());
        size_t orders = 0;
        do {
            Json reordered = Json::object();
            for (const auto& k : keys) reordered[k] = g[k];
            const std::string got = outcome(reordered.dump(1));
            EXPECT_EQ(got, expected) << "keys in the order of " << Json(keys).dump();
            ++orders;
        } while (std::next_permutation(keys.begin(), keys.end()));
        EXPECT_EQ(orders, broken ? 720u : 120u);
    }
}

// Whatever the file's order, diagnostics follow the format's: the root's own keys, then
// features, resources, passes.
TEST(LoaderOrder, DiagnosticsComeInTheFormatsOrder) {
    const Json g = partsGraph(true);
    Json reversed = Json::object();  // passes first, features last
    for (const char* key : {"passes", "resources", "extra", "features", "name", "version"}) reversed[key] = g[key];
    std::vector<std::string> paths;
    try {
        (void)parseGraph(reversed.dump(), "t.json", registry());
    } catch (const GraphError& e) {
        for (const auto& d : e.diagnostics().items()) paths.push_back(d.jsonPath);
    }
    EXPECT_EQ(paths, (std::vector<std::string>{"extra", R"(features["bad feature!"])", R"(features["bad feature!"])",
                                               "resources.volume.type", "passes[3].if", "passes[3].uses.ghost",
                                               "passes[4].name", "passes[4].params", "passes[4].uses"}))
        << Json(paths).dump();
}

// JSON keeps the last of a repeated key: broken first copies of `resources`, `passes` and
// `features` go unread (were they read, they would add diagnostics of their own, and the
// passes would be loaded against the wrong resources).
TEST(LoaderOrder, ARepeatedPartIsReadFromItsLastCopy) {
    const std::string good = partsGraph(false).dump();
    const std::string text = R"({"resources": {"x": {}}, "passes": [7], "features": 3, )" + good.substr(1);
    try {
        (void)parseGraph(text, "t.json", registry());
        ADD_FAILURE() << "a repeated key loaded without a diagnostic";
    } catch (const GraphError& e) {
        std::vector<std::string> messages;
        for (const auto& d : e.diagnostics().items()) messages.push_back(d.jsonPath + ": " + d.message);
        EXPECT_EQ(messages, (std::vector<std::string>{
                                "features: duplicate key 'features'; JSON keeps only the last one",
                                "resources: duplicate key 'resources'; JSON keeps only the last one",
                                "passes: duplicate key 'passes'; JSON keeps only the last one"}));
    }
    // The same file without its first copies loads.
    EXPECT_EQ(outcome(good).find("t.json:"), std::string::npos);
}

}  // namespace
}  // namespace skygraph
