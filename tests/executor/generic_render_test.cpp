// Generic graphs run under validation + synchronization validation, with real pixels read
// back. Each test names the hazard kind (RAW, WAR, WAW, layout transition) it exercises.
#include "executor_test_util.hpp"
#include "queue_blocker.hpp"
#include "renderer_access.hpp"
#include "throwing_pass.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace skygraph::test {
namespace {

std::string graph(const std::string& resources, const std::string& passes) {
    return graphWithSwapchain("t", resources, passes);
}

/// Pass a draws red into `tex` (its declaration); b samples it and adds 0.25 green into the
/// swapchain.
CompiledGraph redThenSampled(const std::string& tex) {
    return compileText(graph(tex, R"({ "name": "a", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" },
                                       "params": { "color": [1, 0, 0, 1] } },
                                     { "name": "b", "type": "Generic",
                                       "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
                                       "params": { "color": [0, 0.25, 0, 0] } })"));
}

TEST_F(ExecutorTest, DeviceIsValidatedLavapipe) {
    EXPECT_TRUE(sharedDevice().validationEnabled());
    EXPECT_FALSE(sharedDevice().name().empty());
}

// RAW through a layout transition: color attachment -> sampled in the fragment shader.
TEST_F(ExecutorTest, ColorThenSampledRAW) {
    const ImageData img = render(redThenSampled(R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })"));
    ASSERT_EQ(img.width, 16u);
    EXPECT_PIXEL_NEAR(img, 0, 0, 1.0, 0.25, 0.0, 1.0);
    EXPECT_PIXEL_NEAR(img, 15, 15, 1.0, 0.25, 0.0, 1.0);
}

// A fixed 1x1 image with "mips": "full" has one level, so it is an attachment as a whole, as
// one of "mips": 1 is; it was refused as several levels.
TEST_F(ExecutorTest, AOneTexelFullChainIsAnAttachment) {
    const ImageData img =
        render(redThenSampled(R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [1, 1], "mips": "full" })"));
    EXPECT_PIXEL_NEAR(img, 7, 7, 1.0, 0.25, 0.0, 1.0);
}

// A `clear` output that no pass that runs uses is cleared after the last pass and handed on
// holding its clear value (it was left out of the plan, and readImage found no such image).
TEST_F(ExecutorTest, AClearOutputNoPassThatRunsUsesHoldsItsClearValue) {
    const auto c = compileText(R"({ "version": 1, "name": "t", "features": { "f": true }, "resources": {
        "shown": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [4, 4], "final": "ShaderRead",
                   "clear": { "color": [0.25, 0.5, 1, 1] } },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true,
                       "final": "Present" } },
      "passes": [
        { "name": "look", "type": "Generic", "if": "f", "uses": { "shown": "Read@Fragment", "swapchain": "Write@ColorAttachment" } },
        { "name": "draw", "type": "Generic", "if": "!f", "uses": { "swapchain": "Write@ColorAttachment" } } ] })",
                               {{"f", false}});
    const auto steps = c.plan().passes();
    ASSERT_TRUE(std::any_of(steps.begin(), steps.end(), [](const PlannedPass& p) { return p.name == "clear shown"; }));
    Renderer r(sharedDevice(), c, genericOptions(2));
    for (int frame = 0; frame < 3; ++frame) r.renderFrame();
    const std::vector<ImageData> levels = r.readImage("shown");
    r.waitIdle();
    ASSERT_EQ(levels.size(), 1u);
    EXPECT_PIXEL_NEAR(levels[0], 0, 0, 0.25, 0.5, 1.0, 1.0);
    EXPECT_PIXEL_NEAR(levels[0], 3, 3, 0.25, 0.5, 1.0, 1.0);
}

// A Read@ColorAttachment is loaded and kept (no store): Generic reads it by the load op and
// draws nothing into it. It drew into it (write mask 0xf), a write the plan never ordered:
// synchronization validation reported the next pass's read, and the contents changed.
TEST_F(ExecutorTest, AColorAttachmentReadIsNotWritten) {
    const auto c = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "a", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" },
             "params": { "color": [1, 0, 0, 1] } },
           { "name": "b", "type": "Generic",
             "uses": { "tex": "Read@ColorAttachment", "swapchain": "Write@ColorAttachment" },
             "params": { "color": [0, 0.25, 0, 0] } },
           { "name": "c", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "ReadWrite@ColorAttachment" },
             "params": { "color": [0, 0, 0.5, 0] } })"));
    const ImageData img = render(c);
    // b's colour, plus what c sampled of a's red and its own blue.
    EXPECT_PIXEL_NEAR(img, 0, 0, 1.0, 0.25, 0.5, 1.0);
    EXPECT_PIXEL_NEAR(img, 15, 15, 1.0, 0.25, 0.5, 1.0);
}

// RAW on a storage image written by compute and loaded in the fragment shader (GENERAL,
// no layout change: a pure memory dependency).
TEST_F(ExecutorTest, ComputeStorageImageThenFragmentLoad) {
    const auto c = compileText(graph(
        R"("img": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" })",
        R"({ "name": "cs", "type": "Generic", "uses": { "img": "Write@Compute" },
             "params": { "color": [0, 0, 0.5, 0.5] } },
           { "name": "fs", "type": "Generic",
             "uses": [ { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" },
                       { "resource": "img", "access": "Read", "stage": "Fragment", "as": "storage" } ],
             "params": { "color": [0.25, 0, 0, 0.5] } })"));
    const ImageData img = render(c);
    EXPECT_PIXEL_NEAR(img, 3, 7, 0.25, 0.0, 0.5, 1.0);
}

