// planMemoryToSvg: a well-formed, deterministic picture of the memory layout with one rectangle
// per placement, whatever the names hold and whether or not anything is placed. Well-formed is
// judged by an XML parser (python3's xml.etree), not by looking at the text.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace skygraph {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;
/// The shipped deferred frame, whose 22 transient resources share memory.
const fs::path kDeferred = kSource / "graphs" / "deferred.json";

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
    return n;
}

/// The exit status of python3's XML parser on `svg`, and the number of <rect class="placement">
/// elements it finds, as "STATUS COUNT" (or just the status when it fails).
std::string parseWithPython(const std::string& svg, const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("skygraph_svg_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path file = dir / (name + ".svg"), result = dir / (name + ".txt");
    std::ofstream(file, std::ios::binary) << svg;
    const std::string cmd =
        "python3 -c \"import sys, xml.etree.ElementTree as E\n"
        "root = E.parse(sys.argv[1]).getroot()\n"
        "assert root.tag == '{http://www.w3.org/2000/svg}svg', root.tag\n"
        "print(sum(1 for e in root.iter('{http://www.w3.org/2000/svg}rect') if e.get('class') == 'placement'))\" '" +
        file.string() + "' > '" + result.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream in(result);
    std::string printed;
    std::getline(in, printed);
    fs::remove_all(dir);
    return std::to_string(status) + " " + printed;
}

Plan compileFile(const fs::path& path, CompileOptions options = {}) {
    return compile(loadGraphFile(path, PassRegistry::withBuiltins()), options);
}

TEST(MemorySvg, DrawsOneRectanglePerPlacementTheSameEveryTime) {
    const Plan plan = compileFile(kDeferred);
    const MemoryLayout& m = plan.memory();
    ASSERT_EQ(m.placements.size(), 22u);
    ASSERT_LT(m.heapBytes(), m.unaliasedBytes) << "the fixture should alias";

    const std::string svg = planMemoryToSvg(plan);
    EXPECT_EQ(svg, planMemoryToSvg(plan));
    EXPECT_EQ(svg, planMemoryToSvg(Plan(plan)));  // a copy draws the same
    EXPECT_EQ(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg ", 0), 0u);
    EXPECT_TRUE(svg.ends_with("</svg>\n"));
    EXPECT_EQ(count(svg, "class=\"placement\""), m.placements.size());
    EXPECT_EQ(count(svg, "class=\"heap\""), m.heaps.size());
    EXPECT_EQ(count(svg, "class=\"peak\""), 1u);
    for (const MemoryPlacement& p : m.placements) {
        const std::string tooltip = "<title>" + std::string(plan.resources()[p.resource].name) + ": ";
        EXPECT_NE(svg.find(tooltip), std::string::npos) << tooltip;
    }
    for (const PlannedPass& pass : plan.passes())  // every column is labelled
        EXPECT_NE(svg.find(": " + std::string(pass.name) + "</title>"), std::string::npos) << pass.name;
    EXPECT_NE(svg.find("heap 0: "), std::string::npos);
    EXPECT_NE(svg.find(" vs unaliased "), std::string::npos);
    EXPECT_NE(svg.find(" vs peak live "), std::string::npos);
    EXPECT_EQ(parseWithPython(svg, "deferred"), "0 22");
}

TEST(MemorySvg, UnaliasedLayoutsAndEveryShippedGraphParse) {
    CompileOptions unaliased;
    unaliased.aliasing = false;
    const Plan plan = compileFile(kDeferred, unaliased);
    ASSERT_EQ(plan.memory().heapBytes(), plan.memory().unaliasedBytes);
    EXPECT_EQ(parseWithPython(planMemoryToSvg(plan), "unaliased"), "0 22");
    for (const char* graph : {"raster.json", "pathtrace.json", "ibl.json", "deferred.json"}) {
        const Plan shipped = compileFile(kSource / "graphs" / graph);
        EXPECT_EQ(parseWithPython(planMemoryToSvg(shipped), "shipped"),
                  "0 " + std::to_string(shipped.memory().placements.size()))
            << graph;
    }
}

TEST(MemorySvg, NamesThatLookLikeMarkupAreEscaped) {
    const char* graph = R"({
      "version": 1, "name": "<&\"'>",
      "resources": {
        "a<b>&\"c'": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64] },
        "a spaced name": { "type": "buffer", "size": 4096, "alias": false },
        "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64],
                 "external": true, "final": "TransferSrc" }
      },
      "passes": [
        { "name": "</svg><script>", "type": "Generic",
          "uses": { "a<b>&\"c'": "Write@ColorAttachment", "a spaced name": "Write@Compute" } },
        { "name": "a pass whose name is far too long to stand under one column of the picture", "type": "Generic",
          "uses": { "a<b>&\"c'": "Read@Fragment", "a spaced name": "Read@Fragment", "out": "Write@ColorAttachment" } }
      ]
    })";
    const Plan plan = compile(parseGraph(graph, "escaped.json", PassRegistry::withBuiltins()));
    ASSERT_EQ(plan.memory().placements.size(), 2u);
    const std::string svg = planMemoryToSvg(plan);
    EXPECT_EQ(svg.find("<script>"), std::string::npos);
    EXPECT_NE(svg.find("a&lt;b&gt;&amp;&quot;c&apos;"), std::string::npos);
    EXPECT_NE(svg.find("a pass whose name is far to\xE2\x80\xA6"), std::string::npos) << "cut with an ellipsis";
    EXPECT_NE(svg.find("stroke-dasharray=\"4,2\""), std::string::npos) << "the unshared buffer is outlined dashed";
    EXPECT_EQ(parseWithPython(svg, "escaped"), "0 2");
}

TEST(MemorySvg, APlanWithNothingPlacedSaysSo) {
    const std::string empty = planMemoryToSvg(Plan{});
    EXPECT_NE(empty.find("no transient resources"), std::string::npos);
    EXPECT_EQ(count(empty, "class=\"placement\""), 0u);
    EXPECT_EQ(parseWithPython(empty, "empty"), "0 0");
}

}  // namespace
}  // namespace skygraph
