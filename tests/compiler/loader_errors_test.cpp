// Error tests for the loader and the compiler's feature-dependent checks (docs/graph-format.md,
// "Errors": every error names the file, the JSON path and, where one is involved, the pass and
// the resource; a file with several errors reports all of them).
#include "json_positions.hpp"

#include <skygraph/compiler.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kFile = "test.json";

/// A valid graph: forward (if geo) writes depth and hdr_color; tonemap reads hdr_color and
/// writes the exported swapchain. Tests break one thing at a time.
Json baseGraph() {
    return Json::parse(R"({
      "version": 1,
      "name": "t",
      "features": { "geo": true, "sky": true },
      "resources": {
        "depth":     { "type": "image2d", "format": "D32_SFLOAT", "extent": "output",
                       "clear": { "depth": 0.0 } },
        "hdr_color": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
                       "external": true, "final": "Present" },
        "buf":       { "type": "buffer", "size": 1024, "external": true },
        "cube":      { "type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64],
                       "mips": "full", "external": true },
        "mipped":    { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64],
                       "mips": 3, "external": true }
      },
      "passes": [
        { "name": "forward", "type": "ForwardPass", "if": "geo",
          "uses": { "depth": "Write@DepthAttachment", "hdr_color": "Write@ColorAttachment" } },
        { "name": "tonemap", "type": "TonemappingPass",
          "uses": { "hdr_color": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
          "params": { "operator": "aces_narkowicz" } }
      ]
    })");
}

/// Appends a Generic pass named `name` with the given uses (object or array form).
Json withGeneric(Json g, const std::string& name, Json uses) {
    g["passes"].push_back(Json{{"name", name}, {"type", "Generic"}, {"uses", std::move(uses)},
                               {"never_cull", true}});
    return g;
}

const PassRegistry& registry() {
    static const PassRegistry r = PassRegistry::withBuiltins();
    return r;
}

/// The diagnostics that loading `text` produces; fails the test if it loads.
std::vector<Diagnostic> textErrors(std::string_view text) {
    try {
        (void)parseGraph(text, kFile, registry());
    } catch (const GraphError& e) {
        EXPECT_FALSE(e.diagnostics().empty());
        EXPECT_EQ(std::string(e.what()), e.diagnostics().format());
        return e.diagnostics().items();
    }
    ADD_FAILURE() << "expected a GraphError for:\n" << text;
    return {};
}
std::vector<Diagnostic> loadErrors(const Json& g) { return textErrors(g.dump(2)); }

std::vector<Diagnostic> compileErrors(const Json& g, const CompileOptions& options) {
    const GraphDesc graph = parseGraph(g.dump(2), kFile, registry());
    try {
        (void)compile(graph, options);
    } catch (const GraphError& e) {
        return e.diagnostics().items();
    }
    ADD_FAILURE() << "expected compile() to throw GraphError";
    return {};
}

std::string listAll(const std::vector<Diagnostic>& ds) {
    std::string out;
    for (const auto& d : ds)
        out += "  {path='" + d.jsonPath + "' pass='" + d.pass + "' resource='" + d.resource +
               "'} " + d.format() + "\n";
    return out;
}

/// Whether some diagnostic has exactly this file, path, pass and resource, and a message
/// containing every one of `words`.
::testing::AssertionResult hasDiag(const std::vector<Diagnostic>& ds, const std::string& path,
                                   const std::string& pass, const std::string& resource,
                                   std::initializer_list<std::string_view> words) {
    for (const auto& d : ds) {
        if (d.file != kFile || d.jsonPath != path || d.pass != pass || d.resource != resource)
            continue;
        bool all = true;
        for (auto w : words) all = all && d.message.find(w) != std::string::npos;
        if (all) return ::testing::AssertionSuccess();
    }
    std::string wanted;
    for (auto w : words) wanted += " '" + std::string(w) + "'";
    return ::testing::AssertionFailure()
           << "no diagnostic {path='" << path << "' pass='" << pass << "' resource='" << resource
           << "'} with" << wanted << "; got " << ds.size() << ":\n"
           << listAll(ds);
}

void expectLoads(const Json& g) {
    try {
        (void)parseGraph(g.dump(2), kFile, registry());
    } catch (const GraphError& e) {
        ADD_FAILURE() << "expected the graph to load:\n" << e.what();
    }
}

// ---------------------------------------------------------------------------------------

TEST(LoaderErrors, BaseGraphIsValid) {
    expectLoads(baseGraph());
    const GraphDesc g = parseGraph(baseGraph().dump(), kFile, registry());
    EXPECT_EQ(g.file, kFile);
    EXPECT_EQ(g.passes.size(), 2u);
    EXPECT_NO_THROW((void)compile(g));
}

TEST(LoaderErrors, MalformedJsonGivesLineAndColumn) {
    const std::string text =
        "{\n"
        "  \"version\": 1,\n"
        "  \"name\": \"t\",\n"
        "  \"resources\": {\n"
        "    \"depth\": { \"type\": \"image2d\", \"format\": \"D32_SFLOAT\" \"extent\": \"output\" }\n"
        "  }\n"
        "}\n";
    const auto ds = textErrors(text);
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    const Diagnostic& d = ds[0];
    EXPECT_EQ(d.file, kFile);
    EXPECT_EQ(d.line, 5);
    // The string literal where a ',' or '}' should be starts on column 58.
    EXPECT_EQ(d.column, 58) << d.format();
    EXPECT_EQ(d.jsonPath, "resources.depth");
    EXPECT_NE(d.message.find("malformed JSON"), std::string::npos) << d.message;
    EXPECT_EQ(d.format().rfind("test.json:5:58: resources.depth: malformed JSON", 0), 0u) << d.format();
}

TEST(LoaderErrors, MalformedJsonStrayComma) {
    const auto ds = textErrors("{\n  \"version\": 1,,\n  \"name\": \"t\"\n}");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].line, 2);
    EXPECT_EQ(ds[0].column, 16);  // the second ','
}

TEST(LoaderErrors, MalformedJsonTruncatedFile) {
    const auto ds = textErrors("{\n  \"version\": 1,\n  \"passes\": [\n");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].line, 4);
    EXPECT_EQ(ds[0].column, 1);
    EXPECT_EQ(ds[0].jsonPath, "passes");
    EXPECT_NE(ds[0].message.find("end of input"), std::string::npos) << ds[0].message;
}

TEST(LoaderErrors, MalformedJsonBadLiteral) {
    const auto ds = textErrors("{ \"version\": 1, \"name\": tru }");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].line, 1);
    EXPECT_EQ(ds[0].column, 25);  // start of "tru"
}

// nlohmann quotes what it read with a control character as <U+000A>; the message writes it
// as JSON does, as every message here writes control characters.
TEST(LoaderErrors, ControlCharactersInAQuotedExcerptAreWrittenAsJsonWritesThem) {
    const auto ds = textErrors("{ \"version\": 1,\n \"name\": \"t\n\" }");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].message.find("<U+"), std::string::npos) << ds[0].message;
    EXPECT_NE(ds[0].message.find("\\u000A"), std::string::npos) << ds[0].message;
}

// A NUL byte is no end of the text: what follows it is not skipped, and a file of NULs is not
// empty. Each is named where it is.
TEST(LoaderErrors, ANulByteIsAnErrorWhereItIs) {
    const std::string graph = baseGraph().dump();
    auto ds = textErrors(graph + "\n" + std::string(1, '\0') + " garbage {{{");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].line, 2);
    EXPECT_EQ(ds[0].column, 1);
    EXPECT_NE(ds[0].message.find("a NUL byte (U+0000)"), std::string::npos) << ds[0].message;
    ds = textErrors(std::string(10, '\0'));
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].column, 1);
    EXPECT_NE(ds[0].message.find("a NUL byte (U+0000)"), std::string::npos) << ds[0].message;
    ds = textErrors("{ \"version\": 1," + std::string(1, '\0') + " \"name\": \"t\" }");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_EQ(ds[0].column, 16);
    EXPECT_NE(ds[0].message.find("a NUL byte (U+0000)"), std::string::npos) << ds[0].message;
}

TEST(LoaderErrors, NumberOverflowIsAnErrorNotACrash) {
    const auto ds = textErrors(R"({ "version": 1e999, "name": "t", "resources": {}, "passes": [] })");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_NE(ds[0].message.find("1e999"), std::string::npos) << ds[0].message;
}

TEST(LoaderErrors, UnknownTopLevelKey) {
    Json g = baseGraph();
    g["passess"] = Json::array();
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passess", "", "", {"unknown key 'passess'", "passes", "resources"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

TEST(LoaderErrors, BadLayoutsSettingNamesTheAllowedValues) {
    for (const Json& bad : {Json("fast"), Json("Optimal"), Json(true)}) {
        Json g = baseGraph();
        g["layouts"] = bad;
        const auto ds = loadErrors(g);
        EXPECT_TRUE(hasDiag(ds, "layouts", "", "", {"expected \"fewest-barriers\" or \"optimal\"", "got " + bad.dump()}));
        EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    }
    for (const char* good : {"optimal", "fewest-barriers"}) {
        Json g = baseGraph();
        g["layouts"] = good;
        expectLoads(g);
    }
}

TEST(LoaderErrors, UnknownResourceKey) {
    Json g = baseGraph();
    g["resources"]["hdr_color"]["fromat"] = "R8_UNORM";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color.fromat", "", "hdr_color", {"unknown key 'fromat'", "format"}));
}

TEST(LoaderErrors, UnknownClearKey) {
    Json g = baseGraph();
    g["resources"]["depth"]["clear"]["dpeth"] = 1.0;
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.depth.clear.dpeth", "", "depth", {"unknown key 'dpeth'", "depth"}));
}

TEST(LoaderErrors, ClearWithColorAndDepthTogether) {
    Json g = baseGraph();
    g["resources"]["hdr_color"]["clear"] = Json{{"color", {0, 0, 0, 1}}, {"depth", 0.5}};
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.hdr_color.clear", "", "hdr_color", {"not both"}));
    g = baseGraph();
    g["resources"]["depth"]["clear"] = Json{{"color", {0, 0, 0, 1}}, {"stencil", 1}};
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.depth.clear", "", "depth", {"not both"}));
}

TEST(LoaderErrors, StencilClearNeedsAStencilAspect) {
    Json g = baseGraph();
    g["resources"]["depth"]["clear"] = Json{{"depth", 0.0}, {"stencil", 3}};
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.depth.clear.stencil", "", "depth",
                        {"format D32_SFLOAT has no stencil aspect"}));
    g["resources"]["depth"]["format"] = "D24_UNORM_S8_UINT";
    expectLoads(g);
}

// The advice for a clear names what the format's aspects take: following it loads.
TEST(LoaderErrors, ClearAdviceFitsTheFormat) {
    Json g = baseGraph();
    g["resources"]["depth"]["format"] = "S8_UINT";
    g["resources"]["depth"]["clear"] = Json::object();
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.depth.clear", "", "depth",
                        {"expected {\"stencil\": s} for the format S8_UINT"}))
        << listAll(loadErrors(g));
    g["resources"]["depth"]["clear"] = Json{{"color", {0, 0, 0, 0}}};
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.depth.clear.color", "", "depth",
                        {"the depth/stencil format S8_UINT needs {\"stencil\": s}"}));
    g["resources"]["depth"]["clear"] = Json{{"stencil", 0}};
    expectLoads(g);
    g = baseGraph();
    g["resources"]["depth"]["clear"] = Json{{"depth", 1.5}};
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.depth.clear.depth", "", "depth", {"in [0, 1], got 1.5"}));
}

TEST(LoaderErrors, DescriptionsAreStrings) {
    Json g = baseGraph();
    g["description"] = 5;
    g["$schema"] = Json::array();
    g["resources"]["depth"]["description"] = true;
    g["passes"][1]["description"] = Json{{"text", "x"}};
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "description", "", "", {"expected a string, got 5"}));
    EXPECT_TRUE(hasDiag(ds, "$schema", "", "", {"expected a string, got []"}));
    EXPECT_TRUE(hasDiag(ds, "resources.depth.description", "", "depth", {"expected a string, got true"}));
    EXPECT_TRUE(hasDiag(ds, "passes[1].description", "tonemap", "", {"expected a string"}));
    g = baseGraph();
    g["description"] = "a frame";
    g["resources"]["depth"]["description"] = "";
    g["passes"][1]["description"] = "tonemaps";
    expectLoads(g);
}

TEST(LoaderErrors, UnknownPassKey) {
    Json g = baseGraph();
    g["passes"][1]["paramz"] = Json::object();
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].paramz", "tonemap", "", {"unknown key 'paramz'", "params"}));
}

TEST(LoaderErrors, UnknownUsageKey) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({{{"resource", "cube"}, {"access", "Read"}, {"stage", "Compute"},
                                       {"mip", Json::array({0, 1})}}}));
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0].mip", "gen", "cube", {"unknown key 'mip'", "mips"}));
}