// Buffers: compute writes a storage buffer, the fragment shader reads it (RAW), a later
// compute pass overwrites it (WAR), and it is finally read as vertex, index and indirect.
TEST_F(ExecutorTest, BufferRawWarAndDrawInputs) {
    const auto c = compileText(graph(
        R"("buf": { "type": "buffer", "size": 256 },
           "tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "fill", "type": "Generic", "uses": { "buf": "Write@Compute" },
             "params": { "color": [0.5, 0, 0, 0] } },
           { "name": "use", "type": "Generic",
             "uses": { "buf": "Read@Fragment", "tex": "Write@ColorAttachment" },
             "params": { "color": [0, 0, 0, 1] } },
           { "name": "refill", "type": "Generic", "uses": { "buf": "Write@Compute" },
             "params": { "color": [0.125, 0, 0, 0] } },
           { "name": "draw", "type": "Generic",
             "uses": [ { "resource": "buf", "access": "Read", "stage": "Indirect" },
                       { "resource": "tex", "access": "Read", "stage": "Fragment" },
                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ],
             "params": { "color": [0, 0, 0, 0] } },
           { "name": "verts", "type": "Generic",
             "uses": [ { "resource": "buf", "access": "Read", "stage": "VertexInput" },
                       { "resource": "swapchain", "access": "ReadWrite", "stage": "ColorAttachment" } ],
             "params": { "color": [0, 0.25, 0, 0] } })"));
    const ImageData img = render(c);
    // use: 0.5 from the buffer in every channel + (0,0,0,1) -> tex = (0.5,0.5,0.5,1)
    // draw: tex -> swapchain; verts adds (0,0.25,0,0) with additive blending.
    EXPECT_PIXEL_NEAR(img, 8, 8, 0.5, 0.75, 0.5, 1.0);
}

// Index buffer and indexed indirect draw (VertexInput as index + Indirect).
TEST_F(ExecutorTest, IndexedIndirectDraw) {
    const auto c = compileText(graph(
        R"("ind": { "type": "buffer", "size": 64 }, "idx": { "type": "buffer", "size": 64 },
           "ubo": { "type": "buffer", "size": 64 })",
        R"({ "name": "fill", "type": "Generic", "uses": { "ind": "Write@Compute", "idx": "Write@Compute" },
             "params": { "color": [0.25, 0, 0, 0] } },
           { "name": "fillubo", "type": "Generic", "uses": { "ubo": "Write@Transfer" },
             "params": { "color": [0.125, 0, 0, 0] } },
           { "name": "draw", "type": "Generic",
             "uses": [ { "resource": "ind", "access": "Read", "stage": "Indirect" },
                       { "resource": "idx", "access": "Read", "stage": "VertexInput", "as": "index" },
                       { "resource": "ubo", "access": "Read", "stage": "Vertex", "as": "uniform" },
                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ],
             "params": { "color": [0, 0, 0, 1] } })"));
    const ImageData img = render(c);
    // The uniform buffer's value (0.125) reaches every channel through the vertex shader.
    EXPECT_PIXEL_NEAR(img, 0, 0, 0.125, 0.125, 0.125, 1.0);
    EXPECT_PIXEL_NEAR(img, 15, 15, 0.125, 0.125, 0.125, 1.0);
}

// WAW and RAW through transfers: a copy writes the image, a draw overwrites it, a copy
// reads it, and the fragment shader samples it.
TEST_F(ExecutorTest, TransferWawAndRead) {
    const auto c = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
           "buf": { "type": "buffer", "size": 64 })",
        R"({ "name": "upload", "type": "Generic", "uses": { "tex": "Write@Transfer" },
             "params": { "color": [0, 1, 0, 1] } },
           { "name": "sample1", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" } },
           { "name": "upload2", "type": "Generic", "uses": { "tex": "Write@Transfer", "buf": "Write@Transfer" },
             "params": { "color": [0, 0, 1, 1] } },
           { "name": "copyout", "type": "Generic", "uses": { "tex": "Read@Transfer", "buf": "ReadWrite@Transfer" } },
           { "name": "sample2", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "ReadWrite@ColorAttachment" },
             "params": { "color": [0, 0, 0, 0] } })"));
    const ImageData img = render(c);
    // sample1 writes (0.25,1.5,0.75,2) clamped; sample2 adds (0,0,1,1).
    EXPECT_PIXEL_NEAR(img, 5, 5, 0.25, 1.0, 1.0, 1.0);
}

// A transient with `clear` read first: the compiler inserts a Clear pass.
TEST_F(ExecutorTest, InsertedClearPass) {
    const auto c = compileText(graph(
        R"("acc": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output",
                    "clear": { "color": [0.0, 0.5, 0.0, 1.0] } })",
        R"({ "name": "read", "type": "Generic",
             "uses": { "acc": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
             "params": { "color": [0.5, 0, 0, 0] } })"));
    const ImageData img = render(c);
    EXPECT_PIXEL_NEAR(img, 1, 2, 0.5, 0.5, 0.0, 1.0);
}

// Depth: written with a depth test, then tested read-only, then sampled.
TEST_F(ExecutorTest, DepthWriteTestSample) {
    const auto c = compileText(graph(
        R"("depth": { "type": "image2d", "format": "D32_SFLOAT", "extent": "output",
                      "clear": { "depth": 0.0 } },
           "color": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "zwrite", "type": "Generic",
             "uses": { "depth": "Write@DepthAttachment", "color": "Write@ColorAttachment" },
             "params": { "color": [0, 0, 0, 1], "depth": 0.75 } },
           { "name": "ztest", "type": "Generic",
             "uses": { "depth": "Read@DepthAttachment", "color": "ReadWrite@ColorAttachment" },
             "params": { "color": [0, 0.25, 0, 0] } },
           { "name": "show", "type": "Generic",
             "uses": { "depth": "Read@Fragment", "color": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
             "params": { "color": [0, 0, 0, 0] } })"));
    const ImageData img = render(c);
    // sampled depth (0.75, 0, 0, 1) + color (0, 0.25, 0, 1)
    EXPECT_PIXEL_NEAR(img, 4, 4, 0.75, 0.25, 0.0, 1.0);
}

