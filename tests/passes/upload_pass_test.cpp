// UploadPass: the application stages pixels (Renderer::stageUpload) and the graph's own pass
// copies them on the queue the graph gives it, here the transfer queue with a compute reader
// after it, under validation. Only the frame they were staged for copies them, and the
// renderer holds the buffer until that copy has run.
#include "compiled_graph_access.hpp"
#include "executor_test_util.hpp"
#include "plan_editor.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/staging_buffer.hpp>

#include <gtest/gtest.h>

#include <cstring>

namespace skygraph::test {
namespace {

constexpr const char* kGraph = R"({
  "version": 1, "name": "upload",
  "resources": {
    "sky": {"type": "cube", "format": "R32G32B32A32_SFLOAT", "extent": [4, 4], "external": true, "final": "ShaderRead"}
  },
  "passes": [
    {"name": "upload_sky", "type": "UploadPass", "queue": "transfer", "uses": {"sky": "Write@Transfer"}},
    {"name": "read_sky", "type": "Generic", "queue": "compute", "never_cull": true, "uses": {"sky": "Read@Compute"}}
  ]
})";

constexpr size_t kFloats = 4 * 4 * 6 * 4;

class UploadPassTest : public ExecutorTest {
protected:
    UploadPassTest()
        : library_(PassLibrary::withBuiltins()),
          graph_(parseGraph(kGraph, "upload.json", library_.registry())),
          renderer_(sharedDevice(), CompiledGraph(graph_, CompileOptions{}), options()) {}

    RendererOptions options() const {
        RendererOptions ro;
        ro.framesInFlight = 2;
        ro.passes = &library_;
        return ro;
    }

    /// Texel floats base, base + 1, ...: every layer, row and channel told apart.
    static std::shared_ptr<StagingBuffer> staged(float base) {
        auto buffer = StagingBuffer::create(sharedDevice(), kFloats * sizeof(float));
        std::vector<float> values(kFloats);
        for (size_t i = 0; i < kFloats; ++i) values[i] = base + float(i);
        std::memcpy(buffer->bytes().data(), values.data(), kFloats * sizeof(float));
        return buffer;
    }

    void expectContents(float base) {
        const std::vector<ImageData> layers = renderer_.readImage("sky");
        ASSERT_EQ(layers.size(), 6u);
        for (size_t layer = 0; layer < 6; ++layer)
            for (size_t i = 0; i < 4 * 4 * 4; ++i)
                ASSERT_EQ(layers[layer].rgba[i], base + float(layer * 64 + i)) << "layer " << layer << " float " << i;
    }

    PassLibrary library_;
    GraphDesc graph_;
    Renderer renderer_;
};

TEST_F(UploadPassTest, CopiesWhatWasStagedOnTheTransferQueue) {
    const Plan& plan = renderer_.plan();
    ASSERT_EQ(plan.passes()[0].name, "upload_sky");
    bool onTransfer = false;
    for (const Submit& submit : plan.submits())
        for (uint32_t pass : submit.passes) onTransfer |= pass == 0 && submit.queue == QueueKind::Transfer;
    EXPECT_TRUE(onTransfer) << "a submit of its own on the transfer queue, with the semaphores between";

    const auto first = staged(1.0f);
    renderer_.stageUpload("sky", first);
    renderer_.renderFrame();
    expectContents(1.0f);

    const auto second = staged(1000.0f);
    renderer_.stageUpload("sky", second);
    renderer_.renderFrame();
    expectContents(1000.0f);
}

TEST_F(UploadPassTest, HoldsTheBufferUntilTheCopyHasRun) {
    const auto buffer = staged(0.0f);
    renderer_.stageUpload("sky", buffer);
    EXPECT_EQ(buffer.use_count(), 2) << "staged";
    EXPECT_FALSE(StagingBuffer::reusable(buffer));
    renderer_.renderFrame();
    EXPECT_EQ(buffer.use_count(), 2) << "held by the frame in flight";
    EXPECT_FALSE(StagingBuffer::reusable(buffer));
    renderer_.waitIdle();
    EXPECT_EQ(buffer.use_count(), 1) << "the copy has run: the caller's again";
    EXPECT_TRUE(StagingBuffer::reusable(buffer));
    EXPECT_FALSE(StagingBuffer::reusable(nullptr));
}

TEST_F(UploadPassTest, OnlyTheFrameItWasStagedForCopiesIt) {
    renderer_.stageUpload("sky", staged(0.0f));
    renderer_.renderFrame();
    try {
        renderer_.renderFrame();
        FAIL() << "a frame with nothing staged for its UploadPass must not run";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'upload_sky' (UploadPass): no pixels staged for 'sky'"),
                  std::string::npos)
            << e.what();
    }
}