// A usage of a whole image as an attachment needs an image of one level: "full" is one only
// for a fixed 1x1 extent; an output-relative extent or a larger fixed one has several.
TEST(LoaderErrors, AWholeFullChainIsAnAttachmentOnlyWhereItIsOneLevel) {
    for (const Json& extent : {Json::array({1, 1}), Json::array({2, 1}), Json("output")}) {
        Json g = baseGraph();
        g["resources"]["chain"] = {{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", extent}, {"mips", "full"}};
        g = withGeneric(g, "gen", Json{{"chain", "Write@ColorAttachment"}});
        if (extent == Json::array({1, 1})) {
            expectLoads(g);
            continue;
        }
        EXPECT_TRUE(hasDiag(loadErrors(g), "passes[2].uses.chain", "gen", "chain",
                            {"an attachment renders to one mip level"}))
            << extent.dump();
    }
}

TEST(LoaderErrors, UnknownResourceType) {
    Json g = baseGraph();
    g["resources"]["hdr_color"]["type"] = "texture3d";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color.type", "", "hdr_color",
                        {"texture3d", "image2d", "cube", "image2d_array", "buffer"}));
}

TEST(LoaderErrors, AResourceRefusedIsNotCheckedAgainstItsUsages) {
    // Its description is unknown: "format  has no depth or stencil" would only mislead.
    Json g = baseGraph();
    g["resources"]["depth"]["type"] = "image3d";
    const auto ds = loadErrors(g);
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.depth.type", "", "depth", {"image3d"}));
}

TEST(LoaderErrors, UnknownFormat) {
    Json g = baseGraph();
    g["resources"]["hdr_color"]["format"] = "R16G16B16A16_SFLOATY";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color.format", "", "hdr_color",
                        {"unknown format 'R16G16B16A16_SFLOATY'", "R16G16B16A16_SFLOAT,", "D32_SFLOAT"}));
    // The VK_FORMAT_ prefix is not part of the name.
    g["resources"]["hdr_color"]["format"] = "VK_FORMAT_R16G16B16A16_SFLOAT";
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.hdr_color.format", "", "hdr_color",
                        {"unknown format 'VK_FORMAT_R16G16B16A16_SFLOAT'"}));
}

TEST(LoaderErrors, UnknownPassTypeListsRegisteredTypes) {
    Json g = baseGraph();
    g["passes"][1]["type"] = "BloomPass";
    const auto ds = loadErrors(g);
    std::vector<std::string_view> words{"unknown pass type 'BloomPass'"};
    const auto names = registry().names();
    ASSERT_GE(names.size(), 9u);
    for (const auto& n : names) words.push_back(n);
    bool found = false;
    for (const auto& d : ds) {
        if (d.jsonPath != "passes[1].type" || d.pass != "tonemap" || d.file != kFile) continue;
        found = true;
        for (auto w : words) EXPECT_NE(d.message.find(w), std::string::npos) << w << " in " << d.message;
    }
    EXPECT_TRUE(found) << listAll(ds);
}

TEST(LoaderErrors, UnknownResourceInUses) {
    Json g = baseGraph();
    g["passes"][1]["uses"] = Json{{"hdr", "Read@Fragment"}, {"swapchain", "Write@ColorAttachment"}};
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.hdr", "tonemap", "hdr", {"unknown resource", "hdr_color"}));
}

TEST(LoaderErrors, UnknownAccessStageAndAs) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json{{"cube", "Sample@Fragment"}, {"mipped", "Read@Pixel"}, {"buf", "Read"}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.cube", "gen", "cube", {"unknown access \"Sample\"", "ReadWrite"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.mipped", "gen", "mipped", {"unknown stage \"Pixel\"", "Compute"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.buf", "gen", "buf", {"Access@Stage"}));
    g = withGeneric(baseGraph(), "gen",
                    Json::array({{{"resource", "cube"}, {"access", "Read"}, {"stage", "Compute"}, {"as", "texture"}},
                                 {{"resource", "mipped"}, {"access", "Sample"}, {"stage", "Pixel"}},
                                 {{"resource", "nothere"}, {"access", "Read"}, {"stage", "Compute"}}}));
    ds = loadErrors(g);
    // In usage objects, each error points at its key.
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0].as", "gen", "cube", {"unknown `as` \"texture\"", "sampled"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1].access", "gen", "mipped", {"unknown access \"Sample\""}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1].stage", "gen", "mipped", {"unknown stage \"Pixel\""}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[2].resource", "gen", "nothere", {"unknown resource; declared"}));
}

TEST(LoaderErrors, NonStringResourceInUsageArrayIsAnError) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({{{"resource", 5}, {"access", "Read"}, {"stage", "Compute"}}}));
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0].resource", "gen", "", {"resource"}));
}

// The names of the steps the compiler inserts are taken: a pass named like one would make two
// steps of one name in a plan. A name that only looks like one (no such resource) is free.
TEST(LoaderErrors, PassNamesOfInsertedStepsAreTaken) {
    const std::pair<std::string, std::string> taken[] = {
        {"clear hdr_color", "hdr_color"}, {"clobber depth", "depth"}, {"read back swapchain", "swapchain"}};
    for (const auto& [name, resource] : taken) {
        Json g = baseGraph();
        g["passes"][1]["name"] = name;
        EXPECT_TRUE(hasDiag(loadErrors(g), "passes[1].name", name, resource,
                            {"the name the compiler gives the step it inserts", "choose another"}))
            << name;
    }
    // The setup plan's step names are in a plan of their own: free for a frame's passes.
    for (const std::string name : {"clear the sky", "clearhdr_color", "upload cube", "initialize mipped"}) {
        Json g = baseGraph();
        g["passes"][1]["name"] = name;
        EXPECT_NO_THROW((void)parseGraph(g.dump(2), kFile, registry())) << name;
    }
}

// A file that cannot be opened says why: a missing file reads differently from one the user
// may not read.
TEST(LoaderErrors, AFileThatCannotBeOpenedSaysWhy) {
    const std::filesystem::path missing = std::filesystem::temp_directory_path() / "skygraph_no_such_dir" / "g.json";
    try {
        (void)loadGraphFile(missing, registry());
        FAIL() << "loaded " << missing;
    } catch (const GraphError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(missing.string()), std::string::npos) << what;
        EXPECT_NE(what.find("cannot open the file: No such file or directory"), std::string::npos) << what;
    }
}

TEST(LoaderErrors, DuplicatePassNames) {
    Json g = baseGraph();
    g["passes"][1]["name"] = "forward";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].name", "forward", "", {"duplicate pass name", "passes[0]"}));
}

TEST(LoaderErrors, DuplicateResourceNames) {
    // Only raw text can repeat a key; a JSON library would keep just the last one silently.
    const std::string text = R"({
      "version": 1, "name": "t",
      "resources": {
        "hdr_color": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
                       "external": true, "final": "Present" },
        "hdr_color": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" }
      },
      "passes": [
        { "name": "a", "type": "Generic", "uses": { "hdr_color": "Write@ColorAttachment" } },
        { "name": "b", "type": "Generic", "uses": { "hdr_color": "Read@Fragment",
                                                    "swapchain": "Write@ColorAttachment" } }
      ]
    })";
    const auto ds = textErrors(text);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color", "", "hdr_color", {"duplicate", "'hdr_color'"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

TEST(LoaderErrors, DuplicateResourceInOnePassUses) {
    const std::string text = R"({
      "version": 1, "name": "t",
      "resources": {
        "hdr_color": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output",
                       "external": true, "final": "ShaderRead" }
      },
      "passes": [
        { "name": "a", "type": "Generic",
          "uses": { "hdr_color": "Write@ColorAttachment", "hdr_color": "Read@Fragment" } }
      ]
    })";
    const auto ds = textErrors(text);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.hdr_color", "a", "hdr_color", {"duplicate"}));
}

TEST(LoaderErrors, UsageContradictingPassSlots) {
    Json g = baseGraph();
    g["passes"][1]["uses"]["hdr_color"] = "Write@Compute";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.hdr_color", "tonemap", "hdr_color",
                        {"Write@Compute", "TonemappingPass", "Read@Fragment"}));
}

TEST(LoaderErrors, UsageContradictingANamedSlot) {
    Json g = baseGraph();
    g["passes"][1]["uses"] = Json::array(
        {{{"resource", "hdr_color"}, {"access", "Read"}, {"stage", "Compute"}, {"slot", "hdr"}},
         {{"resource", "swapchain"}, {"access", "Write"}, {"stage", "ColorAttachment"}}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses[0]", "tonemap", "hdr_color",
                        {"Read@Compute", "slot 'hdr'", "TonemappingPass", "expected Read@Fragment"}));
    g["passes"][1]["uses"][0] = Json{{"resource", "hdr_color"}, {"access", "Read"}, {"stage", "Fragment"},
                                     {"slot", "bloom"}};
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses[0].slot", "tonemap", "hdr_color", {"no slot 'bloom'", "hdr (Read@Fragment"}));
}

// A slot whose shaders sample or store through one view type takes only resources of that
// type: a cube sampled as an equirect map crashed the shader compiler when the pass ran.
TEST(LoaderErrors, ASlotTakesOnlyTheResourceTypesItDeclares) {
    Json g = baseGraph();
    g["resources"]["acc"] = Json{{"type", "image2d"}, {"format", "R32G32B32A32_SFLOAT"}, {"extent", Json::array({16, 16})},
                                 {"external", true}, {"final", "General"}};
    g["passes"].push_back(Json{{"name", "pt"}, {"type", "PathTracePass"},
                               {"uses", {{"acc", "ReadWrite@Compute"}, {"cube", "Read@Compute"}}}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.cube", "pt", "cube",
                        {"slot 'environment' of PathTracePass takes an image2d, not 'cube' of type cube"}))
        << listAll(ds);
    g["passes"][1]["uses"] = Json{{"cube", "Read@Fragment"}, {"swapchain", "Write@ColorAttachment"}};
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.cube", "tonemap", "cube", {"slot 'hdr'", "takes an image2d"})) << listAll(ds);
    // The skybox samples a cube or an equirect map; the forward pass a cube only.
    Json sky = baseGraph();
    sky["passes"].push_back(Json{{"name", "sky"}, {"type", "SkyboxPass"},
                                 {"uses", {{"depth", "Read@DepthAttachment"}, {"hdr_color", "ReadWrite@ColorAttachment"},
                                           {"mipped", "Read@Fragment"}}}});
    expectLoads(sky);
    sky["passes"][0]["uses"] = Json::array(
        {{{"resource", "depth"}, {"access", "Write"}, {"stage", "DepthAttachment"}},
         {{"resource", "hdr_color"}, {"access", "Write"}, {"stage", "ColorAttachment"}},
         {{"resource", "mipped"}, {"access", "Read"}, {"stage", "Fragment"}, {"slot", "environment"}}});
    ds = loadErrors(sky);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses[2]", "forward", "mipped", {"takes a cube, not 'mipped' of type image2d"}))
        << listAll(ds);
    // Such a slot binds a cube view, of every face: some of them would make a 2D array view,
    // which the shader's samplerCube cannot read.
    sky["passes"][0]["uses"][2] = {{"resource", "cube"}, {"access", "Read"}, {"stage", "Fragment"},
                                   {"slot", "environment"}, {"layers", Json::array({0, 3})}};
    ds = loadErrors(sky);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses[2].layers", "forward", "cube",
                        {"slot 'environment' of ForwardPass binds the whole cube: its usage must cover layers [0, 6], "
                         "not [0, 3]"}))
        << listAll(ds);
}

// The environment pipeline's shaders store through a float format qualifier: another
// storage format is refused at the usage when the graph loads, not when its pipeline is made.
TEST(LoaderErrors, EnvironmentPassesWriteOnlyTheirStorageFormats) {
    Json g = baseGraph();
    g["resources"]["lut"] = Json{{"type", "image2d"}, {"format", "R32_SFLOAT"}, {"extent", Json::array({32, 32})},
                                 {"external", true}, {"final", "ShaderRead"}};
    g["passes"].push_back(Json{{"name", "brdf"}, {"type", "BrdfLutPass"}, {"uses", {{"lut", "Write@Compute"}}}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.lut", "brdf", "lut",
                        {"BrdfLutPass writes R16G16B16A16_SFLOAT, R32G32B32A32_SFLOAT, R16G16_SFLOAT or R32G32_SFLOAT "
                         "storage images, not R32_SFLOAT"}))
        << listAll(ds);
    g["resources"]["lut"]["format"] = "R16G16_SFLOAT";
    expectLoads(g);
}

/// graphs/ibl.json, the shipped environment graph, for tests that break one thing of it.
Json shippedEnvironmentGraph() {
    std::ifstream in(std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "ibl.json");
    return Json::parse(in);
}

/// The index in `g["passes"]` of the pass named `name`.
size_t passIndex(const Json& g, std::string_view name) {
    for (size_t i = 0; i < g["passes"].size(); ++i)
        if (g["passes"][i]["name"].get<std::string>() == name) return i;
    ADD_FAILURE() << "no pass '" << name << "'";
    return 0;
}