// Mip chain: render mip 0, sample it while rendering mip 1, sample mip 1 into the output.
TEST_F(ExecutorTest, MipChainPerLevelTransitions) {
    const auto c = compileText(graph(
        R"("chain": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "mips": 3 })",
        R"({ "name": "base", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Write", "stage": "ColorAttachment", "mips": [0, 1] } ],
             "params": { "color": [0.25, 0, 0, 1] } },
           { "name": "down1", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Read", "stage": "Fragment", "mips": [0, 1] },
                       { "resource": "chain", "access": "Write", "stage": "ColorAttachment", "mips": [1, 1] } ],
             "params": { "color": [0, 0.25, 0, 0] } },
           { "name": "down2", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Read", "stage": "Compute", "mips": [1, 1] },
                       { "resource": "chain", "access": "Write", "stage": "Transfer", "mips": [2, 1] } ] },
           { "name": "show", "type": "Generic",
             "uses": [ { "resource": "chain", "access": "Read", "stage": "Fragment", "mips": [1, 1] },
                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ],
             "params": { "color": [0, 0, 0.5, 0] } })"));
    const ImageData img = render(c);
    EXPECT_PIXEL_NEAR(img, 0, 0, 0.25, 0.25, 0.5, 1.0);
    EXPECT_PIXEL_NEAR(img, 15, 15, 0.25, 0.25, 0.5, 1.0);
}

// Cube faces: each face written as a layer of a layered attachment, sampled as a cube.
TEST_F(ExecutorTest, CubeLayersAndArray) {
    const auto c = compileText(graph(
        R"("cube": { "type": "cube", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
           "arr": { "type": "image2d_array", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "layers": 2 })",
        R"({ "name": "faces", "type": "Generic", "uses": { "cube": "Write@ColorAttachment" },
             "params": { "color": [0.5, 0, 0, 1] } },
           { "name": "face0again", "type": "Generic",
             "uses": [ { "resource": "cube", "access": "ReadWrite", "stage": "Compute", "layers": [0, 1] } ],
             "params": { "color": [0, 0, 0, 0] } },
           { "name": "arrays", "type": "Generic", "uses": { "arr": "Write@Compute" },
             "params": { "color": [0, 0.25, 0, 0] } },
           { "name": "show", "type": "Generic",
             "uses": { "cube": "Read@Fragment", "arr": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
             "params": { "color": [0, 0, 0, 0] } })"));
    const ImageData img = render(c);
    EXPECT_PIXEL_NEAR(img, 3, 3, 0.5, 0.25, 0.0, 1.0);
}

// Persistent external accumulated every frame (cross-frame RAW/WAR on one shared image,
// with two frames in flight), like the path tracer's accumulation buffer.
TEST_F(ExecutorTest, PersistentExternalAcrossFrames) {
    const auto c = compileText(graph(
        R"("accum": { "type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": "output",
                      "external": true, "final": "General" })",
        R"({ "name": "accumulate", "type": "Generic", "uses": { "accum": "ReadWrite@Compute" },
             "params": { "color": [0.0625, 0, 0, 0] } },
           { "name": "show", "type": "Generic",
             "uses": [ { "resource": "accum", "access": "Read", "stage": "Fragment", "as": "storage" },
                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ],
             "params": { "color": [0, 0, 0, 0] } })"));
    // Imported grey (0.5, 0.5, 0.5, 1); the accumulation adds 0.0625 to red each frame.
    const ImageData img = render(c, 4);
    EXPECT_PIXEL_NEAR(img, 2, 9, 0.75, 0.5, 0.5, 1.0);
}

/// "a" writes a half-size image in a compute shader, "b" samples it into the target.
CompiledGraph computeThenFragment() {
    return compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output/2" })",
        R"({ "name": "a", "type": "Generic", "uses": { "tex": "Write@Compute" },
             "params": { "color": [0, 1, 0, 1] } },
           { "name": "b", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
}

TEST_F(ExecutorTest, ResizeRecreatesOutputSizedResources) {
    const auto c = computeThenFragment();
    Renderer r(sharedDevice(), c, genericOptions());
    r.renderFrame();
    EXPECT_EQ(r.readback().width, 16u);
    r.resize(24, 8);
    r.renderFrame();
    r.renderFrame();
    const ImageData img = r.readback();
    EXPECT_EQ(img.width, 24u);
    EXPECT_EQ(img.height, 8u);
    EXPECT_PIXEL_NEAR(img, 23, 7, 0.25, 1.0, 0.75, 1.0);
    EXPECT_EQ(r.plan().outputWidth(), 24u) << "resize compiles the graph again at the new size";
    const auto timings = r.lastTimings();
    ASSERT_EQ(timings.size(), 3u) << "a, b and the read-back step";
    EXPECT_EQ(timings[0].pass, "a");
    EXPECT_GE(timings[1].milliseconds, 0.0);
    EXPECT_EQ(timings[2].pass, "read back swapchain");
}

// RendererOptions::timestamps off: the same pixels, no query written, no timing.
TEST_F(ExecutorTest, ARendererWithoutTimestampsRendersTheSameAndTimesNothing) {
    const auto c = computeThenFragment();
    RendererOptions untimed = genericOptions();
    untimed.timestamps = false;
    Renderer timedRenderer(sharedDevice(), c, genericOptions()), untimedRenderer(sharedDevice(), c, untimed);
    for (Renderer* r : {&timedRenderer, &untimedRenderer})
        for (int i = 0; i < 3; ++i) r->renderFrame();
    EXPECT_EQ(untimedRenderer.readback().rgba, timedRenderer.readback().rgba);
    EXPECT_EQ(timedRenderer.lastTimings().size(), 3u);
    EXPECT_TRUE(untimedRenderer.lastTimings().empty());
    EXPECT_TRUE(untimedRenderer.completedTimings().empty());
}