TEST_F(UploadPassTest, StagingRefusesAnUnknownResourceOrAWrongSize) {
    auto expectRefused = [&](const std::string& resource, std::shared_ptr<const StagingBuffer> buffer,
                             const std::string& message) {
        try {
            renderer_.stageUpload(resource, std::move(buffer));
            FAIL() << "staged " << resource;
        } catch (const ExecutorError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    };
    expectRefused("moon", staged(0.0f), "stageUpload: no resource 'moon' in the plan");
    expectRefused("sky", StagingBuffer::create(sharedDevice(), 16),
                  "stageUpload: 'sky' takes 1536 bytes (4x4, 6 layer(s) of R32G32B32A32_SFLOAT), the staging buffer "
                  "holds 16");
    expectRefused("sky", nullptr, "no staging buffer for 'sky'");
    EXPECT_THROW((void)StagingBuffer::create(sharedDevice(), 0), ExecutorError);
    // Of the right size, but another device's: its copy would name a buffer this device
    // never made.
    auto other = Device::create(validatedOptions());
    expectRefused("sky", StagingBuffer::create(*other, renderer_.stagingBytes("sky")),
                  "stageUpload: 'sky': the staging buffer belongs to another device");
    EXPECT_EQ(other->messageCount(), 0u) << formatMessages(*other);
}

// The oracle can fail: without the compute submit's wait for the transfer queue's signal, the
// read (and its layout transition) races the copy, which synchronization validation reports.
TEST_F(UploadPassTest, ADroppedWaitForTheCopyIsCaught) {
    CompileOptions o;
    o.memory = sharedDevice().memoryModel();
    o.queueFamilies = sharedDevice().queueFamilies();
    const CompiledGraph intact(graph_, o);
    Plan broken = intact.plan();
    auto submits = detail::PlanEditor::submits(broken);
    size_t dropped = 0;
    for (auto& s : submits)
        for (uint32_t p : s.passes)
            if (broken.passes()[p].name == "read_sky")
                dropped += std::erase_if(s.waits, [](const SemaphoreOp& w) { return w.semaphore == QueueKind::Transfer; });
    ASSERT_EQ(dropped, 1u) << planToText(broken);
    detail::PlanEditor::setSubmits(broken, submits);
    allowMessages();
    sharedDevice().clearMessages();
    Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(intact, broken), options());
    for (int i = 0; i < 2; ++i) {
        r.stageUpload("sky", staged(float(i)));
        r.renderFrame();
    }
    r.waitIdle();
    EXPECT_TRUE(sharedDevice().hasMessage("SYNC-HAZARD")) << formatMessages(sharedDevice());
}

// stageUpload() checks the size against the plan of its day: pixels staged before a resize that
// grew the target would have been copied past the end of their buffer (validation's
// VUID-vkCmdCopyBufferToImage-pRegions-00171), and the frame went on.
TEST_F(ExecutorTest, PixelsStagedBeforeAResizeAreRefusedWhenTheFrameCopiesThem) {
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = parseGraph(R"({
      "version": 1, "name": "upload_output_sized",
      "resources": {"img": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": "output",
                            "external": true, "final": "ShaderRead"}},
      "passes": [{"name": "upload_img", "type": "UploadPass", "uses": {"img": "Write@Transfer"}},
                 {"name": "read_img", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Compute"}}]
    })",
                                       "upload_output_sized.json", library.registry());
    CompileOptions co;
    co.outputWidth = co.outputHeight = 4;
    RendererOptions ro;
    ro.passes = &library;
    Renderer r(sharedDevice(), CompiledGraph(graph, co), ro);
    r.stageUpload("img", StagingBuffer::create(sharedDevice(), 4 * 4 * 16));
    r.resize(16, 16);
    try {
        r.renderFrame();
        FAIL() << "a copy of 4096 bytes from a buffer of 256 was recorded";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'upload_img' (UploadPass): the pixels staged for 'img' are 256 "
                                             "bytes, and it takes 4096 now (staged before a resize or a new graph: "
                                             "stage again)"),
                  std::string::npos)
            << e.what();
    }
    r.stageUpload("img", StagingBuffer::create(sharedDevice(), r.stagingBytes("img")));
    r.renderFrame();
    r.waitIdle();
    EXPECT_FALSE(sharedDevice().messageCount()) << formatMessages(sharedDevice());
}

// Only an UploadPass copies staged pixels: staged for a resource none writes, they were
// accepted and dropped unread after the frame.
TEST_F(ExecutorTest, StagingForAResourceNoUploadPassWritesIsRefused) {
    const PassLibrary library = PassLibrary::withBuiltins();
    const GraphDesc graph = parseGraph(R"({
      "version": 1, "name": "no_upload",
      "resources": {"img": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [4, 4],
                            "external": true, "initial": "ShaderRead"}},
      "passes": [{"name": "read_img", "type": "Generic", "never_cull": true, "uses": {"img": "Read@Compute"}}]
    })",
                                       "no_upload.json", library.registry());
    RendererOptions ro;
    ro.passes = &library;
    Renderer r(sharedDevice(), CompiledGraph(graph, CompileOptions{}), ro);
    try {
        r.stageUpload("img", StagingBuffer::create(sharedDevice(), r.stagingBytes("img")));
        FAIL() << "staged for a resource no UploadPass writes";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("stageUpload: no UploadPass of the plan writes 'img'"), std::string::npos)
            << e.what();
    }
}

TEST_F(ExecutorTest, AnUploadPassWritesMipZeroAlone) {
    // The loader refuses such a usage in a file (LoaderErrors.PassTypesCheckWhatTheirSlotsCannotSay);
    // for a graph built in code the renderer runs the type's usage validator.
    const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = parseGraph(R"({
      "version": 1, "name": "upload_mips",
      "resources": {"img": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": [8, 8], "mips": 2,
                            "external": true, "final": "ShaderRead"}},
      "passes": [{"name": "upload_img", "type": "UploadPass",
                  "uses": [{"resource": "img", "access": "Write", "stage": "Transfer", "mips": [0, 1]}]}]
    })",
                                 "upload_mips.json", library.registry());
    graph.passes[0].uses[0].usage.range = SubresourceRange{0, 2, 0, 1};
    RendererOptions ro;
    ro.passes = &library;
    try {
        Renderer r(sharedDevice(), CompiledGraph(graph, CompileOptions{}), ro);
        FAIL() << "a usage of both mips was accepted";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("pass 'upload_img', resource 'img': UploadPass copies mip 0 of every layer: "
                                             "its usage of 'img' must cover that and nothing else"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace skygraph::test