// Each environment pass stores through a view of its usage's first mip level: a usage of more
// levels compiled, and the plan called the other levels written while they stayed undefined.
TEST(LoaderErrors, EnvironmentPassesWriteOneMipPerStorageUsage) {
    const Json shipped = shippedEnvironmentGraph();
    expectLoads(shipped);  // one usage per level, or the whole of a resource of one level

    // PrefilterPass's six per-mip usages as one usage of the whole resource.
    Json g = shipped;
    const size_t prefilter = passIndex(g, "prefilter");
    Json uses = Json::array();
    for (const Json& use : g["passes"][prefilter]["uses"])
        if (use["resource"] != "prefiltered") uses.push_back(use);
    uses.push_back(Json{{"resource", "prefiltered"}, {"access", "Write"}, {"stage", "Compute"}});
    g["passes"][prefilter]["uses"] = uses;
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[" + std::to_string(prefilter) + "].uses[1]", "prefilter", "prefiltered",
                        {"PrefilterPass writes one mip per usage of slot 'prefiltered': the usage of 'prefiltered' "
                         "covers all 6 of its mips; give one usage per mip (\"mips\": [m, 1])"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);

    // The cube's faces without `"mips": [0, 1]`: the whole chain of a "full" resource.
    g = shipped;
    const size_t toCube = passIndex(g, "equirect_to_cube");
    g["passes"][toCube]["uses"][1].erase("mips");
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[" + std::to_string(toCube) + "].uses[1]", "equirect_to_cube", "environment",
                        {"EquirectToCubemapPass writes one mip per usage of slot 'cubemap': the usage of 'environment' "
                         "covers its whole mip chain (\"mips\": \"full\"); name one mip (\"mips\": [m, 1])"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);

    // A range of two levels, and whole resources of several.
    g = shipped;
    const size_t mip1 = passIndex(g, "environment_mip1"), irradiance = passIndex(g, "irradiance"),
                 lut = passIndex(g, "brdf_lut");
    g["passes"][mip1]["uses"][1]["mips"] = Json::array({1, 2});
    g["resources"]["irradiance"]["mips"] = 2;
    g["resources"]["brdf_lut"]["mips"] = "full";
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[" + std::to_string(mip1) + "].uses[1]", "environment_mip1", "environment",
                        {"CubemapMipPass writes one mip per usage of slot 'target'", "covers mips [1, 2]"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[" + std::to_string(irradiance) + "].uses.irradiance", "irradiance", "irradiance",
                        {"IrradiancePass writes one mip per usage of slot 'irradiance'", "covers all 2 of its mips"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[" + std::to_string(lut) + "].uses.brdf_lut", "brdf_lut", "brdf_lut",
                        {"BrdfLutPass writes one mip per usage of slot 'lut'", "covers its whole mip chain"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 3u) << listAll(ds);

    // The "full" chain of a 1x1 extent is one level.
    g = shipped;
    g["resources"]["irradiance"]["extent"] = Json::array({1, 1});
    g["resources"]["irradiance"]["mips"] = "full";
    expectLoads(g);
}

// ForwardPass clears nothing itself: a Write of its depth loads nothing (DONT_CARE), so without
// the resource's load-op clear every fragment met undefined depth, and the frame rendered black.
TEST(LoaderErrors, ForwardPassWritesDepthOnlyFromAClear) {
    Json g = baseGraph();
    g["resources"]["depth"].erase("clear");
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.depth", "forward", "depth",
                        {"ForwardPass tests depth against what slot 'depth' starts with, and a Write of 'depth', "
                         "which has no `clear`, starts with undefined values: add \"clear\": { \"depth\": 0.0 } "
                         "(reverse-Z's far plane) to 'depth', or use ReadWrite after an earlier depth pass"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    // A Write of part of a cleared image is cleared by a Clear step the Write then discards:
    // only the load op of a whole-image Write starts it from the clear.
    Json partial = baseGraph();
    partial["resources"]["depth"]["mips"] = 2;
    partial["passes"][0]["uses"] = Json::parse(R"([
        { "resource": "depth", "access": "Write", "stage": "DepthAttachment", "mips": [0, 1] },
        { "resource": "hdr_color", "access": "Write", "stage": "ColorAttachment" } ])");
    const auto parts = loadErrors(partial);
    EXPECT_TRUE(hasDiag(parts, "passes[0].uses[0]", "forward", "depth",
                        {"ForwardPass tests depth against what slot 'depth' starts with, and a Write of part of "
                         "'depth' discards it: only a Write of the whole image starts from its `clear` (the load "
                         "op's); write all of it, or use ReadWrite"}))
        << listAll(parts);
    EXPECT_EQ(parts.size(), 1u) << listAll(parts);
    // A full chain's length waits for the output size: a range of one level is a part of it.
    partial["resources"]["depth"]["mips"] = "full";
    EXPECT_TRUE(hasDiag(loadErrors(partial), "passes[0].uses[0]", "forward", "depth", {"a Write of part of"}))
        << listAll(loadErrors(partial));
    partial["resources"]["depth"]["mips"] = 1;  // the same range is now all of it
    expectLoads(partial);
    // A ReadWrite starts from an earlier pass's depth.
    g["passes"][0]["uses"]["depth"] = "ReadWrite@DepthAttachment";
    g["passes"].insert(g["passes"].begin(), Json{{"name", "depth_prepass"}, {"type", "Generic"},
                                                 {"uses", {{"depth", "Write@DepthAttachment"}}}});
    expectLoads(g);
}

// SkyboxPass samples its environment as the resource's type says: `sampling` only states how,
// and a statement that contradicts the type is refused rather than ignored.
TEST(LoaderErrors, SkyboxSamplingAgreesWithTheEnvironmentsType) {
    const auto skyOf = [](const std::string& environment, const std::string& sampling) {
        Json g = baseGraph();
        Json uses = {{"depth", "Read@DepthAttachment"}, {"hdr_color", "ReadWrite@ColorAttachment"}};
        if (!environment.empty()) uses[environment] = "Read@Fragment";
        g["passes"].push_back(Json{{"name", "sky"}, {"type", "SkyboxPass"}, {"uses", uses},
                                   {"params", {{"sampling", sampling}}}});
        return g;
    };
    auto ds = loadErrors(skyOf("cube", "equirect"));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.cube", "sky", "cube",
                        {"SkyboxPass samples the cube 'cube' as a cubemap, which its type decides, but \"sampling\" "
                         "says \"equirect\": say \"cubemap\" or bind an image2d"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    ds = loadErrors(skyOf("mipped", "cubemap"));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.mipped", "sky", "mipped",
                        {"SkyboxPass samples the image2d 'mipped' as an equirect map",
                         "say \"equirect\" or bind a cube"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    expectLoads(skyOf("cube", "cubemap"));
    expectLoads(skyOf("mipped", "equirect"));
    expectLoads(skyOf("", "equirect"));  // the procedural sky samples nothing
}

// SkyboxPass's `previous` is bound by name only: a sampled fragment read still binds to
// `environment` as the one slot it fits, as it did before `previous` existed.
TEST(LoaderErrors, ASlotBoundByNameOnlyIsNeverChosenByFit) {
    const auto graphWith = [](const std::string& fadeFrom) {
        return R"({"version": 1, "name": "t",
          "resources": {
            "depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": {"depth": 0.0}},
            "hdr": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output", "external": true,
                    "initial": "ShaderRead", "final": "ShaderRead"},
            "sky": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "external": true, "initial": "ShaderRead"},
            "previous": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "external": true, "initial": "ShaderRead"},
            "older": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "external": true, "initial": "ShaderRead"}},
          "passes": [{"name": "sky", "type": "SkyboxPass", "uses": [
            {"resource": "depth", "access": "Read", "stage": "DepthAttachment"},
            {"resource": "hdr", "access": "ReadWrite", "stage": "ColorAttachment"},
            {"resource": "sky", "access": "Read", "stage": "Fragment"})" + fadeFrom + "]}]}";
    };
    const auto slots = [](const GraphDesc& g) {
        std::vector<std::string> out;
        for (const UsageDecl& u : g.passes.at(0).uses) out.emplace_back(g.slotName(u.slot));
        return out;
    };
    EXPECT_EQ(slots(parseGraph(graphWith(""), kFile, registry())),
              (std::vector<std::string>{"depth", "color", "environment"}));
    EXPECT_EQ(slots(parseGraph(graphWith(R"(, {"resource": "previous", "access": "Read", "stage": "Fragment"})"), kFile,
                               registry())),
              (std::vector<std::string>{"depth", "color", "environment", "previous"}))
        << "by the resource's name";
    EXPECT_EQ(slots(parseGraph(graphWith(R"(, {"resource": "older", "access": "Read", "stage": "Fragment", "slot": "previous"})"),
                               kFile, registry())),
              (std::vector<std::string>{"depth", "color", "environment", "previous"}))
        << "by the usage's slot";
    const auto ds = textErrors(graphWith(R"(, {"resource": "older", "access": "Read", "stage": "Fragment"})"));
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses[3]", "sky", "older",
                        {"slot 'environment' of SkyboxPass is already filled by 'sky'",
                         "slot 'previous' takes it by name only: \"slot\": \"previous\""}))
        << listAll(ds);
}

TEST(LoaderErrors, DepthFormatAsColorAttachment) {
    Json g = baseGraph();
    g["passes"][0]["uses"]["depth"] = "Write@ColorAttachment";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.depth", "forward", "depth",
                        {"D32_SFLOAT", "depth", "cannot be a color attachment", "DepthAttachment"}));
}

TEST(LoaderErrors, ColorFormatAsDepthAttachment) {
    Json g = baseGraph();
    g["passes"][0]["uses"]["hdr_color"] = "Write@DepthAttachment";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.hdr_color", "forward", "hdr_color",
                        {"R16G16B16A16_SFLOAT", "cannot be a depth attachment", "ColorAttachment"}));
}

TEST(LoaderErrors, StorageUseOfSrgbOrDepthFormat) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({{{"resource", "swapchain"}, {"access", "Write"}, {"stage", "Compute"}},
                                      {{"resource", "depth"}, {"access", "Read"}, {"stage", "Fragment"},
                                       {"as", "storage"}}}));
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0]", "gen", "swapchain",
                        {"B8G8R8A8_SRGB", "cannot be a storage image"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "gen", "depth", {"D32_SFLOAT", "cannot be a storage image"}));
}

TEST(LoaderErrors, SampledWrite) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({{{"resource", "mipped"}, {"access", "Write"}, {"stage", "Fragment"},
                                       {"as", "sampled"}},
                                      {{"resource", "cube"}, {"access", "ReadWrite"}, {"stage", "Compute"},
                                       {"as", "sampled"}}}));
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0]", "gen", "mipped", {"sampled image is read-only", "Read@Fragment"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "gen", "cube", {"sampled image is read-only", "Read@Compute"}));
}

TEST(LoaderErrors, BufferAsAttachment) {
    Json g = withGeneric(baseGraph(), "gen", Json{{"buf", "Write@ColorAttachment"}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.buf", "gen", "buf", {"buffer cannot be an attachment"}));
    g = withGeneric(baseGraph(), "gen", Json{{"buf", "Read@DepthAttachment"}});
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.buf", "gen", "buf", {"buffer cannot be an attachment"}));
}

TEST(LoaderErrors, BufferUsagesThatOnlyImagesHave) {
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({{{"resource", "buf"}, {"access", "Read"}, {"stage", "Fragment"},
                                       {"as", "sampled"}}}));
    EXPECT_TRUE(hasDiag(loadErrors(g), "passes[2].uses[0]", "gen", "buf", {"buffer cannot be sampled"}));
}

TEST(LoaderErrors, VertexInputOrIndirectOnImage) {
    Json g = withGeneric(baseGraph(), "gen", Json{{"mipped", "Read@VertexInput"}, {"cube", "Read@Indirect"}});
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.mipped", "gen", "mipped", {"VertexInput reads buffers, not images"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.cube", "gen", "cube", {"Indirect reads buffers, not images"}));
    // And they only read.
    g = withGeneric(baseGraph(), "gen", Json{{"buf", "Write@Indirect"}});
    EXPECT_TRUE(hasDiag(loadErrors(g), "passes[2].uses.buf", "gen", "buf", {"only reads", "Read@Indirect"}));
}

TEST(LoaderErrors, ReadWithNoEarlierWriter) {
    Json g = baseGraph();
    g["passes"].erase(0);  // nobody writes hdr_color any more
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.hdr_color", "tonemap", "hdr_color",
                        {"no earlier pass writes it", "clear", "external"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

// A read whose range is written in part names the part no pass writes.
TEST(LoaderErrors, AReadOfLevelsNoPassWritesNamesThem) {
    Json g = baseGraph();
    g["resources"]["levels"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", Json::array({16, 16})},
                                    {"mips", 3}};
    g = withGeneric(g, "w", Json::array({{{"resource", "levels"}, {"access", "Write"}, {"stage", "Compute"},
                                          {"mips", Json::array({0, 1})}}}));
    g = withGeneric(g, "r", {{"levels", "Read@Compute"}});
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.levels", "r", "levels",
                        {"reads 'levels' (Read@Compute", "but no earlier pass writes mips 1 and 2 of it"}))
        << listAll(ds);
    g["resources"]["levels"] = Json{{"type", "image2d_array"}, {"format", "R8G8B8A8_UNORM"},
                                    {"extent", Json::array({16, 16})}, {"layers", 4}};
    g["passes"][2]["uses"][0]["layers"] = Json::array({0, 2});
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.levels", "r", "levels", {"no earlier pass writes mip 0 (layers 2, 3) of it"}))
        << listAll(ds);
    // Runs of three layers or more by their ends: 2048 layers of which only layer 0 is written
    // make one short line, not one number per layer; a run of two is listed.
    g["resources"]["levels"]["layers"] = 2048;
    g["passes"][2]["uses"][0]["layers"] = Json::array({0, 1});
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.levels", "r", "levels", {"no earlier pass writes mip 0 (layers 1 to 2047) of it"}))
        << listAll(ds);
    g["passes"][2]["uses"] = Json::array({{{"resource", "levels"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"layers", Json::array({0, 1})}},
                                          {{"resource", "levels"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"layers", Json::array({3, 2044})}},
                                          {{"resource", "levels"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"layers", Json::array({2047, 1})}}});
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.levels", "r", "levels", {"no earlier pass writes mip 0 (layers 1, 2) of it"}))
        << listAll(ds);
    for (const auto& d : ds) EXPECT_LT(d.format().size(), 400u) << d.format();
}