// RendererOptions::shaderCacheDir: the SPIR-V is kept where it says, and an empty path keeps
// none on disk, whatever SKYGRAPH_SHADER_CACHE says.
TEST_F(ExecutorTest, ARendererKeepsItsSpirvWhereItsOptionsSay) {
    namespace fs = std::filesystem;
    const fs::path root = fs::temp_directory_path() / ("skygraph-shader-cache-option-" + std::to_string(::getpid()));
    fs::remove_all(root);
    const char* previous = std::getenv("SKYGRAPH_SHADER_CACHE");
    const std::string saved = previous ? previous : "";
    ASSERT_EQ(::setenv("SKYGRAPH_SHADER_CACHE", (root / "from the environment").c_str(), 1), 0);
    const auto c = computeThenFragment();
    RendererOptions o = genericOptions();
    o.shaderCacheDir = root / "from the options";
    Renderer(sharedDevice(), c, o).renderFrame();
    o.shaderCacheDir = fs::path();
    Renderer(sharedDevice(), c, o).renderFrame();
    if (previous) ::setenv("SKYGRAPH_SHADER_CACHE", saved.c_str(), 1);
    else ::unsetenv("SKYGRAPH_SHADER_CACHE");
    EXPECT_TRUE(fs::is_directory(root / "from the options") && !fs::is_empty(root / "from the options"));
    EXPECT_FALSE(fs::exists(root / "from the environment"));
    fs::remove_all(root);
}

// A graph built in code skips the loader, but compile() holds it to the loader's 8 colour
// attachments a pass, so no plan reaches a renderer with more than lavapipe's 8 (the
// renderer's own check, against a device's maxColorAttachments, is for devices of fewer: the
// spec's minimum is 4).
TEST_F(ExecutorTest, APassPastEightColourAttachmentsIsRefusedByName) {
    std::string resources, uses;
    for (int i = 0; i < 8; ++i) {
        const std::string name = "t" + std::to_string(i);
        resources += (i ? ", " : "") + ("\"" + name + R"(": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })");
        uses += (i ? ", " : "") + ("\"" + name + "\": \"Write@ColorAttachment\"");
    }
    GraphDesc graph = parseGraph(
        graphWithSwapchain("mrt", resources,
                           R"({ "name": "mrt", "type": "Generic", "uses": { )" + uses +
                               R"( } }, { "name": "show", "type": "Generic", "uses": { "t0": "Read@Fragment", "t7": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"),
        "<test>", PassRegistry::withBuiltins());
    ResourceDesc ninth = *graph.findResource("t7");
    ninth.name = "t8";
    graph.resources.push_back(ninth);
    PassDesc& mrt = graph.passes[0];
    UsageDecl extra = mrt.uses.back();
    extra.resource = static_cast<uint32_t>(graph.resources.size() - 1);
    mrt.uses.push_back(extra);
    CompileOptions o = sizedOptions();
    o.memory = sharedDevice().memoryModel();
    try {
        o = headless(graph, std::move(o));
        const CompiledGraph compiled(std::move(graph), std::move(o));
        FAIL() << "a plan of 9 colour attachments in a pass";
    } catch (const GraphError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'mrt', resource 't8': a pass renders to at most 8 colour attachments"),
                  std::string::npos)
            << e.what();
    }
}

// Generic binds a pass's shader usages in one push-descriptor set: a pass sampling more images
// than the device allows in one (lavapipe's maxPushDescriptors is 32) is refused by name when
// its pipelines are made, and one at the limit renders with validation silent.
TEST_F(ExecutorTest, AGenericPassPastTheDevicesDescriptorsIsRefusedByName) {
    const auto sampling = [](int images) {
        std::string resources, writes, reads;
        for (int i = 0; i < images; ++i) {
            const std::string name = "s" + std::to_string(i);
            resources += (i ? ", " : "") + ("\"" + name + R"(": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [4, 4], "clear": { "color": [0, 0, 0, 1] } })");
            reads += ", \"" + name + "\": \"Read@Fragment\"";
        }
        return compileText(graphWithSwapchain(
            "sampling", resources,
            R"({ "name": "sample", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment")" + reads + " } }"));
    };
    (void)render(sampling(31));  // the swapchain is an attachment, not a descriptor
    try {
        (void)render(sampling(40));
        ADD_FAILURE() << "a renderer bound 40 sampled images in one push-descriptor set";
    } catch (const ExecutorError& e) {
        // Named where the graph declares the pass, as the compiler names what it refuses.
        EXPECT_NE(std::string(e.what()).find("<test>: passes[0]: pass 'sample': binds 40 descriptors in one set, and "
                                             "the device"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("(maxPushDescriptors)"), std::string::npos) << e.what();
    }
}

