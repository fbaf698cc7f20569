// planMemoryToSvg: a well-formed, deterministic picture of the memory layout with one rectangle
// per placement, whatever the names hold and whether or not anything is placed. Well-formed is
// judged by an XML parser (python3's xml.etree), not by looking at the text.
#include <skygraph/compiler.hpp>
#include <skygraph/plan_format.hpp>

#include "byte_text.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

TEST(ByteText, PrintsEachSizeInTheLargestUnitItReaches) {
    EXPECT_EQ(byteText(0), "0");
    EXPECT_EQ(byteText(512), "512 B");
    EXPECT_EQ(byteText(1024), "1.0 KiB");
    EXPECT_EQ(byteText((1u << 20) - 52), "1023.9 KiB");
    EXPECT_EQ(byteText((1u << 20) - 51), "1.00 MiB") << "not 1024.0 KiB";
    EXPECT_EQ(byteText(16u << 20), "16.00 MiB");
    EXPECT_EQ(byteText((uint64_t(1) << 30) - 5000), "1.00 GiB") << "not 1024.00 MiB";
    EXPECT_EQ(byteText(uint64_t(11) << 40), "11.00 TiB");
    EXPECT_EQ(byteText(~uint64_t(0)), "16.00 EiB");
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

/// The number after `attribute="` in `element`.
double attributeOf(const std::string& element, const std::string& attribute) {
    const size_t at = element.find(" " + attribute + "=\"");
    return at == std::string::npos ? -1.0 : std::stod(element.substr(at + attribute.size() + 3));
}

/// Each <rect class="CLASS" ...> element of `svg`, in order, up to its '>'.
std::vector<std::string> rects(const std::string& svg, const std::string& cls) {
    std::vector<std::string> out;
    const std::string open = "<rect class=\"" + cls + "\"";
    for (size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1))
        out.push_back(svg.substr(at, svg.find('>', at) - at));
    return out;
}

// A placement too small to see is drawn 2 pixels tall; one at its heap's end is drawn from 2
// pixels above the end, so that it stays inside the heap's band.
TEST(MemorySvg, EveryPlacementIsDrawnInsideItsHeap) {
    const char* graph = R"({
      "version": 1, "name": "ends",
      "resources": {
        "big": { "type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [4096, 4096] },
        "tiny": { "type": "image2d", "format": "R8_UNORM", "extent": [1, 1] },
        "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64],
                 "external": true, "final": "TransferSrc" }
      },
      "passes": [
        { "name": "write", "type": "Generic", "uses": { "big": "Write@ColorAttachment", "tiny": "Write@Compute" } },
        { "name": "read", "type": "Generic",
          "uses": { "big": "Read@Fragment", "tiny": "Read@Fragment", "out": "Write@ColorAttachment" } }
      ]
    })";
    const Plan ends = compile(parseGraph(graph, "ends.json", PassRegistry::withBuiltins()));
    const MemoryLayout& m = ends.memory();
    ASSERT_EQ(m.placements.size(), 2u);
    const auto tiny = std::find_if(m.placements.begin(), m.placements.end(), [&](const MemoryPlacement& p) {
        return ends.resources()[p.resource].name == "tiny";
    });
    ASSERT_NE(tiny, m.placements.end());
    ASSERT_EQ(tiny->offset + tiny->bytes, m.heaps[tiny->heap].bytes) << "the fixture puts it at its heap's end";
    const Plan deferred = compileFile(kDeferred);
    for (const Plan* plan : {&ends, &deferred}) {
        const std::string svg = planMemoryToSvg(*plan);
        const std::vector<std::string> heaps = rects(svg, "heap"), placed = rects(svg, "placement");
        ASSERT_EQ(heaps.size(), plan->memory().heaps.size());
        ASSERT_EQ(placed.size(), plan->memory().placements.size());
        for (size_t i = 0; i < placed.size(); ++i) {
            const std::string& band = heaps.at(plan->memory().placements[i].heap);
            const double top = attributeOf(band, "y"), bottom = top + attributeOf(band, "height");
            const double y = attributeOf(placed[i], "y"), h = attributeOf(placed[i], "height");
            EXPECT_GE(h, 2.0) << placed[i];
            EXPECT_GE(y, top) << placed[i] << " in " << band;
            EXPECT_LE(y + h, bottom + 0.05) << placed[i] << " in " << band;  // num() rounds to 0.1
        }
    }
}

TEST(MemorySvg, APlanWithNothingPlacedSaysSo) {
    const std::string empty = planMemoryToSvg(Plan{});
    EXPECT_NE(empty.find("no transient resources"), std::string::npos);
    EXPECT_EQ(count(empty, "class=\"placement\""), 0u);
    EXPECT_EQ(parseWithPython(empty, "empty"), "0 0");
}

}  // namespace
}  // namespace skygraph