TEST(LoaderErrors, ReadBeforeItsWriterInFileOrder) {
    Json g = baseGraph();
    std::swap(g["passes"][0], g["passes"][1]);  // tonemap now reads before forward writes
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.hdr_color", "tonemap", "hdr_color", {"no earlier pass writes it"}));
}

TEST(LoaderErrors, ReadOfAnUnwrittenMipLevel) {
    // Writing mip 0 does not make mip 1 readable.
    Json g = baseGraph();
    g["resources"]["lvl"] = Json::parse(
        R"({ "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": 2 })");
    g = withGeneric(g, "w", Json::array({{{"resource", "lvl"}, {"access", "Write"}, {"stage", "Compute"},
                                          {"mips", Json::array({0, 1})}}}));
    g = withGeneric(g, "r", Json::array({{{"resource", "lvl"}, {"access", "Read"}, {"stage", "Compute"},
                                          {"mips", Json::array({1, 1})}}}));
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses[0]", "r", "lvl", {"no earlier pass writes it"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

// The loader checks reads without an output size. A "full" chain of an output-relative image
// has the levels the output gives it, so the loader checks a read of one at its first level,
// which every output has; the levels past it are compile()'s to check, at the output it is
// given (before, the loader invented one: 1920x1080).
TEST(LoaderErrors, ReadOfAnOutputSizedChainIsCheckedAtTheOutputSizeItCompilesFor) {
    Json g = baseGraph();
    g["resources"]["chain"] = Json::parse(
        R"({ "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output", "mips": "full" })");
    g = withGeneric(g, "w", Json::array({{{"resource", "chain"}, {"access", "Write"}, {"stage", "Compute"},
                                          {"mips", {0, 4}}}}));
    g = withGeneric(g, "r", Json{{"chain", "Read@Fragment"}});
    expectLoads(g);
    // An 8x8 output has the 4 levels w writes; a 1920x1080 one has 11, and r reads 7 that
    // nothing writes.
    const GraphDesc graph = parseGraph(g.dump(2), kFile, registry());
    CompileOptions small;
    small.outputWidth = small.outputHeight = 8;
    EXPECT_NO_THROW((void)compile(graph, small));
    const auto ds = compileErrors(g, CompileOptions{});
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.chain", "r", "chain",
                        {"reads 'chain' (Read@Fragment as sampled) but no earlier pass writes mips 4, 5, 6, 7, 8, 9 and 10 "
                         "of it", "clear", "external"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    // A read whose first level nothing writes has no source at any output size.
    g["passes"][3]["uses"] = Json::array({{{"resource", "chain"}, {"access", "Read"}, {"stage", "Fragment"},
                                           {"mips", {4, 1}}}});
    const auto ls = loadErrors(g);
    EXPECT_TRUE(hasDiag(ls, "passes[3].uses[0]", "r", "chain", {"no earlier pass writes it"}));
    EXPECT_EQ(ls.size(), 1u) << listAll(ls);
}

TEST(LoaderErrors, ClearOrExternalIsASource) {
    Json g = baseGraph();
    g["passes"].erase(0);
    g["resources"]["hdr_color"]["clear"] = Json{{"color", {0, 0, 0, 1}}};
    expectLoads(g);
    g["resources"]["hdr_color"].erase("clear");
    g["resources"]["hdr_color"]["external"] = true;
    expectLoads(g);
}

TEST(LoaderErrors, ReadWhoseOnlyWriterIsSwitchedOffByAFeature) {
    CompileOptions options;
    options.features["geo"] = false;
    const auto ds = compileErrors(baseGraph(), options);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.hdr_color", "tonemap", "hdr_color",
                        {"no earlier pass writes it", "'forward'", "feature 'geo' is off"}));
    // With the feature on it compiles.
    options.features["geo"] = true;
    EXPECT_NO_THROW((void)compile(parseGraph(baseGraph().dump(), kFile, registry()), options));
}

TEST(LoaderErrors, ReadWhoseWriterHasACompoundConditionNamesTheCondition) {
    Json g = baseGraph();
    g["passes"][0]["if"] = "geo && !sky";
    CompileOptions options;
    options.features["sky"] = true;
    const auto ds = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.hdr_color", "tonemap", "hdr_color",
                        {"'forward'", "geo && !sky", "sky=on"}));
}

TEST(LoaderErrors, BadIfExpressionNamesTheColumn) {
    Json g = baseGraph();
    g["passes"][0]["if"] = "geo && && sky";
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].if", "forward", "", {"geo && && sky", "column 8"}));
    g["passes"][0]["if"] = "(geo || sky";
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].if", "forward", "", {"column 12", "expected ')'"}));
    g["passes"][0]["if"] = true;
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].if", "forward", "", {"string expression"}));
}

TEST(LoaderErrors, UnknownFeatureInIf) {
    Json g = baseGraph();
    g["passes"][0]["if"] = "geo && bloom";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[0].if", "forward", "", {"unknown feature 'bloom'", "geo", "sky"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

TEST(LoaderErrors, BadFeatureDeclarations) {
    Json g = baseGraph();
    g["features"]["has space"] = true;
    g["features"]["on"] = "yes";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, R"(features["has space"])", "", "", {"not a valid feature name"}));
    EXPECT_TRUE(hasDiag(ds, "features.on", "", "", {"true or false"}));
}

// A name with a zero-width space prints like the name without it, and a right-to-left override
// makes the rest of a message read backwards: refused where the name is given, like control
// characters, and shown escaped in every message.
TEST(LoaderErrors, NamesWithInvisibleCharactersAreRefusedAndShownEscaped) {
    Json g = baseGraph();
    g["name"] = "t\u00ad";                                   // a soft hyphen
    g["passes"][1]["name"] = "\u202eevil";                  // a right-to-left override
    g["resources"]["hdr_color\u200b"] = g["resources"]["hdr_color"];  // a zero-width space
    g["resources"]["b\ufeff"] = g["resources"]["buf"];               // a byte order mark
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "name", "", "", {"'t\\u00ad' holds the invisible character U+00AD", "printed in plans"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[1].name", "", "", {"'\\u202eevil' holds the invisible character U+202E"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color\u200b", "", "hdr_color\u200b",
                        {"its name holds the invisible character U+200B"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.b\ufeff", "", "b\ufeff", {"U+FEFF"})) << listAll(ds);
    for (const Diagnostic& d : ds)
        for (const std::string raw : {"\u00ad", "\u202e", "\u200b", "\ufeff"})
            EXPECT_EQ(d.format().find(raw), std::string::npos) << "escaped in every message: " << d.format();
    // Other characters outside ASCII are names like any other.
    Json ok = baseGraph();
    ok["passes"][1]["name"] = "tonemap_\u00e9t\u00e9_\u6f22";
    EXPECT_NO_THROW((void)parseGraph(ok.dump(2), kFile, registry()));
}

// A control character in a name would ring a terminal or break a line of a text plan or DOT
// graph: refused where the name is given, and shown escaped in every message.
TEST(LoaderErrors, NamesWithControlCharactersAreRefusedAndShownEscaped) {
    Json g = baseGraph();
    g["name"] = "t\u0001";
    g["passes"][1]["name"] = "tone\u0007map";
    g["resources"]["hdr\ncolor"] = g["resources"]["hdr_color"];
    g["passes"].push_back(Json{{"name", "reader"}, {"type", "Generic"}, {"uses", {{"no\tsuch", "Read@Fragment"}}}});
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "name", "", "", {"'t\\u0001' holds a control character", "printed in plans"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[1].name", "", "", {"'tone\\u0007map' holds a control character"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources[\"hdr\ncolor\"]", "", "hdr\ncolor", {"its name holds a control character"}))
        << listAll(ds);
    for (const Diagnostic& d : ds) {
        const std::string line = d.format();
        EXPECT_EQ(std::count_if(line.begin(), line.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }), 0)
            << line;
    }
    const std::string all = listAll(ds);
    EXPECT_NE(all.find("resource 'no\\u0009such': unknown resource; declared: buf, cube, depth, hdr\\u000acolor"),
              std::string::npos)
        << all;
}