// A ReadWrite colour attachment of a format the device cannot blend (SNORM on lavapipe, or an
// integer one) is read through a logical XOR: what the pass leaves depends on what the image
// held, and validation stays silent (blending it is an error).
TEST_F(ExecutorTest, AReadWriteAttachmentTheDeviceCannotBlendIsReadThroughALogicOp) {
    const auto withClear = [](const char* format, const char* clear) {
        return compileText(graphWithSwapchain(
            "unblendable", std::string(R"("t": { "type": "image2d", "format": ")") + format +
                               R"(", "extent": "output", "clear": { "color": )" + clear + " } }",
            R"({ "name": "accumulate", "type": "Generic", "uses": { "t": "ReadWrite@ColorAttachment" } },
               { "name": "show", "type": "Generic", "uses": { "t": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    };
    for (const char* format : {"R8G8B8A8_SNORM", "R32_UINT", "R32G32B32A32_UINT"}) {
        SCOPED_TRACE(format);
        const ImageData fromZero = render(withClear(format, "[0, 0, 0, 0]"));
        const ImageData fromOther = render(withClear(format, "[1, 1, 1, 1]"));
        EXPECT_NE(fromZero.rgba, fromOther.rgba) << "the pass did not read the attachment";
        EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
    }
}

// A pass that blends a float attachment keeps blending: the integer attachment beside it,
// which a logic op would read only by turning that blending off, is only written.
TEST_F(ExecutorTest, APassBlendingAFloatAttachmentWritesItsIntegerOneWithoutReading) {
    const auto c = compileText(graphWithSwapchain(
        "mixed", R"("f": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output", "clear": { "color": [0, 0, 0, 0] } },
                    "u": { "type": "image2d", "format": "R32_UINT", "extent": "output", "clear": { "color": [1, 1, 1, 1] } })",
        R"({ "name": "accumulate", "type": "Generic", "uses": { "f": "ReadWrite@ColorAttachment", "u": "ReadWrite@ColorAttachment" } },
           { "name": "show", "type": "Generic", "uses": { "f": "Read@Fragment", "u": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    (void)render(c);
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
}

// A stencil-only image sampled by Generic is read as the unsigned integers its view holds
// (a float sampler on it is a validation error at every draw), in the fragment and compute stages.
TEST_F(ExecutorTest, AStencilOnlyImageIsSampledAsUnsignedIntegers) {
    const auto c = compileText(graphWithSwapchain(
        "stencil", R"("st": { "type": "image2d", "format": "S8_UINT", "extent": "output", "clear": { "stencil": 0 } })",
        R"({ "name": "mark", "type": "Generic", "uses": { "st": "Write@DepthAttachment" } },
           { "name": "count", "type": "Generic", "uses": { "st": "Read@Compute" }, "never_cull": true },
           { "name": "show", "type": "Generic", "uses": { "st": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    (void)render(c);
    EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
}

TEST_F(ExecutorTest, BadParamsAreClearErrors) {
    const auto c = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "a", "type": "Generic", "uses": { "tex": "Write@ColorAttachment" },
             "params": { "color": "red" } },
           { "name": "b", "type": "Generic",
             "uses": { "tex": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })"));
    try {
        Renderer r(sharedDevice(), c, genericOptions());
        FAIL() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'a'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("params.color"), std::string::npos) << e.what();
    }
}

// Only what CompileOptions::readbacks names is copied to the host.
TEST_F(ExecutorTest, ReadbackNeedsTheImageInCompileOptionsReadbacks) {
    GraphDesc g = parseGraph(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "b", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" } })"),
        "<test>", PassRegistry::withBuiltins());
    CompileOptions co;  // nothing read back
    co.outputWidth = co.outputHeight = 16;
    co.presentReplacement = ExternalState::ShaderRead;
    Renderer r(sharedDevice(), CompiledGraph(std::move(g), co), genericOptions());
    r.renderFrame();
    EXPECT_THROW((void)r.readback(), ExecutorError);
    EXPECT_THROW((void)r.readback("swapchain"), ExecutorError);
    r.waitIdle();
}

// A read-back of a format the renderer does not convert (integer, stencil, packed) is refused
// when the plan is installed, naming the formats it converts, before any frame renders;
// readImage() refuses it the same way.
TEST_F(ExecutorTest, AReadBackOfAnUnconvertedFormatIsRefusedBeforeRendering) {
    const std::string g = graph(R"("ids": { "type": "image2d", "format": "R32_UINT", "extent": "output",
                                            "external": true, "final": "TransferSrc" })",
                                R"({ "name": "b", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment",
                                                                              "ids": "Write@Compute" } })");
    CompileOptions co;
    co.outputWidth = co.outputHeight = 16;
    co.presentReplacement = ExternalState::ShaderRead;
    co.readbacks = {"ids"};
    const std::string expected = "cannot read back 'ids': its format R32_UINT is not supported for read-back, "
                                 "which converts ";
    try {
        Renderer r(sharedDevice(), CompiledGraph(parseGraph(g, "<test>", PassRegistry::withBuiltins()), co),
                   genericOptions());
        ADD_FAILURE() << "expected an ExecutorError";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(expected), std::string::npos) << what;
        for (const char* converted : {"R8G8B8A8_UNORM", "B8G8R8A8_SRGB", "R16G16B16A16_SFLOAT", "D32_SFLOAT"})
            EXPECT_NE(what.find(converted, expected.size()), std::string::npos) << converted << ": " << what;
        EXPECT_EQ(what.find("R32_UINT", expected.size()), std::string::npos) << what;
    }
    co.readbacks.clear();
    Renderer r(sharedDevice(), CompiledGraph(parseGraph(g, "<test>", PassRegistry::withBuiltins()), co),
               genericOptions());
    r.renderFrame();
    try {
        (void)r.readImage("ids");
        ADD_FAILURE() << "expected an ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    r.waitIdle();
}

TEST_F(ExecutorTest, SetGraphFailureKeepsOldPlan) {
    const auto good = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "b", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
             "params": { "color": [1, 0, 0, 1] } })"));
    const auto bad = compileText(graph(
        R"("tex": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "b", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
             "params": { "depth": 7 } })"));
    Renderer r(sharedDevice(), good, genericOptions());
    r.renderFrame();
    EXPECT_THROW(r.setGraph(bad), ExecutorError);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readback(), 0, 0, 1.0, 0.0, 0.0, 1.0);
    r.waitIdle();
}