TEST(LoaderErrors, MeaninglessDeclarationsAreRefused) {
    Json g = baseGraph();
    g["version"] = 1.0;
    g["features"]["tab\t"] = true;
    g["features"]["line\n"] = true;
    g["features"]["9lives"] = true;
    g["resources"][""] = Json{{"type", "buffer"}, {"size", 4}};
    g["resources"]["shown"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", "output"},
                                   {"final", "Present"}};
    g["resources"]["stencil"] = Json{{"type", "image2d"}, {"format", "S8_UINT"}, {"extent", "output"},
                                     {"clear", {{"depth", 0.5}}}};
    g["resources"]["unused_output"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"},
                                           {"extent", "output"}, {"final", "TransferSrc"}};
    g = withGeneric(g, "generic", Json::array({Json{{"resource", "shown"}, {"access", "Write"},
                                                    {"stage", "ColorAttachment"}, {"slot", "color"}},
                                               Json{{"resource", "stencil"}, {"access", "Read"},
                                                    {"stage", "Fragment"}},
                                               Json{{"resource", ""}, {"access", "Read"}, {"stage", "Compute"}}}));
    g["passes"][1]["uses"] = Json::array({Json{{"resource", "hdr_color"}, {"access", "Read"}, {"stage", "Fragment"},
                                               {"slot", ""}},
                                          Json{{"resource", "swapchain"}, {"access", "Write"},
                                               {"stage", "ColorAttachment"}}});
    g = withGeneric(g, "idle", Json::object());
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "version", "", "", {"unsupported version 1.0"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "features[\"tab\t\"]", "", "", {"'tab\\u0009' is not a valid feature name"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "features[\"line\n\"]", "", "", {"'line\\u000a' is not a valid feature name"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "features.9lives", "", "", {"'9lives' is not a valid feature name"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, R"(resources[""])", "", "", {"a resource needs a name"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.shown.final", "", "shown", {"only an external image", "can be presented"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.stencil.clear.depth", "", "stencil", {"S8_UINT has no depth aspect"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0].slot", "generic", "shown", {"Generic takes any usage and has no slots"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses[0].slot", "tonemap", "hdr_color", {"`slot` must name a slot"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses", "idle", "", {"empty; a pass that uses nothing does nothing"}))
        << listAll(ds);
}

TEST(LoaderErrors, AnOutputNoPassUsesIsRefused) {
    Json g = baseGraph();
    g["resources"]["unused_output"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", "output"},
                                           {"final", "TransferSrc"}};
    g["resources"]["unused_input"] = Json{{"type", "buffer"}, {"size", 4}, {"external", true}};
    const auto ds = loadErrors(g);
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);  // an unused resource that is no output is left out, not refused
    EXPECT_TRUE(hasDiag(ds, "resources.unused_output.final", "", "unused_output",
                        {"'unused_output' is an output of the graph (`final`), but no pass uses it"}))
        << listAll(ds);
}

// An output is handed on whole: a mip or layer of it that no pass writes (and no clear fills)
// would leave the frame undefined. Written whole, cleared, or external, it loads.
TEST(LoaderErrors, AnOutputThatNoPassWritesWholeIsRefused) {
    Json g = withGeneric(baseGraph(), "half",
                         Json::array({Json{{"resource", "partial"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"mips", {0, 1}}},
                                      Json{{"resource", "layered"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"layers", {1, 1}}},
                                      Json{{"resource", "chain"}, {"access", "Write"}, {"stage", "Compute"},
                                           {"mips", {1, 1}}}}));
    g["resources"]["partial"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", {16, 16}},
                                     {"mips", 3}, {"final", "ShaderRead"}};
    g["resources"]["layered"] = Json{{"type", "image2d_array"}, {"format", "R8G8B8A8_UNORM"}, {"extent", {16, 16}},
                                     {"layers", 3}, {"final", "ShaderRead"}};
    // A full chain of the output's size: its length waits for the output, its first level not.
    g["resources"]["chain"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", "output"},
                                   {"mips", "full"}, {"final", "ShaderRead"}};
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.partial.final", "", "partial",
                        {"'partial' is an output of the graph (`final`), but no pass writes mips 1 and 2 of it, and "
                         "it is not `clear`: the frame would hand that part on undefined"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.layered.final", "", "layered", {"no pass writes mip 0 (layers 0, 2) of it"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.chain.final", "", "chain", {"no pass writes mip 0 of it"})) << listAll(ds);
    EXPECT_EQ(ds.size(), 3u) << listAll(ds);
    g["resources"]["partial"]["clear"] = Json{{"color", {0, 0, 0, 1}}};
    g["resources"]["layered"]["external"] = true;
    g["resources"]["chain"]["clear"] = Json{{"color", {0, 0, 0, 1}}};
    expectLoads(g);
}

// The loader checks outputs with every pass on; compile() with the passes that run: a feature
// that switches off a writer of an output would leave that part of it, or all of it, undefined
// as the frame hands it on. The message names the writer that is off.
TEST(LoaderErrors, AnOutputWhoseWriterAFeatureSwitchesOffIsRefusedWhereItIsOff) {
    const Json g = Json::parse(R"({"version": 1, "name": "outputs", "features": {"m1": true, "all": true},
        "resources": {"o": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "mips": 2,
                            "final": "ShaderRead"},
                      "b": {"type": "buffer", "size": 256, "final": "ShaderRead"}},
        "passes": [
          {"name": "w0", "type": "Generic", "uses": [{"resource": "o", "access": "Write", "stage": "Compute", "mips": [0, 1]}]},
          {"name": "w1", "type": "Generic", "if": "m1",
           "uses": [{"resource": "o", "access": "Write", "stage": "Compute", "mips": [1, 1]}]},
          {"name": "wb", "type": "Generic", "if": "all", "uses": {"b": "Write@Compute"}}]})");
    CompileOptions options;
    options.features["m1"] = false;
    const auto ds = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(ds, "resources.o.final", "", "o",
                        {"'o' is an output of the graph (`final`), but no pass that runs with these features writes "
                         "mip 1 of it, and it is not `clear`: the frame would hand that part on undefined; its writer "
                         "'w1' is off: feature 'm1' is off"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
    options.features = {{"all", false}};
    const auto none = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(none, "resources.b.final", "", "b",
                        {"no pass that runs with these features writes it, and it is not `clear`: the frame would "
                         "hand it on undefined; its writer 'wb' is off: feature 'all' is off"}))
        << listAll(none);
    options.features = {};
    EXPECT_NO_THROW((void)compile(parseGraph(g.dump(), kFile, registry()), options));
}

TEST(LoaderErrors, ASlotAlreadyFilledNamesWhatFilledIt) {
    Json g = baseGraph();
    g["resources"]["other"] = g["resources"]["hdr_color"];
    g["passes"][1]["uses"] = Json{{"hdr_color", "Read@Fragment"}, {"other", "Read@Fragment"},
                                  {"swapchain", "Write@ColorAttachment"}};
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.other", "tonemap", "other",
                        {"slot 'hdr' of TonemappingPass is already filled by 'hdr_color'"}))
        << listAll(ds);
}

TEST(LoaderErrors, ARepeatedKeyNamesAResourceWhoseNameHoldsADot) {
    const std::string text = R"({"version": 1, "name": "t", "resources": {
        "a": {"type": "buffer", "size": 4, "external": true},
        "a.b": {"type": "buffer", "size": 4, "size": 8, "external": true},
        "q\"]": {"type": "buffer", "size": 4, "external": true, "external": true}},
      "passes": [{"name": "p", "type": "Generic", "never_cull": true,
                  "uses": {"a.b": "Read@Compute", "a": "Read@Compute", "a": "Read@Compute"}}]})";
    const auto ds = textErrors(text);
    EXPECT_TRUE(hasDiag(ds, R"(resources["a.b"].size)", "", "a.b", {"duplicate key 'size'"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, R"(resources["q\"]"].external)", "", "q\"]", {"duplicate key 'external'"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[0].uses.a", "p", "a", {"duplicate key 'a'"})) << listAll(ds);
}

// "resources.gbuffer.normal.format" could be a key "normal.format" of resource "gbuffer": a
// name that a dot cannot delimit is quoted, wherever a path names it.
TEST(LoaderErrors, PathsQuoteNamesThatHoldADotOrABracket) {
    const std::string text = R"({"version": 1, "name": "t", "features": {"a.b": true}, "resources": {
        "gbuffer.normal": {"type": "image2d", "format": "R8G8B8A8_UNROM", "extent": "output"},
        "list[0]": {"type": "buffer", "size": 4, "external": true, "colour": 1}},
      "passes": [{"name": "p", "type": "Generic", "never_cull": true,
                  "uses": {"gbuffer.normal": "Write@ColorAttachment", "list[0]": "Read@Somewhere"}}]})";
    const auto ds = textErrors(text);
    EXPECT_TRUE(hasDiag(ds, R"(resources["gbuffer.normal"].format)", "", "gbuffer.normal", {"R8G8B8A8_UNROM"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, R"(resources["list[0]"].colour)", "", "list[0]", {"unknown key 'colour'"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, R"(passes[0].uses["list[0]"])", "p", "list[0]", {"Somewhere"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, R"(features["a.b"])", "", "", {"not a valid feature name"})) << listAll(ds);
}

TEST(LoaderErrors, PassTypesCheckWhatTheirSlotsCannotSay) {
    Json g = baseGraph();
    g["resources"]["mipped_target"] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", {8, 8}},
                                           {"mips", 2}, {"external", true}, {"final", "ShaderRead"}};
    g["resources"]["r32"] = Json{{"type", "image2d"}, {"format", "R32_SFLOAT"}, {"extent", "output"},
                                 {"external", true}, {"final", "ShaderRead"}};
    g["resources"]["flat_sky"] = Json{{"type", "image2d"}, {"format", "R16G16B16A16_SFLOAT"}, {"extent", {8, 4}},
                                      {"external", true}};
    g["passes"].push_back(Json{{"name", "upload"}, {"type", "UploadPass"}, {"uses", {{"mipped_target", "Write@Transfer"}}}});
    g["passes"].push_back(Json{{"name", "tonemap_cs"}, {"type", "TonemappingComputePass"},
                               {"uses", {{"hdr_color", "Read@Compute"}, {"r32", "Write@Compute"}}}});
    g["passes"].push_back(Json{{"name", "sky"}, {"type", "SkyboxPass"},
                               {"uses", {{"depth", "Read@DepthAttachment"}, {"hdr_color", "ReadWrite@ColorAttachment"},
                                         {"cube", "Read@Fragment"}, {"previous", "Read@Fragment"}}}});
    g["resources"]["previous"] = g["resources"]["flat_sky"];
    g["resources"].erase("flat_sky");
    // The same usages a type accepts pass: a whole single-level target, a storage format it writes.
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.mipped_target", "upload", "mipped_target",
                        {"UploadPass copies mip 0 of every layer", "\"mips\": [0, 1]"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[3].uses.r32", "tonemap_cs", "r32",
                        {"TonemappingComputePass writes R8G8B8A8_UNORM", "not R32_SFLOAT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[4].uses.previous", "sky", "previous",
                        {"slot 'previous' of SkyboxPass takes a cube, not 'previous' of type image2d"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 3u) << listAll(ds);

    g["passes"][2]["uses"] = Json::array({Json{{"resource", "mipped_target"}, {"access", "Write"},
                                               {"stage", "Transfer"}, {"mips", {0, 1}}}});
    g["resources"]["r32"]["format"] = "R16G16B16A16_SFLOAT";
    g["resources"]["previous"]["type"] = "cube";
    g["resources"]["previous"]["extent"] = {8, 8};
    expectLoads(g);
}

/// A 4x4 image of `format` cleared to `color`.
Json clearedImage(const char* format, Json color) {
    return Json{{"type", "image2d"}, {"format", format}, {"extent", {4, 4}}, {"clear", {{"color", std::move(color)}}}};
}

TEST(LoaderErrors, IntegerFormatsClearToIntegers) {
    Json g = baseGraph();
    g["resources"]["fraction"] = clearedImage("R32_UINT", {0.5, 0, 0, 1});
    g["resources"]["negative"] = clearedImage("R32G32B32A32_UINT", {-1, 0, 0, 1});
    g["resources"]["huge"] = clearedImage("R32_SINT", {0, 0, 0, 16777217});
    g["resources"]["fine_uint"] = clearedImage("R32_UINT", {16777216, 0, 0, 1});
    g["resources"]["fine_sint"] = clearedImage("R32_SINT", {-16777216, 7, 0, 1});
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.fraction.clear.color", "", "fraction",
                        {"expected four integers in [0, 16777216] for the integer format R32_UINT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.negative.clear.color", "", "negative", {"[0, 16777216]", "R32G32B32A32_UINT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.huge.clear.color", "", "huge", {"[-16777216, 16777216]", "R32_SINT"}))
        << listAll(ds);
    EXPECT_EQ(ds.size(), 3u) << listAll(ds);
}

// A clear converts its value to the format: a normalized format clamps what lies outside its
// range and a float format overflows, so a value the format does not hold is refused, never
// changed. The edges of each range load.
TEST(LoaderErrors, ColorClearsHoldValuesOfTheirFormat) {
    Json g = baseGraph();
    g["resources"]["unorm"] = clearedImage("R8G8B8A8_UNORM", {0, 0, 1.5, 1});
    g["resources"]["srgb"] = clearedImage("B8G8R8A8_SRGB", {-0.25, 0, 0, 1});
    g["resources"]["snorm"] = clearedImage("R8G8B8A8_SNORM", {0, -1.01, 0, 1});
    g["resources"]["half"] = clearedImage("R16G16B16A16_SFLOAT", {0, 0, 0, 65505});
    g["resources"]["single"] = clearedImage("R32_SFLOAT", {1e39, 0, 0, 1});
    g["resources"]["ufloat"] = clearedImage("B10G11R11_UFLOAT_PACK32", {-1, 0, 0, 1});
    g["resources"]["fine_unorm"] = clearedImage("A2B10G10R10_UNORM_PACK32", {0, 1, 0.5, 1});
    g["resources"]["fine_snorm"] = clearedImage("R8G8B8A8_SNORM", {-1, 1, 0, 1});
    g["resources"]["fine_half"] = clearedImage("R16_SFLOAT", {-65504, 65504, 0, 1});
    g["resources"]["past_single"] = clearedImage("R32_SFLOAT", {0, 3.4028236e38, 0, 1});
    // FLT_MAX as printed to 9 digits: a little more, and stored as a float it is FLT_MAX.
    g["resources"]["fine_single"] = clearedImage("R32G32B32A32_SFLOAT", {-3.4028235e38, 3.4028235e38, 1e30, 1});
    g["resources"]["fine_ufloat"] = clearedImage("B10G11R11_UFLOAT_PACK32", {64512, 0, 0, 1});
    g["resources"]["fine_shared"] = clearedImage("E5B9G9R9_UFLOAT_PACK32", {65408, 0, 0, 1});
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.unorm.clear.color", "", "unorm",
                        {"expected four numbers in [0, 1], the range of the format R8G8B8A8_UNORM (a clear would not "
                         "write any other value as given), got [0,0,1.5,1]"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.srgb.clear.color", "", "srgb", {"[0, 1]", "B8G8R8A8_SRGB"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.snorm.clear.color", "", "snorm", {"[-1, 1]", "R8G8B8A8_SNORM"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.half.clear.color", "", "half", {"[-65504, 65504]", "R16G16B16A16_SFLOAT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.single.clear.color", "", "single",
                        {"[-3.40282357e+38, 3.40282357e+38]", "R32_SFLOAT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.ufloat.clear.color", "", "ufloat", {"[0, 64512]", "B10G11R11_UFLOAT_PACK32"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.past_single.clear.color", "", "past_single", {"R32_SFLOAT"})) << listAll(ds);
    EXPECT_EQ(ds.size(), 7u) << listAll(ds);
}

TEST(LoaderErrors, UnknownFeatureOverrideInCompileOptions) {
    CompileOptions options;
    options.features["bloom"] = true;
    const auto ds = compileErrors(baseGraph(), options);
    EXPECT_TRUE(hasDiag(ds, "features", "", "", {"unknown feature 'bloom'", "geo", "sky"}));
}

// A presented image is a swapchain's: a 2D colour image of one mip, and one per plan. A file
// is told so at the image's `final`; options that would make such a plan (a GraphDesc built in
// code is checked the same way) are named at the resource.
TEST(LoaderErrors, APlanPresentsOneImageOfASwapchainsShape) {
    Json g = baseGraph();
    const auto presented = [](Json image) {
        image["external"] = true;
        image["final"] = "Present";
        return image;
    };
    g["resources"]["depth_shown"] = presented({{"type", "image2d"}, {"format", "D32_SFLOAT"}, {"extent", "output"}});
    g["resources"]["cube_shown"] =
        presented({{"type", "cube"}, {"format", "B8G8R8A8_UNORM"}, {"extent", {64, 64}}});
    g["resources"]["layers_shown"] =
        presented({{"type", "image2d_array"}, {"format", "B8G8R8A8_UNORM"}, {"extent", "output"}, {"layers", 2}});
    g["resources"]["mips_shown"] =
        presented({{"type", "image2d"}, {"format", "B8G8R8A8_UNORM"}, {"extent", {64, 64}}, {"mips", "full"}});
    Json uses = Json::object();
    for (const char* name : {"depth_shown", "cube_shown", "layers_shown", "mips_shown"})
        uses[name] = std::string(name) == "depth_shown" ? "Write@DepthAttachment" : "Write@Compute";
    g = withGeneric(g, "shows", uses);
    const auto ds = loadErrors(g);
    const std::string shape = "a presented image is a swapchain's: an image2d of a color format with one mip, not ";
    EXPECT_TRUE(hasDiag(ds, "resources.depth_shown.final", "", "depth_shown", {shape + "of the depth format D32_SFLOAT"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.cube_shown.final", "", "cube_shown", {shape + "a cube"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.layers_shown.final", "", "layers_shown", {shape + "an image2d_array"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.mips_shown.final", "", "mips_shown", {shape + "of the full mip chain"}))
        << listAll(ds);

    Json valid = withGeneric(baseGraph(), "reads", {{"mipped", "Read@Fragment"}});
    // It arrives as it would be presented: exported so, the next frame finds it as it arrived.
    valid["resources"]["plain"] = {{"type", "image2d"}, {"format", "B8G8R8A8_UNORM"}, {"extent", "output"}, {"external", true},
                                   {"initial", "Present"}};
    valid["passes"].back()["uses"]["plain"] = "Read@Fragment";
    CompileOptions mips;
    mips.exports["mipped"] = ExternalState::Present;
    EXPECT_TRUE(hasDiag(compileErrors(valid, mips), "resources.mipped", "", "mipped", {shape + "of 3 mips"}));
    // Two presented images in one plan; a file may declare both for passes that features
    // choose between (graphs/raster.json's compute tonemap), and then compiles.
    const std::string both = "a frame presents one image, and passes of this plan also use the presented image ";
    CompileOptions second;
    second.exports["plain"] = ExternalState::Present;
    EXPECT_TRUE(hasDiag(compileErrors(valid, second), "resources.plain.final", "", "plain", {both + "'swapchain'"}));
    Json twice = withGeneric(baseGraph(), "shows", {{"second", "Write@Compute"}});
    twice["resources"]["second"] = presented({{"type", "image2d"}, {"format", "B8G8R8A8_UNORM"}, {"extent", "output"}});
    twice["passes"].back()["if"] = "sky";
    EXPECT_TRUE(hasDiag(compileErrors(twice, CompileOptions{}), "resources.second.final", "", "second",
                        {both + "'swapchain'"}));
    CompileOptions skyOff;
    skyOff.features["sky"] = false;
    EXPECT_NO_THROW((void)compile(parseGraph(twice.dump(), kFile, registry()), skyOff));
    // Built in code, a presented (external) image with a clear is told it is not cleared, as
    // the loader tells a file.
    GraphDesc coded = parseGraph(baseGraph().dump(), kFile, registry());
    for (ResourceDesc& r : coded.resources)
        if (r.name == "swapchain") r.clear = ClearValue{.isDepth = true};
    try {
        (void)compile(coded, CompileOptions{});
        ADD_FAILURE() << "expected a GraphError";
    } catch (const GraphError& e) {
        EXPECT_TRUE(hasDiag(e.diagnostics().items(), "resources.swapchain", "", "swapchain",
                            {"an external resource arrives with contents; it is not cleared"}))
            << e.what();
    }
    // A plan compiled to run headless presents neither: both are outputs read like any other.
    CompileOptions headless;
    headless.presentReplacement = ExternalState::TransferSrc;
    EXPECT_NO_THROW((void)compile(parseGraph(twice.dump(), kFile, registry()), headless));
}

// Options that would give a plan the loader never lets a file give: a presented image ending
// in UNDEFINED, a transient or a buffer presented, and outputs that cull every pass.
TEST(LoaderErrors, CompileOptionsThatWouldMakeAnInvalidPlan) {
    CompileOptions none;
    none.presentReplacement = ExternalState::None;
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), none), "", "", "", {"presentReplacement must be a state", "not None"}));
    CompileOptions transient;
    transient.exports["hdr_color"] = ExternalState::Present;
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), transient), "resources.hdr_color", "", "hdr_color",
                        {"only an external image (the swapchain's) can be presented"}));
    CompileOptions buffer;
    buffer.exports["buf"] = ExternalState::TransferSrc;
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), buffer), "resources.buf", "", "buf",
                        {"a buffer cannot start or end as Present or TransferSrc"}));
    CompileOptions outputs;
    outputs.outputs = std::set<std::string, std::less<>>{"hdr_color"};
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), outputs), "resources.hdr_color", "", "hdr_color",
                        {"cannot keep 'hdr_color' as an output: it is not exported"}));
    // An export in state None exported nothing, and outputs naming it culled every pass.
    CompileOptions exportNone;
    exportNone.exports["hdr_color"] = ExternalState::None;
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), exportNone), "resources.hdr_color", "", "hdr_color",
                        {"cannot export 'hdr_color' in state None"}));
    exportNone.outputs = std::set<std::string, std::less<>>{"hdr_color"};
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), exportNone), "resources.hdr_color", "", "hdr_color",
                        {"cannot export 'hdr_color' in state None"}));
    CompileOptions huge;
    huge.outputWidth = 16385;
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), huge), "", "", "", {"the output extent 16385x1080 is past 16384 a side"}));
    huge.outputWidth = 0xffffffffu;  // whose images' byte counts wrapped
    EXPECT_TRUE(hasDiag(compileErrors(baseGraph(), huge), "", "", "", {"is past 16384 a side"}));
    outputs.exports["hdr_color"] = ExternalState::TransferSrc;
    EXPECT_NO_THROW((void)compile(parseGraph(baseGraph().dump(2), kFile, registry()), outputs))
        << "exported by the options, it is an output";
}