// A loaded texture: an external image read first, its pixels given by the application.
TEST_F(ExecutorTest, ExternalImageUpload) {
    const auto c = compileText(
        R"({ "version": 1, "name": "t", "resources": {
          "photo": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 4],
                     "external": true, "initial": "ShaderRead" },
          "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": [8, 4],
                         "external": true, "final": "Present" } },
          "passes": [ { "name": "show", "type": "Generic",
            "uses": { "photo": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
            "params": { "color": [0, 0, 0, 0] } } ] })");
    Renderer r(sharedDevice(), c, genericOptions());
    ImageData px;
    px.width = 8;
    px.height = 4;
    px.rgba.resize(8 * 4 * 4);
    for (uint32_t y = 0; y < 4; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            float* p = &px.rgba[(y * 8 + x) * 4];
            p[0] = float(x) / 8.0f;
            p[1] = float(y) / 4.0f;
            p[2] = 0.5f;
            p[3] = 1.0f;
        }
    r.setExternalImage("photo", px);
    for (int i = 0; i < 3; ++i) r.renderFrame();
    const ImageData out = r.readback();
    EXPECT_PIXEL_NEAR(out, 0, 0, 0.0, 0.0, 0.5, 1.0);
    EXPECT_PIXEL_NEAR(out, 6, 3, 0.75, 0.75, 0.5, 1.0);
    ImageData wrong = px;
    wrong.width = 4;
    EXPECT_THROW(r.setExternalImage("photo", wrong), ExecutorError);
    EXPECT_THROW(r.setExternalImage("swapchainx", px), ExecutorError);
    r.waitIdle();
}

// Pixels kept from setExternalImage() for an output-sized image fit only the output size they
// were given at: a resize either way was a copy past their end (growing) or a garbled image
// (shrinking). The rebuild refuses them, keeping the old plan, until they are forgotten.
TEST_F(ExecutorTest, ExternalPixelsThatNoLongerFitFailTheRebuildUntilForgotten) {
    const auto c = compileText(
        R"({ "version": 1, "name": "t", "resources": {
          "photo": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output",
                     "external": true, "initial": "ShaderRead" },
          "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                         "external": true, "final": "Present" } },
          "passes": [ { "name": "show", "type": "Generic",
            "uses": { "photo": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
            "params": { "color": [0, 0, 0, 0] } } ] })");
    Renderer r(sharedDevice(), c, genericOptions());
    const auto pixels = [](uint32_t w, uint32_t h) {
        ImageData px;
        px.width = w;
        px.height = h;
        px.rgba.assign(size_t(w) * h * 4, 0.5f);
        return px;
    };
    const uint32_t w = c.outputWidth(), h = c.outputHeight();
    r.setExternalImage("photo", pixels(w, h));
    for (const auto& [nw, nh] : {std::pair{w * 2, h * 2}, std::pair{w / 2, h / 2}}) {
        try {
            r.resize(nw, nh);
            FAIL() << "resized to " << nw << "x" << nh << " with pixels of " << w << "x" << h;
        } catch (const ExecutorError& e) {
            EXPECT_NE(std::string(e.what()).find("the pixels setExternalImage() gave 'photo' do not fit this plan: "
                                                 "'photo' is " + std::to_string(nw) + "x" + std::to_string(nh) +
                                                 ", the pixels are " + std::to_string(w) + "x" + std::to_string(h) +
                                                 " (forgetExternalImage() them"),
                      std::string::npos)
                << e.what();
        }
        EXPECT_EQ(r.plan().outputWidth(), w) << "the old plan keeps running";
    }
    r.renderFrame();
    r.forgetExternalImage("photo");
    r.resize(w * 2, h * 2);
    r.setExternalImage("photo", pixels(w * 2, h * 2));
    r.renderFrame();
    EXPECT_EQ(r.readback().width, w * 2);
    EXPECT_THROW(r.forgetExternalImage("swapchain"), ExecutorError);
    ImageData shortPixels = pixels(w * 2, h * 2);
    shortPixels.rgba.resize(4);
    try {
        r.setExternalImage("photo", shortPixels);
        FAIL() << "4 floats for " << w * 2 << "x" << h * 2;
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("hold 4 floats, not"), std::string::npos) << e.what();
    }
    r.waitIdle();
}

// A null image among the application's present images was reported as "an image barrier on a
// buffer" once the plan's barriers met it.
TEST_F(ExecutorTest, ANullPresentImageIsRefusedByIndex) {
    Renderer r(sharedDevice(), compileText(R"({ "version": 1, "name": "t", "resources": {
          "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                         "external": true, "final": "Present" } },
          "passes": [ { "name": "fill", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
                        "params": { "color": [0, 0, 0, 1] } } ] })"),
               genericOptions());
    PresentImages images;
    images.images = {VK_NULL_HANDLE};
    images.format = VK_FORMAT_B8G8R8A8_UNORM;
    images.extent = {8, 8};
    images.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    try {
        r.setPresentImages(images);
        FAIL() << "a null image was taken";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("setPresentImages: image 0 is VK_NULL_HANDLE"), std::string::npos)
            << e.what();
    }
}

// A plan compiled to present, rendered headless, left the renderer's own image in
// PRESENT_SRC_KHR on a device without VK_KHR_swapchain, unnoticed.
TEST_F(ExecutorTest, APlanCompiledToPresentIsRefusedHeadless) {
    const std::string json = R"({ "version": 1, "name": "t", "resources": {
          "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                         "external": true, "final": "Present" } },
          "passes": [ { "name": "fill", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" },
                        "params": { "color": [0, 0, 0, 1] } } ] })";
    CompileOptions o = sizedOptions();
    o.memory = sharedDevice().memoryModel();
    Renderer r(sharedDevice(), CompiledGraph(parseGraph(json, "<test>", PassRegistry::withBuiltins()), o),
               genericOptions());
    try {
        r.renderFrame();
        FAIL() << "a plan that presents rendered headless";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("present resource 'swapchain': the plan was compiled to present"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("CompileOptions::presentReplacement"), std::string::npos) << e.what();
    }
    EXPECT_EQ(r.frameCount(), 0u);
    // Compiled headless, the same graph renders.
    Renderer headlessRenderer(sharedDevice(), compileText(json), genericOptions());
    headlessRenderer.renderFrame();
    headlessRenderer.waitIdle();
}

// shareImage() names why a resource cannot be shared; it had said "set `final`" of a resource
// whose `final` was set.
TEST_F(ExecutorTest, ShareImageSaysWhyAResourceCannotBeShared) {
    Renderer r(sharedDevice(), compileText(R"({ "version": 1, "name": "t", "resources": {
          "kept": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "final": "ShaderRead" },
          "photo": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                     "initial": "ShaderRead" },
          "buf": { "type": "buffer", "size": 64, "external": true, "final": "General" },
          "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                   "final": "ShaderRead" },
          "screen": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "external": true,
                      "final": "Present" } },
          "passes": [ { "name": "fill", "type": "Generic", "params": { "color": [0, 0, 0, 1] },
                        "uses": { "kept": "Write@ColorAttachment", "photo": "Read@Fragment",
                                  "buf": "Write@Compute", "out": "Write@ColorAttachment" } },
                      { "name": "show", "type": "Generic", "uses": { "screen": "Write@ColorAttachment" } } ] })"),
               genericOptions());
    for (const auto& [resource, why] :
         {std::pair{"kept", "is not external: set \"external\": true and `final`"},
          std::pair{"photo", "is not exported: set `final`"}, std::pair{"buf", "is a buffer, and only images are shared"},
          std::pair{"screen", "is the plan's presented image (`final: Present`, compiled headless"}}) {
        try {
            (void)r.shareImage(resource);
            FAIL() << resource << " was shared";
        } catch (const ExecutorError& e) {
            EXPECT_NE(std::string(e.what()).find("shareImage: '" + std::string(resource) + "' " + why), std::string::npos)
                << e.what();
        }
    }
    EXPECT_NO_THROW((void)r.shareImage("out"));
}

// The loader refuses two resources of one name; a GraphDesc built in code can hold them, and
// the renderer, which finds resources by name, names the one it would confuse.
TEST_F(ExecutorTest, TwoResourcesOfOneNameAreRefused) {
    GraphDesc graph = parseGraph(R"({ "version": 1, "name": "t", "resources": {
          "a": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
          "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "external": true,
                   "final": "ShaderRead" } },
          "passes": [ { "name": "w", "type": "Generic", "params": { "color": [0, 0, 0, 1] },
                        "uses": { "a": "Write@ColorAttachment" } },
                      { "name": "r", "type": "Generic",
                        "uses": { "a": "Read@Fragment", "out": "Write@ColorAttachment" } } ] })",
                                 "<test>", PassRegistry::withBuiltins());
    graph.resources[0].name = "out";
    try {
        Renderer r(sharedDevice(), CompiledGraph(graph, sizedOptions()), genericOptions());
        FAIL() << "two resources named 'out' were taken";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("the graph has two resources named 'out'"), std::string::npos) << e.what();
    }
}

// Cross-frame RAW into a different read stage: the frame reads the persistent buffer as
// vertex input first, then overwrites it in compute, then reads it in the fragment shader.
// The next frame's vertex-input read must see this frame's compute write, so the final
// barrier has to make that write visible to VERTEX_ATTRIBUTE_READ (found by random seed 36).
TEST_F(ExecutorTest, PersistentBufferCrossFrameReadInAnotherStage) {
    const auto c = compileText(graph(
        R"("buf": { "type": "buffer", "size": 256, "external": true, "final": "General" })",
        R"({ "name": "vin", "type": "Generic", "never_cull": true,
             "uses": [ { "resource": "buf", "access": "Read", "stage": "VertexInput" },
                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] },
           { "name": "cs", "type": "Generic", "uses": { "buf": "Write@Compute" } },
           { "name": "fs", "type": "Generic",
             "uses": { "buf": "Read@Fragment", "swapchain": "ReadWrite@ColorAttachment" } })"));
    (void)render(c);
}

// An external buffer the graph writes without exporting it: each frame slot gets its own
// copy, so frames in flight never race on it.
TEST_F(ExecutorTest, UnexportedExternalWrittenEveryFrame) {
    const auto c = compileText(graph(
        R"("scratch": { "type": "buffer", "size": 256, "external": true })",
        R"({ "name": "cs", "type": "Generic", "uses": { "scratch": "Write@Transfer" },
             "params": { "color": [0.5, 0, 0, 0] } },
           { "name": "fs", "type": "Generic",
             "uses": { "scratch": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
             "params": { "color": [0, 0, 0, 0] } })"));
    const ImageData img = render(c, 4);
    EXPECT_PIXEL_NEAR(img, 3, 3, 0.5, 0.5, 0.5, 0.5);
}

/// `json` compiled as compileText() does, with the pass types of `library`.
CompiledGraph compileWith(const PassLibrary& library, const std::string& json) {
    GraphDesc g = parseGraph(json, "<test>", library.registry());
    CompileOptions o = sizedOptions();
    o.memory = sharedDevice().memoryModel();
    o = headless(g, std::move(o));
    return CompiledGraph(std::move(g), std::move(o));
}

/// 8x4 pixels of one grey `value`, alpha 1.
ImageData grey(float value) {
    ImageData px;
    px.width = 8;
    px.height = 4;
    px.rgba.assign(8 * 4 * 4, value);
    for (size_t i = 3; i < px.rgba.size(); i += 4) px.rgba[i] = 1.0f;
    return px;
}

/// An 8x4 external image `photo` that pass "show", of type `type`, copies to the output.
std::string photoGraph(const std::string& type) {
    return R"({ "version": 1, "name": "t", "resources": {
      "photo": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 4],
                 "external": true, "initial": "ShaderRead" },
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": [8, 4],
                     "external": true, "final": "Present" } },
      "passes": [ { "name": "show", "type": ")" + type + R"(",
        "uses": { "photo": "Read@Fragment", "swapchain": "Write@ColorAttachment" },
        "params": { "color": [0, 0, 0, 0] } } ] })";
}