// A list of names to choose from that is empty says so, rather than ending in "declared: ".
TEST(LoaderErrors, AnEmptyListOfDeclaredNamesSaysNone) {
    Json g = baseGraph();
    g["resources"] = Json::object();
    EXPECT_TRUE(hasDiag(loadErrors(g), "passes[0].uses.depth", "forward", "depth", {"unknown resource; declared: none"}))
        << listAll(loadErrors(g));
}

// A feature refused for its name has its own error and is not offered as a declared one.
TEST(LoaderErrors, ARefusedFeatureIsNotListedAsDeclared) {
    Json g = baseGraph();
    g["features"]["bad name"] = true;
    g["passes"][1]["if"] = "skyy";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, R"(features["bad name"])", "", "", {"is not a valid feature name"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[1].if", "tonemap", "", {"unknown feature 'skyy'; the file declares: "}))
        << listAll(ds);
    for (const auto& d : ds) {
        if (d.message.find("unknown feature") != std::string::npos) {
            EXPECT_EQ(d.message.find("bad name"), std::string::npos) << d.message;
        }
    }
}

// nlohmann's message shows the bytes it read last; one that is not UTF-8 is escaped, as control
// characters are, rather than written raw to the terminal or the log.
TEST(LoaderErrors, BytesThatAreNotUtf8AreShownEscaped) {
    const auto ds = textErrors("{\"version\": 1, \"name\": \"t\xff\"}");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_NE(ds[0].message.find("ill-formed UTF-8 byte; last read: '\"t\\xff'"), std::string::npos) << ds[0].message;
    EXPECT_EQ(ds[0].message.find('\xff'), std::string::npos) << "no raw byte";
}

TEST(LoaderErrors, AbsurdExtents) {
    const std::vector<std::pair<Json, std::string_view>> cases{
        {Json::array({0, 16}), "outside 1..16384"},
        {Json::array({16, 0}), "outside 1..16384"},
        {Json::array({-4, 16}), "outside 1..16384"},
        {Json::array({100000, 100000}), "outside 1..16384"},
        {Json::array({16384, 16385}), "outside 1..16384"},
        // Named as written, not as the 64-bit integer it wraps to (it said [-1, 32]).
        {Json::array({18446744073709551615ull, 32}), "[18446744073709551615, 32] is outside 1..16384"},
        {"output/0", "between 1 and 4096"},
        {"output/5000", "between 1 and 4096"},
        {"output/", "\"output\", \"output/N\" or [width, height]"},
        {"output/-2", "\"output\", \"output/N\" or [width, height]"},
        {"output/99999999999999", "\"output\", \"output/N\" or [width, height]"},
        {"input", "\"output\", \"output/N\" or [width, height]"},
        {Json::array({16}), "[width, height]"},
        {Json::array({16.5, 16}), "[width, height]"},
        {Json{{"w", 1}}, "[width, height]"},
    };
    for (const auto& [extent, words] : cases) {
        Json g = baseGraph();
        g["resources"]["hdr_color"]["extent"] = extent;
        EXPECT_TRUE(hasDiag(loadErrors(g), "resources.hdr_color.extent", "", "hdr_color", {words}))
            << "extent " << extent.dump();
    }
    Json g = baseGraph();
    g["resources"]["hdr_color"].erase("extent");
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.hdr_color.extent", "", "hdr_color", {"missing"}));
    g["resources"]["hdr_color"]["extent"] = Json::array({16384, 1});
    expectLoads(g);
    g["resources"]["hdr_color"]["extent"] = "output/4096";
    expectLoads(g);
    // Cube faces are square.
    g = baseGraph();
    g["resources"]["cube"]["extent"] = Json::array({64, 32});
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.cube.extent", "", "cube", {"square"}));
    g["resources"]["cube"]["extent"] = "output/2";
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.cube.extent", "", "cube", {"square", "[n, n]"}));
}

TEST(LoaderErrors, AbsurdMipCounts) {
    const std::vector<std::pair<Json, std::string_view>> cases{
        {0, "between 1 and 15, got 0"},
        {99, "between 1 and 15, got 99"},
        {-1, "between 1 and 15"},
        {"half", "\"full\""},
        {2.5, "between 1 and 15"},
    };
    for (const auto& [mips, words] : cases) {
        Json g = baseGraph();
        g["resources"]["mipped"]["mips"] = mips;
        EXPECT_TRUE(hasDiag(loadErrors(g), "resources.mipped.mips", "", "mipped", {words})) << mips.dump();
    }
    // A 64x64 image has 7 levels (64, 32, ..., 1).
    Json g = baseGraph();
    g["resources"]["mipped"]["mips"] = 8;
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.mipped.mips", "", "mipped", {"8 levels", "64x64"}));
    g["resources"]["mipped"]["extent"] = Json::array({64, 3});
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.mipped.mips", "", "mipped", {"8 levels", "64x3"}));
    g["resources"]["mipped"]["mips"] = 7;
    expectLoads(g);
    g["resources"]["mipped"]["mips"] = "full";
    expectLoads(g);
}

TEST(LoaderErrors, MipCountsOfOutputSizedImagesAreCheckedAtCompile) {
    // "output/2" at 1920x1080 is 960x540: 10 levels. The loader cannot know the output size.
    Json g = baseGraph();
    g["resources"]["hdr_color"]["extent"] = "output/2";
    g["resources"]["hdr_color"]["mips"] = 11;
    g["resources"]["depth"]["extent"] = "output/2";  // forward's attachments share a size
    g["passes"][0]["uses"] = Json::array(
        {{{"resource", "depth"}, {"access", "Write"}, {"stage", "DepthAttachment"}},
         {{"resource", "hdr_color"}, {"access", "Write"}, {"stage", "ColorAttachment"}, {"mips", {0, 1}}}});
    g["passes"][1]["uses"] = Json::array(
        {{{"resource", "hdr_color"}, {"access", "Read"}, {"stage", "Fragment"}, {"mips", {0, 1}}},
         {{"resource", "swapchain"}, {"access", "Write"}, {"stage", "ColorAttachment"}}});
    expectLoads(g);
    CompileOptions options;
    const auto ds = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color.mips", "", "hdr_color", {"11 levels", "960x540", "1920x1080"}));
    options.outputWidth = 3840;
    options.outputHeight = 2160;
    EXPECT_NO_THROW((void)compile(parseGraph(g.dump(), kFile, registry()), options));
}

TEST(LoaderErrors, AbsurdLayerCounts) {
    Json g = baseGraph();
    g["resources"]["arr"] = Json::parse(
        R"({ "type": "image2d_array", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "layers": 0 })");
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.arr.layers", "", "arr", {"between 1 and 2048", "got 0"}));
    g["resources"]["arr"]["layers"] = 5000;
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.arr.layers", "", "arr", {"between 1 and 2048", "got 5000"}));
    g["resources"]["arr"]["layers"] = "many";
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.arr.layers", "", "arr", {"between 1 and 2048"}));
    g = baseGraph();
    g["resources"]["cube"]["layers"] = 5;
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.cube.layers", "", "cube", {"a cube has 6 layers"}));
    g = baseGraph();
    g["resources"]["mipped"]["layers"] = 2;
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.mipped.layers", "", "mipped", {"image2d_array"}));
}

TEST(LoaderErrors, AbsurdBufferSizes) {
    const std::vector<Json> sizes{0, -16, 1.5, "1k", Json::number_unsigned_t(1) << 40,
                                  Json::number_unsigned_t(18446744073709551615ull)};
    for (const auto& size : sizes) {
        Json g = baseGraph();
        g["resources"]["buf"]["size"] = size;
        EXPECT_TRUE(hasDiag(loadErrors(g), "resources.buf.size", "", "buf", {"between 1 and 2 GiB"})) << size.dump();
    }
    Json g = baseGraph();
    g["resources"]["buf"].erase("size");
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.buf.size", "", "buf", {"missing; buffers need a size in bytes"}));
    // A whole number written with a fraction is not taken as an integer (the schema cannot
    // tell): the message says so, where it said only the range the value is in.
    g["resources"]["buf"]["size"] = 256.0;
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.buf.size", "", "buf", {"got 256.0 (write it as an integer)"}));
    g["resources"]["buf"]["size"] = 1.5;
    EXPECT_FALSE(hasDiag(loadErrors(g), "resources.buf.size", "", "buf", {"write it as an integer"}));
    // Digits alone from 2^64 on are read as a float: the range is the problem, not the writing.
    const auto huge = textErrors(R"({"version": 1, "name": "t", "resources": {"buf": {"type": "buffer",
                                    "size": 99999999999999999999999}}, "passes": []})");
    ASSERT_FALSE(huge.empty());
    EXPECT_NE(huge[0].message.find("between 1 and 2 GiB"), std::string::npos) << huge[0].message;
    EXPECT_EQ(huge[0].message.find("write it as an integer"), std::string::npos) << huge[0].message;
    Json extent = baseGraph();
    extent["resources"]["hdr_color"]["extent"] = Json::array({16.0, 16});
    EXPECT_TRUE(hasDiag(loadErrors(extent), "resources.hdr_color.extent", "", "hdr_color",
                        {"got [16.0,16] (write it as an integer)"}));
    g["resources"]["buf"]["size"] = 1;
    g["resources"]["buf"]["extent"] = "output";
    EXPECT_TRUE(hasDiag(loadErrors(g), "resources.buf.extent", "", "buf", {"buffers have no extent"}));
}

// Every integer the loader or a pass type's params want gets the hint, not only the resource
// keys': a stencil value, a usage's range, a count in params.
TEST(LoaderErrors, WholeNumbersWithAFractionAreHintedWhereverAnIntegerIsWanted) {
    Json g = baseGraph();
    g["resources"]["ds"] = Json::parse(R"({"type": "image2d", "format": "D32_SFLOAT_S8_UINT", "extent": "output",
                                           "clear": {"depth": 0, "stencil": 1.0}})");
    g["resources"]["ids"] = Json::parse(R"({"type": "image2d", "format": "R32_UINT", "extent": [4, 4], "external": true,
                                            "clear": {"color": [7, 0, 0, 1.0]}})");
    g = withGeneric(g, "reader", Json::array({Json{{"resource", "mipped"}, {"access", "Read"}, {"stage", "Compute"},
                                                   {"mips", Json::array({0, 1.0})}}}));
    g["passes"].push_back(Json{{"name", "trace"}, {"type", "PathTracePass"}, {"uses", {{"buf", "Read@Compute"}}},
                               {"params", {{"samples_per_frame", 4.0}, {"max_bounces", 2.5}}}});
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "resources.ds.clear.stencil", "", "ds", {"got 1.0 (write it as an integer)"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "resources.ids.clear.color", "", "ids", {"got [7,0,0,1.0] (write it as an integer)"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[0].mips", "reader", "mipped", {"got [0,1.0] (write it as an integer)"}))
        << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[3].params.samples_per_frame", "trace", "", {"got 4.0 (write it as an integer)"}))
        << listAll(ds);
    // Not whole, or not every element whole, or an array where a number is wanted: the value is
    // wrong, not its writing.
    EXPECT_TRUE(hasDiag(ds, "passes[3].params.max_bounces", "trace", "", {"got 2.5"})) << listAll(ds);
    EXPECT_FALSE(hasDiag(ds, "passes[3].params.max_bounces", "trace", "", {"write it as an integer"}));
    g = baseGraph();
    g["resources"]["ids"] = Json::parse(R"({"type": "image2d", "format": "R32_UINT", "extent": [4.5, 4.0],
                                            "external": true, "clear": {"color": [0.5, 0, 0, 1.0]}})");
    g["resources"]["buf"]["size"] = Json::array({64.0});
    g["resources"]["ds"] = Json::parse(R"({"type": "image2d", "format": "D32_SFLOAT_S8_UINT", "extent": "output",
                                           "clear": {"depth": 0, "stencil": 300.0}})");
    g["passes"].push_back(Json{{"name", "trace"}, {"type", "PathTracePass"}, {"uses", {{"buf", "Read@Compute"}}},
                               {"params", {{"samples_per_frame", 1e6}}}});
    const auto wrong = loadErrors(g);
    EXPECT_TRUE(hasDiag(wrong, "resources.ds.clear.stencil", "", "ds", {"got 300.0"})) << listAll(wrong);
    EXPECT_TRUE(hasDiag(wrong, "passes[2].params.samples_per_frame", "trace", "", {"got 1000000.0"})) << listAll(wrong);
    EXPECT_TRUE(hasDiag(wrong, "resources.ids.clear.color", "", "ids", {"got [0.5,0,0,1.0]"})) << listAll(wrong);
    EXPECT_TRUE(hasDiag(wrong, "resources.ids.extent", "", "ids", {"got [4.5,4.0]"})) << listAll(wrong);
    EXPECT_TRUE(hasDiag(wrong, "resources.buf.size", "", "buf", {"got [64.0]"})) << listAll(wrong);
    for (const Diagnostic& d : wrong) EXPECT_EQ(d.message.find("write it as an integer"), std::string::npos) << d.format();
}

TEST(LoaderErrors, UsageRangesOutOfBounds) {
    auto usage = [](const char* res, Json mips, Json layers) {
        Json u{{"resource", res}, {"access", "Read"}, {"stage", "Compute"}};
        if (!mips.is_null()) u["mips"] = std::move(mips);
        if (!layers.is_null()) u["layers"] = std::move(layers);
        return u;
    };
    // mipped has 3 levels, cube 6 layers and a full chain of a 64x64 face (7 levels).
    const std::vector<std::tuple<Json, std::string, std::string_view>> cases{
        {usage("mipped", {3, 1}, nullptr), "mipped", "exceed the resource's 3 mip levels"},
        {usage("mipped", {1, 3}, nullptr), "mipped", "exceed the resource's 3 mip levels"},
        {usage("mipped", {0, 0}, nullptr), "mipped", "count >= 1"},
        {usage("mipped", {-1, 1}, nullptr), "mipped", "[first, count]"},
        {usage("mipped", {0}, nullptr), "mipped", "[first, count]"},
        {usage("mipped", {4294967295u, 1}, nullptr), "mipped", "[4294967295,1] is past any image's mip levels (at most 15)"},
        {usage("mipped", {3000, 1}, nullptr), "mipped", "[3000,1] is past any image's mip levels (at most 15)"},
        {usage("cube", nullptr, {0, 5000}), "cube", "[0,5000] is past any image's layers (at most 2048)"},
        {usage("cube", nullptr, {5, 2}), "cube", "exceed the resource's 6 layers"},
        {usage("cube", nullptr, {6, 1}), "cube", "exceed the resource's 6 layers"},
        {usage("cube", {7, 1}, nullptr), "cube", "7 mip levels"},
        {usage("cube", {0, 8}, nullptr), "cube", "7 mip levels"},
        {usage("buf", {0, 1}, nullptr), "buf", "buffers have no mips"},
        {usage("buf", nullptr, {0, 1}), "buf", "buffers have no layers"},
    };
    for (const auto& [u, res, words] : cases) {
        Json g = withGeneric(baseGraph(), "gen", Json::array({u}));
        // The error points at the key it is about.
        const std::string path = std::string("passes[2].uses[0].") + (u.contains("mips") ? "mips" : "layers");
        EXPECT_TRUE(hasDiag(loadErrors(g), path, "gen", res, {words})) << u.dump();
    }
    // The last level of each is fine.
    Json g = withGeneric(baseGraph(), "gen",
                         Json::array({usage("mipped", {2, 1}, nullptr), usage("cube", {6, 1}, {5, 1})}));
    expectLoads(g);
}

TEST(LoaderErrors, LayersOnlyRangeCoversEveryMipOfAFullChain) {
    // Giving only "layers" leaves the mips whole, also for a "full" chain: a writer of every
    // face makes the whole cube readable.
    Json g = baseGraph();
    g["resources"]["fullcube"] = Json::parse(
        R"({ "type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "mips": "full" })");
    g["resources"]["fullsky"] = Json::parse(
        R"({ "type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": "output/4", "mips": "full", "layers": 6 })");
    g = withGeneric(g, "w", Json::array({{{"resource", "fullcube"}, {"access", "Write"}, {"stage", "Compute"},
                                          {"layers", {0, 6}}},
                                         {{"resource", "fullsky"}, {"access", "Write"}, {"stage", "Compute"},
                                          {"layers", {0, 6}}}}));
    g = withGeneric(g, "r", Json{{"fullcube", "Read@Fragment"}, {"fullsky", "Read@Fragment"}});
    const GraphDesc graph = parseGraph(g.dump(), kFile, registry());
    const UsageDecl& fixed = graph.passes[2].uses[0];
    ASSERT_TRUE(fixed.usage.range.has_value());
    EXPECT_EQ(fixed.usage.range->baseMip, 0u);
    EXPECT_EQ(fixed.usage.range->mipCount, 7u);  // 64, 32, ..., 1
    EXPECT_EQ(fixed.usage.range->layerCount, 6u);
    const Plan plan = compile(graph);  // 1920x1080: "output/4" is 480x270, 9 levels
    const int32_t sky = plan.resourceIndex("fullsky");
    ASSERT_GE(sky, 0);
    bool seen = false;
    for (const auto& p : plan.passes())
        for (const auto& u : p.usages)
            if (p.name == "w" && u.resource == static_cast<uint32_t>(sky)) {
                seen = true;
                EXPECT_EQ(u.range.mipCount, 9u);
                EXPECT_EQ(u.range.layerCount, 6u);
            }
    EXPECT_TRUE(seen);
}

TEST(LoaderErrors, OverlappingUsagesOfOneResourceInOnePass) {
    auto usage = [](const char* access, Json mips) {
        return Json{{"resource", "mipped"}, {"access", access}, {"stage", "Compute"}, {"mips", std::move(mips)}};
    };
    Json g = withGeneric(baseGraph(), "gen", Json::array({usage("Read", {0, 2}), usage("Write", {1, 2})}));
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "gen", "mipped", {"overlaps passes[2].uses[0]"}));
    // Whole resource twice.
    g = withGeneric(baseGraph(), "gen",
                    Json::array({{{"resource", "buf"}, {"access", "Read"}, {"stage", "Compute"}},
                                 {{"resource", "buf"}, {"access", "Read"}, {"stage", "Vertex"}}}));
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "gen", "buf", {"overlaps passes[2].uses[0]"}));
    // A level range against a whole full-chain resource.
    g = withGeneric(baseGraph(), "gen",
                    Json::array({{{"resource", "cube"}, {"access", "Read"}, {"stage", "Compute"}},
                                 {{"resource", "cube"}, {"access", "Write"}, {"stage", "Compute"},
                                  {"mips", {5, 1}}}}));
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "gen", "cube", {"overlaps passes[2].uses[0]"}));
    // Disjoint levels are fine: mip generation reads one level and writes the next.
    g = withGeneric(baseGraph(), "gen", Json::array({usage("Read", {0, 1}), usage("Write", {1, 1})}));
    expectLoads(g);
}

// One subpass holds one depth attachment and, on every current GPU, at most 8 colour ones: a
// pass past either is refused where it is written, not when a device builds its render pass.
TEST(LoaderErrors, APassRendersToOneDepthAndAtMostEightColourAttachments) {
    Json g = baseGraph();
    Json eight = Json::object(), nine;
    for (int i = 0; i < 9; ++i) {
        const std::string name = "target" + std::to_string(i);
        g["resources"][name] = Json{{"type", "image2d"}, {"format", "R8G8B8A8_UNORM"}, {"extent", "output"}};
        (i < 8 ? eight : nine)[name] = "Write@ColorAttachment";
    }
    nine.update(eight);
    Json d2 = g;
    expectLoads(withGeneric(g, "mrt", eight));
    auto ds = loadErrors(withGeneric(g, "mrt", nine));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.target8", "mrt", "target8",
                        {"at most 8 colour attachments", "this is its 9th"}));
    EXPECT_EQ(ds.size(), 1u);
    d2["resources"]["depth2"] = Json{{"type", "image2d"}, {"format", "D16_UNORM"}, {"extent", "output"}};
    ds = loadErrors(withGeneric(d2, "both", Json{{"depth", "Write@DepthAttachment"}, {"depth2", "Write@DepthAttachment"}}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.depth2", "both", "depth2",
                        {"one depth attachment", "passes[2].uses.depth is its depth attachment"}));
}

// Generic draws one triangle and touches a word of each buffer a shader binds: buffers too
// small for that, and a second index or indirect buffer, are refused at the usage (before,
// the renderer refused them with neither file nor path).
TEST(LoaderErrors, GenericRefusesBuffersItCannotDrawWith) {
    Json g = baseGraph();
    const auto buffer = [](int bytes) { return Json{{"type", "buffer"}, {"size", bytes}, {"external", true}}; };
    g["resources"]["ib"] = buffer(8);
    g["resources"]["ib2"] = buffer(12);
    g["resources"]["args"] = buffer(16);
    g["resources"]["word"] = buffer(3);
    const auto index = [](const char* resource) {
        return Json{{"resource", resource}, {"access", "Read"}, {"stage", "VertexInput"}, {"as", "index"}};
    };
    Json uses = Json::array();
    uses.push_back(Json{{"resource", "hdr_color"}, {"access", "Write"}, {"stage", "ColorAttachment"}});
    uses.push_back(index("ib"));
    uses.push_back(index("ib2"));
    uses.push_back(Json{{"resource", "args"}, {"access", "Read"}, {"stage", "Indirect"}});
    uses.push_back(Json{{"resource", "word"}, {"access", "Read"}, {"stage", "Fragment"}});
    auto ds = loadErrors(withGeneric(g, "draw", uses));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[1]", "draw", "ib", {"12 bytes of an index buffer", "'ib' has 8"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[2]", "draw", "ib2", {"one index buffer, and 'ib' is already this pass's index buffer"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[3]", "draw", "args", {"20 bytes of an indirect buffer", "has 16"})) << listAll(ds);
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses[4]", "draw", "word", {"4 bytes of a buffer a shader binds"})) << listAll(ds);
    EXPECT_EQ(ds.size(), 4u) << listAll(ds);
    g["resources"]["ib"] = buffer(12);
    g["resources"]["args"] = buffer(20);
    g["resources"]["word"] = buffer(4);
    uses.erase(2);
    expectLoads(withGeneric(g, "draw", uses));
}

TEST(LoaderErrors, BadParams) {
    Json g = baseGraph();
    g["passes"][1]["params"]["operator"] = "foo";
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].params.operator", "tonemap", "",
                        {"\"foo\"", "aces_narkowicz", "khronos_pbr_neutral"}));
    g = baseGraph();
    g["passes"][1]["params"]["exposure_ev"] = 1000;
    g["passes"][1]["params"]["gamma"] = 2.2;
    ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].params.exposure_ev", "tonemap", "", {"[-64", "1000"}));
    EXPECT_TRUE(hasDiag(ds, "passes[1].params.gamma", "tonemap", "", {"unknown parameter", "operator"}));
    g = baseGraph();
    g["passes"][1]["params"]["exposure.ev"] = 1;
    EXPECT_TRUE(hasDiag(loadErrors(g), R"(passes[1].params["exposure.ev"])", "tonemap", "", {"unknown parameter"}));
    g = baseGraph();
    g["passes"][1]["params"] = "aces";
    EXPECT_TRUE(hasDiag(loadErrors(g), "passes[1].params", "tonemap", "", {"expected an object"}));
}