// A pass that throws while its frame is recorded: the frame is not submitted, and the renderer
// goes on. The upload that was to ride with that frame rides with the next, and the recording
// code, which recorded work that never ran, is made again before it.
TEST_F(ExecutorTest, AFrameWhosePassThrowsIsNotSubmittedAndTheNextCarriesItsUpload) {
    const PassLibrary library = throwingPassLibrary();
    RendererOptions ro = genericOptions(2);
    ro.passes = &library;
    Renderer r(sharedDevice(), compileWith(library, photoGraph("ThrowingPass")), ro);
    r.setExternalImage("photo", grey(0.25f));
    r.renderFrame();
    r.renderFrame();
    const int made = ThrowingPass::made();
    r.updateExternalImage("photo", grey(0.75f), UploadTiming::WithNextFrame);
    r.frameData().set(ThrowWhileRecording{true});
    EXPECT_THROW(r.renderFrame(), PassThrew);
    EXPECT_THROW(r.renderFrame(), PassThrew) << "the same again: the recording code is made again first";
    EXPECT_EQ(ThrowingPass::made(), made + 1);
    EXPECT_EQ(r.frameCount(), 2u) << "frames that threw are not submitted";
    EXPECT_PIXEL_NEAR(r.readback(), 3, 2, 0.25, 0.25, 0.25, 1.0);
    r.frameData().set(ThrowWhileRecording{false});
    r.renderFrame();
    r.renderFrame();
    EXPECT_EQ(ThrowingPass::made(), made + 2) << "made again once more, after the second throw";
    EXPECT_EQ(r.frameCount(), 4u);
    EXPECT_PIXEL_NEAR(r.readback(), 3, 2, 0.75, 0.75, 0.75, 1.0);
    r.waitIdle();
}

// updateExternalImage with WithNextFrame waits for no frame, even one held up on the queue;
// uploads of several resources all ride with the next frame, and one made now replaces one
// still waiting for a frame.
TEST_F(ExecutorTest, UploadsWithTheNextFrameWaitForNoFrameAndAllArrive) {
    const auto c = compileText(R"({ "version": 1, "name": "t", "resources": {
      "photo": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 4],
                 "external": true, "initial": "ShaderRead" },
      "photo2": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [8, 4],
                  "external": true, "initial": "ShaderRead" },
      "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": [8, 4],
                     "external": true, "final": "Present" } },
      "passes": [ { "name": "show", "type": "Generic",
        "uses": { "photo": "Read@Fragment", "photo2": "Read@Fragment", "swapchain": "Write@ColorAttachment" } } ] })");
    Renderer r(sharedDevice(), c, genericOptions(2));
    r.setExternalImage("photo", grey(0.1f));
    r.setExternalImage("photo2", grey(0.2f));
    r.renderFrame();
    r.waitIdle();
    {
        QueueBlocker blocked(sharedDevice());
        r.renderFrame();  // queued behind the blocker, in flight until it is released
        r.updateExternalImage("photo", grey(0.3f), UploadTiming::WithNextFrame);
        r.updateExternalImage("photo2", grey(0.4f), UploadTiming::WithNextFrame);
        EXPECT_FALSE(blocked.released()) << "an upload with the next frame waited for the frame in flight";
    }
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readImage("photo").at(0), 7, 3, 0.3, 0.3, 0.3, 1.0);
    EXPECT_PIXEL_NEAR(r.readImage("photo2").at(0), 7, 3, 0.4, 0.4, 0.4, 1.0);
    r.updateExternalImage("photo", grey(0.5f), UploadTiming::WithNextFrame);
    r.updateExternalImage("photo", grey(0.6f), UploadTiming::Now);
    r.renderFrame();
    EXPECT_PIXEL_NEAR(r.readImage("photo").at(0), 7, 3, 0.6, 0.6, 0.6, 1.0);
    r.waitIdle();
}

// completedTimings() are the newest finished frame's, whatever order the frame slots are
// waited for in. Three in flight: frame 3 reuses slot 0, and waitIdle() must not let the older
// frames of slots 1 and 2 overwrite its timings; nor may the next frame's wait for its slot
// bring back an older frame's after lastTimings() took the newest.
TEST_F(ExecutorTest, TimingsAreOfTheNewestFinishedFrame) {
    Renderer r(sharedDevice(), computeThenFragment(), genericOptions(3));
    for (int i = 0; i < 4; ++i) r.renderFrame();
    r.waitIdle();
    EXPECT_EQ(RendererAccess::timingsFrame(r), 3u);
    EXPECT_EQ(r.completedTimings().size(), 3u);
    for (int i = 0; i < 3; ++i) r.renderFrame();  // frames 4, 5, 6 in slots 1, 2, 0
    (void)r.lastTimings();                         // waits for frame 6
    EXPECT_EQ(RendererAccess::timingsFrame(r), 6u);
    r.renderFrame();  // frame 7 waits for slot 1's frame 4
    EXPECT_EQ(RendererAccess::timingsFrame(r), 6u);
    r.waitIdle();
    EXPECT_EQ(RendererAccess::timingsFrame(r), 7u);
}

}  // namespace
}  // namespace skygraph::test