TEST(LoaderErrors, MissingRequiredSlot) {
    Json g = baseGraph();
    g["passes"][1]["uses"].erase("swapchain");
    g["resources"].erase("swapchain");
    g["resources"]["hdr_color"]["final"] = "ShaderRead";
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses", "tonemap", "",
                        {"TonemappingPass needs slot 'output'", "Write@ColorAttachment"}));
    EXPECT_EQ(ds.size(), 1u) << listAll(ds);
}

TEST(LoaderErrors, MissingOrMistypedRequiredFields) {
    Json g = baseGraph();
    g.erase("version");
    g["passes"][1].erase("uses");
    g["passes"][0].erase("type");
    g["passes"][0]["name"] = "";
    auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "version", "", "", {"version 1"}));
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses", "tonemap", "", {"missing"}));
    EXPECT_TRUE(hasDiag(ds, "passes[0].type", "", "", {"missing"}));
    EXPECT_TRUE(hasDiag(ds, "passes[0].name", "", "", {"non-empty string"}));
    g = baseGraph();
    g["version"] = 2;
    EXPECT_TRUE(hasDiag(loadErrors(g), "version", "", "", {"unsupported version 2"}));
    EXPECT_TRUE(hasDiag(textErrors("[1, 2]"), "", "", "", {"JSON object"}));
}

TEST(LoaderErrors, SeveralErrorsAreAllReported) {
    Json g = baseGraph();
    g["bogus"] = 1;                                                   // unknown key
    g["resources"]["hdr_color"]["format"] = "RGBA16F";                // unknown format
    g["resources"]["mipped"]["mips"] = 0;                             // absurd mips
    g["passes"][0]["if"] = "geo &&";                                  // bad expression
    g["passes"][1]["type"] = "TonemapPass";                           // unknown type
    g["passes"][1]["uses"]["swapchan"] = "Write@ColorAttachment";     // unknown resource
    g = withGeneric(g, "forward", Json{{"depth", "Read@ColorAttachment"}});  // dup name + depth as color
    const auto ds = loadErrors(g);
    EXPECT_TRUE(hasDiag(ds, "bogus", "", "", {"unknown key"}));
    EXPECT_TRUE(hasDiag(ds, "resources.hdr_color.format", "", "hdr_color", {"RGBA16F"}));
    EXPECT_TRUE(hasDiag(ds, "resources.mipped.mips", "", "mipped", {"got 0"}));
    EXPECT_TRUE(hasDiag(ds, "passes[0].if", "forward", "", {"column 7"}));
    EXPECT_TRUE(hasDiag(ds, "passes[1].type", "tonemap", "", {"TonemapPass"}));
    EXPECT_TRUE(hasDiag(ds, "passes[1].uses.swapchan", "tonemap", "swapchan", {"unknown resource"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].name", "forward", "", {"duplicate pass name"}));
    EXPECT_TRUE(hasDiag(ds, "passes[2].uses.depth", "forward", "depth", {"cannot be a color attachment"}));
    EXPECT_EQ(ds.size(), 8u) << listAll(ds);
}

TEST(LoaderErrors, SeveralCompileErrorsAreAllReported) {
    Json g = baseGraph();
    g["passes"][0]["uses"] = Json{{"depth", "Write@DepthAttachment"}, {"hdr_color", "Write@ColorAttachment"}};
    g["passes"].push_back(Json::parse(R"({ "name": "post", "type": "Generic",
        "uses": { "hdr_color": "Read@Compute", "mipped": "Write@Compute" } })"));
    CompileOptions options;
    options.features = {{"geo", false}, {"bloom", true}, {"dof", false}};
    const auto ds = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(ds, "features", "", "", {"'bloom'"}));
    EXPECT_TRUE(hasDiag(ds, "features", "", "", {"'dof'"}));
    // Unknown overrides are reported first; the reads are checked once the features are valid.
    options.features = {{"geo", false}};
    const auto reads = compileErrors(g, options);
    EXPECT_TRUE(hasDiag(reads, "passes[1].uses.hdr_color", "tonemap", "hdr_color", {"'forward'"}));
    EXPECT_TRUE(hasDiag(reads, "passes[2].uses.hdr_color", "post", "hdr_color", {"'forward'"}));
    EXPECT_EQ(reads.size(), 2u) << listAll(reads);
}

TEST(LoaderErrors, FileErrorsNameTheFile) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("skygraph_loader_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::create_directories(dir);
    const fs::path file = dir / "broken.json";
    {
        Json g = baseGraph();
        g["passes"][1]["params"]["operator"] = "foo";
        std::ofstream(file) << g.dump(2);
    }
    try {
        (void)loadGraphFile(file, registry());
        ADD_FAILURE() << "expected GraphError";
    } catch (const GraphError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u);
        const Diagnostic& d = e.diagnostics().items()[0];
        EXPECT_EQ(d.file, file.string());
        EXPECT_EQ(d.jsonPath, "passes[1].params.operator");
        EXPECT_EQ(d.format().rfind(file.string() + ": passes[1].params.operator: pass 'tonemap': ", 0), 0u)
            << d.format();
    }
    try {
        (void)loadGraphFile(dir / "missing.json", registry());
        ADD_FAILURE() << "expected GraphError";
    } catch (const GraphError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u);
        EXPECT_EQ(e.diagnostics().items()[0].file, (dir / "missing.json").string());
        EXPECT_NE(e.diagnostics().items()[0].message.find("cannot open"), std::string::npos);
    }
    fs::remove_all(dir);
}

TEST(LoaderErrors, DiagnosticFormatNamesEverything) {
    Json g = baseGraph();
    g["passes"][0]["uses"]["depth"] = "Write@ColorAttachment";
    for (const auto& d : loadErrors(g)) {
        if (d.jsonPath != "passes[0].uses.depth") continue;
        EXPECT_EQ(d.format().rfind("test.json: passes[0].uses.depth: pass 'forward', resource 'depth': ", 0), 0u)
            << d.format();
        return;
    }
    ADD_FAILURE() << "no diagnostic for passes[0].uses.depth";
}

// ---- JSON nesting and positions (json_positions) ----------------------------------------

TEST(JsonPositions, DeepNestingIsRefusedNotFatal) {
    // Balanced: parses, but the depth limit turns it into an error.
    const std::string balanced = std::string(100000, '[') + std::string(100000, ']');
    JsonParseResult r = parseJsonWithPositions(balanced);
    EXPECT_NE(r.error.find("nesting deeper than 256"), std::string::npos) << r.error;
    EXPECT_EQ(r.line, 1);
    EXPECT_EQ(r.column, 257);  // the bracket that opens level 257
    // Through the loader, inside a graph.
    const std::string prefix = R"({ "version": 1, "name": "t", "resources": {},
  "passes": )";
    auto ds = textErrors(prefix + balanced + "}");
    ASSERT_EQ(ds.size(), 1u) << listAll(ds);
    EXPECT_NE(ds[0].message.find("nesting deeper than 256"), std::string::npos) << ds[0].message;
    EXPECT_EQ(ds[0].jsonPath.rfind("passes[0][0]", 0), 0u) << ds[0].jsonPath;
    EXPECT_EQ(ds[0].line, 2);
    EXPECT_EQ(ds[0].column, 268);  // 12 characters of "  \"passes\": ", then 255 brackets (the root is level 1)
    // Unbalanced: refused at the same place, without reading on to the end.
    ds = textErrors(std::string(100000, '['));
    ASSERT_EQ(ds.size(), 1u);
    EXPECT_NE(ds[0].message.find("nesting deeper than 256"), std::string::npos) << ds[0].message;
    EXPECT_EQ(ds[0].line, 1);
    EXPECT_EQ(ds[0].column, 257);
    // Brackets inside strings do not count.
    r = parseJsonWithPositions("[\"" + std::string(1000, '[') + "\"]");
    EXPECT_EQ(r.error, "");
    // Deep objects too.
    std::string objects;
    for (int i = 0; i < 50000; ++i) objects += "{\"a\":";
    objects += "1" + std::string(50000, '}');
    r = parseJsonWithPositions(objects);
    EXPECT_NE(r.error.find("nesting deeper than 256"), std::string::npos) << r.error;
}

TEST(JsonPositions, NestingUpToTheLimitParses) {
    const std::string ok = std::string(256, '[') + std::string(256, ']');
    JsonParseResult r = parseJsonWithPositions(ok);
    EXPECT_EQ(r.error, "");
    EXPECT_TRUE(r.value.is_array());
    const std::string tooDeep = std::string(258, '[') + std::string(258, ']');
    EXPECT_NE(parseJsonWithPositions(tooDeep).error, "");
}

TEST(JsonPositions, DuplicateKeysCarryTheirPath) {
    JsonParseResult r = parseJsonWithPositions(
        R"({ "a": { "x": 1, "x": 2 }, "b": [ {}, { "y": 1, "z": 2, "y": 3 } ], "a": 0 })");
    EXPECT_EQ(r.error, "");
    ASSERT_EQ(r.duplicateKeys.size(), 3u);
    EXPECT_EQ(r.duplicateKeys[0].path, "a.x");
    EXPECT_EQ(r.duplicateKeys[1].path, "b[1].y");
    EXPECT_EQ(r.duplicateKeys[2].path, "a");
    EXPECT_EQ(r.duplicateKeys[2].key, "a");
}

TEST(JsonPositions, ErrorPathFollowsArraysAndObjects) {
    JsonParseResult r = parseJsonWithPositions(R"({ "p": [ 1, {"q": 2}, [3, {"r": ] } ] })");
    EXPECT_NE(r.error, "");
    EXPECT_EQ(r.errorPath, "p[2][1]");
    EXPECT_EQ(r.line, 1);
    EXPECT_EQ(r.column, 33);  // the ']'
}

TEST(JsonPositions, NumberTooLargeNamesTheNumberItself) {
    struct Case {
        std::string text, path;
        int column;
    };
    // The column is the number's first character, as for other bad tokens.
    for (const Case& c : {Case{R"({ "p": [ 1, {"q": 2e400} ] })", "p[1].q", 19},
                          Case{R"({ "p": [ 1, [3, -1e999 ] ] })", "p[1][1]", 17},
                          Case{R"([ 1e999 ])", "[0]", 3}, Case{R"(1e999)", "", 1},
                          // structure broken off after a number names the array it is in
                          Case{R"({ "p": [ 1, [3 4 ] ] })", "p[1]", 16}}) {
        SCOPED_TRACE(c.text);
        JsonParseResult r = parseJsonWithPositions(c.text);
        EXPECT_NE(r.error, "");
        EXPECT_EQ(r.errorPath, c.path);
        EXPECT_EQ(r.line, 1);
        EXPECT_EQ(r.column, c.column);
    }
    // The words quoted from the text do not make a syntax error a number's.
    const JsonParseResult quoted = parseJsonWithPositions("{\"a\": \"number overflow\x01\"}");
    EXPECT_EQ(quoted.errorPath, "");
    EXPECT_EQ(quoted.column, 23) << "the control character";
}

TEST(JsonPositions, ColumnsPointAtTheStartOfTheBadToken) {
    struct Case {
        std::string text;
        int line, column;
    };
    const std::vector<Case> cases{
        {R"([1 2])", 1, 4},                         // unexpected number
        {R"([1, 23456 789])", 1, 11},               // multi-digit number
        {R"([1, -2.5e3 7])", 1, 12},
        {R"([1})", 1, 3},                           // '}' right after a number
        {R"({"a" true})", 1, 6},                    // unexpected true literal
        {R"({"a": 1 null})", 1, 9},
        {R"({"a": tru})", 1, 7},                    // invalid literal, broken by '}'
        {R"({"a": nulll})", 1, 7},
        {R"({"a": 1 "b\"c" : 2})", 1, 9},          // string with an escaped quote
        {"{\n  \"a\": 1,\n  \"b\": 01\n}", 3, 8},  // leading zero: the lexer stops at the 1
        {"{\"\u00e9t\u00e9\": 1 2}", 1, 11},       // columns count characters, not bytes
        {"[\"abc\ndef\"]", 1, 6},                  // the control character inside a string
    };
    for (const auto& c : cases) {
        const JsonParseResult r = parseJsonWithPositions(c.text);
        EXPECT_NE(r.error, "") << c.text;
        EXPECT_EQ(r.line, c.line) << c.text << " -> " << r.error;
        EXPECT_EQ(r.column, c.column) << c.text << " -> " << r.error;
    }
}

}  // namespace
}  // namespace skygraph
