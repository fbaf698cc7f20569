// Resizing recompiles: a full mip chain of an output-sized image has as many levels as the new
// size gives, and the plan's barriers cover exactly those, under synchronization validation.
#include "compiled_graph_access.hpp"
#include "executor_test_util.hpp"
#include "queue_blocker.hpp"

#include <skygraph/compiled_graph.hpp>

#include <functional>
#include <vector>

namespace skygraph::test {
namespace {

const char* kChainGraph = R"({ "version": 1, "name": "chain", "resources": {
    "chain": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "mips": "full" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "fill", "type": "Generic", "uses": { "chain": "Write@Transfer" } },
    { "name": "show", "type": "Generic", "uses": { "chain": "Read@Fragment", "swapchain": "Write@ColorAttachment" } } ] })";

class Resize : public ExecutorTest {};

TEST_F(Resize, AnOutputSizedFullMipChainIsRecompiledAtEverySize) {
    CompileOptions o;
    o.presentReplacement = ExternalState::TransferSrc;
    o.readbacks = {"swapchain"};
    o.outputWidth = 64;
    o.outputHeight = 64;
    Renderer r(sharedDevice(), CompiledGraph(parseGraph(kChainGraph, "chain.json", PassRegistry::withBuiltins()), o), genericOptions());
    struct Size {
        uint32_t width, height, mips;
    };
    for (const Size size : {Size{64, 64, 7}, Size{200, 120, 8}, Size{37, 19, 6}}) {
        if (size.width != r.compiled().outputWidth() || size.height != r.compiled().outputHeight())
            r.resize(size.width, size.height);
        EXPECT_EQ(r.plan().outputWidth(), size.width);
        ASSERT_FALSE(r.plan().passes().empty());
        const PlannedUsage& fill = r.plan().passes().front().usages[0];
        EXPECT_EQ(fill.range.mipCount, size.mips) << "at " << size.width << "x" << size.height;
        for (int frame = 0; frame < 3; ++frame) r.renderFrame();
        const ImageData shown = r.readback();
        EXPECT_EQ(shown.width, size.width);
        EXPECT_EQ(shown.height, size.height);
        r.waitIdle();
        EXPECT_EQ(sharedDevice().messageCount(), 0u) << "at " << size.width << "x" << size.height << ":\n"
                                                     << formatMessages(sharedDevice());
    }
}

// The negative control: what a resize that keeps the old plan does is caught by validation, so
// the test above fails without the recompile. Shrinking shows it: the stale plan's barriers and
// views cover the 7 levels of 64x64, and the image at 37x19 has 6. (Growing leaves the new
// level unused by the stale plan, which nothing reports.)
TEST_F(Resize, APlanCompiledForAnotherSizeIsCaughtByValidation) {
    allowMessages();
    CompileOptions o;
    o.presentReplacement = ExternalState::TransferSrc;
    o.readbacks = {"swapchain"};
    o.outputWidth = 64;
    o.outputHeight = 64;
    o.memory = sharedDevice().memoryModel();  // the renderer runs such a plan as given
    const CompiledGraph at64(parseGraph(kChainGraph, "chain.json", PassRegistry::withBuiltins()), o);
    const CompiledGraph at37 = at64.resized(37, 19);
    ASSERT_FALSE(at37.plan().passes().empty());
    ASSERT_EQ(at37.plan().passes().front().usages[0].range.mipCount, 6u);
    try {
        Renderer r(sharedDevice(), detail::CompiledGraphAccess::withPlan(at37, at64.plan()), genericOptions());
        for (int frame = 0; frame < 3; ++frame) r.renderFrame();
        r.waitIdle();
    } catch (const ExecutorError&) {
        // lavapipe may refuse the out-of-range view itself once validation has reported it
    }
    EXPECT_GT(sharedDevice().messageCount(), 0u) << "a stale plan's extra mip level went unnoticed";
}

TEST_F(Resize, ASizeTheGraphCannotTakeKeepsTheOldPlanRunning) {
    // A range past the chain of a small output is an error of the compile at that size.
    const char* graph = R"({ "version": 1, "name": "ranged", "resources": {
        "chain": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "mips": "full" },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
      "passes": [
        { "name": "fill", "type": "Generic", "uses": [ { "resource": "chain", "access": "Write", "stage": "Transfer", "mips": [6, 1] } ] },
        { "name": "show", "type": "Generic", "uses": [ { "resource": "chain", "access": "Read", "stage": "Fragment", "mips": [6, 1] },
                                                      { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";
    CompileOptions o;
    o.presentReplacement = ExternalState::TransferSrc;
    o.readbacks = {"swapchain"};
    o.outputWidth = 64;
    o.outputHeight = 64;
    Renderer r(sharedDevice(), CompiledGraph(parseGraph(graph, "ranged.json", PassRegistry::withBuiltins()), o), genericOptions());
    r.renderFrame();
    try {
        r.resize(16, 16);  // 5 levels: mip 6 is not there
        FAIL() << "resize to 16x16 should fail";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("resize to 16x16"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("mip level"), std::string::npos) << e.what();
    }
    EXPECT_EQ(r.plan().outputWidth(), 64u);
    r.renderFrame();
    EXPECT_EQ(r.readback().width, 64u);
    r.waitIdle();
}

// An imported output-sized image stops fitting at a resize, which then fails and keeps the old
// plan; forgetImport lets the resize make an image of the renderer's own, and an import of the
// new size is read from the next frame on.
/// A producer that paints `shared` and a consumer that samples it (importImage), headless.
const char* kProducerGraph = R"({ "version": 1, "name": "producer", "resources": {
    "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "external": true, "final": "ShaderRead" } },
  "passes": [ { "name": "paint", "type": "Generic", "uses": { "shared": "Write@ColorAttachment" },
                "params": { "color": [0, 1, 0, 1] } } ] })";
const char* kConsumerGraph = R"({ "version": 1, "name": "consumer", "resources": {
    "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "external": true, "initial": "ShaderRead" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [ { "name": "show", "type": "Generic", "uses": { "shared": "Read@Fragment", "swapchain": "Write@ColorAttachment" } } ] })";

CompiledGraph compileImportGraph(const char* json, uint32_t size, bool readback) {
    CompileOptions o;
    o.presentReplacement = ExternalState::TransferSrc;
    if (readback) o.readbacks = {"swapchain"};
    o.outputWidth = o.outputHeight = size;
    o.memory = sharedDevice().memoryModel();
    return CompiledGraph(parseGraph(json, "import.json", PassRegistry::withBuiltins()), o);
}

TEST_F(Resize, AnImportThatNoLongerFitsIsForgottenForAResize) {
    Renderer producer(sharedDevice(), compileImportGraph(kProducerGraph, 32, false), genericOptions());
    Renderer consumer(sharedDevice(), compileImportGraph(kConsumerGraph, 32, true), genericOptions());
    const auto importFromProducer = [&] {
        producer.renderFrame();
        producer.waitIdle();
        consumer.importImage("shared", producer.shareImage("shared"));
    };
    importFromProducer();
    consumer.renderFrame();
    EXPECT_THROW(consumer.resize(48, 40), ExecutorError) << "a 32x32 import in a 48x40 plan";
    EXPECT_EQ(consumer.plan().outputWidth(), 32u);
    consumer.renderFrame();

    consumer.forgetImport("shared");
    consumer.resize(48, 40);
    consumer.renderFrame();
    const ImageData own = consumer.readback();
    EXPECT_EQ(own.width, 48u);
    producer.resize(48, 40);
    importFromProducer();
    consumer.renderFrame();
    const ImageData imported = consumer.readback();
    ASSERT_EQ(imported.width, 48u);
    EXPECT_NE(imported.rgba, own.rgba) << "the frame reads the new import, not the renderer's own image";
    EXPECT_THROW(consumer.forgetImport("swapchain"), ExecutorError);
    consumer.waitIdle();
}

// An imported image is the producer's: pixels for it waiting to ride with the consumer's next
// frame were copied into the producer's image (silently, validation has no word for it), and
// pixels given after the import did nothing. The first are dropped, the second refused.
TEST_F(Resize, PixelsAreNeverCopiedIntoAnImportedImage) {
    Renderer producer(sharedDevice(), compileImportGraph(kProducerGraph, 16, false), genericOptions());
    Renderer consumer(sharedDevice(), compileImportGraph(kConsumerGraph, 16, true), genericOptions());
    const auto solid = [](float r, float g, float b) {
        ImageData pixels;
        pixels.width = pixels.height = 16;
        for (int i = 0; i < 16 * 16; ++i) pixels.rgba.insert(pixels.rgba.end(), {r, g, b, 1.0f});
        return pixels;
    };
    producer.renderFrame();
    producer.waitIdle();
    const std::vector<float> painted = producer.readImage("shared").at(0).rgba;
    consumer.setExternalImage("shared", solid(1, 0, 0));
    consumer.renderFrame();
    consumer.updateExternalImage("shared", solid(0, 0, 1), UploadTiming::WithNextFrame);
    consumer.importImage("shared", producer.shareImage("shared"));
    consumer.renderFrame();
    consumer.waitIdle();
    EXPECT_EQ(producer.readImage("shared").at(0).rgba, painted) << "the consumer's pixels went into the producer's image";
    for (const auto& set : std::vector<std::function<void()>>{
             [&] { consumer.setExternalImage("shared", solid(0, 1, 1)); },
             [&] { consumer.updateExternalImage("shared", solid(0, 1, 1), UploadTiming::Now); }}) {
        try {
            set();
            ADD_FAILURE() << "pixels for an imported image were taken";
        } catch (const ExecutorError& e) {
            EXPECT_NE(std::string(e.what()).find("'shared' is an imported image (importImage()), which this renderer "
                                                 "only reads"),
                      std::string::npos)
                << e.what();
        }
    }
    EXPECT_EQ(producer.readImage("shared").at(0).rgba, painted);
}

// A rebuild waits for this renderer's own frames only: work that another renderer or the
// application has on the device's queue goes on, however long it takes.
TEST_F(Resize, ARebuildWaitsForNoOtherWorkOnTheDevice) {
    // No external resource, so no setup: that would be submitted behind the blocker.
    Renderer r(sharedDevice(), compileText(R"({ "version": 1, "name": "inner", "resources": {
        "chain": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output", "mips": "full" },
        "target": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" } },
      "passes": [
        { "name": "fill", "type": "Generic", "never_cull": true, "uses": { "chain": "Write@Transfer" } },
        { "name": "show", "type": "Generic", "never_cull": true,
          "uses": { "chain": "Read@Fragment", "target": "Write@ColorAttachment" } } ] })"),
               genericOptions());
    ASSERT_TRUE(r.setupPlan().passes().empty());
    r.renderFrame();
    r.waitIdle();
    {
        QueueBlocker blocked(sharedDevice());
        r.resize(24, 20);
        r.setGraph(r.compiled());
        r.reloadShaders();
        EXPECT_FALSE(blocked.released()) << "a rebuild waited for work that is not the renderer's";
    }
    r.renderFrame();
    r.waitIdle();
    EXPECT_EQ(r.compiled().outputWidth(), 24u);
    EXPECT_EQ(r.lastTimings().size(), 2u) << "the frame after the rebuilds ran";
}

// importImage checks an image for a resource the plan culled against the graph's declaration:
// device, format, extent, mips and layers, as for one the plan uses.
TEST_F(Resize, AnImportForACulledResourceIsCheckedAgainstItsDeclaration) {
    const auto compile = [](const std::string& json) {
        CompileOptions o;
        o.presentReplacement = ExternalState::TransferSrc;
        o.outputWidth = o.outputHeight = 16;
        o.memory = sharedDevice().memoryModel();
        return CompiledGraph(parseGraph(json, "import.json", PassRegistry::withBuiltins()), o);
    };
    const auto producerGraph = [](const std::string& extent) {
        return R"({ "version": 1, "name": "producer", "resources": {
            "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": )" + extent + R"(,
                        "external": true, "final": "ShaderRead" } },
          "passes": [ { "name": "paint", "type": "Generic", "uses": { "shared": "Write@ColorAttachment" } } ] })";
    };
    // "look" reads the import into an image nothing reads: the plan culls both.
    const char* consumerGraph = R"({ "version": 1, "name": "consumer", "resources": {
        "shared": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true, "initial": "ShaderRead" },
        "unseen": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16] },
        "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
      "passes": [ { "name": "look", "type": "Generic", "uses": { "shared": "Read@Fragment", "unseen": "Write@ColorAttachment" } },
                  { "name": "show", "type": "Generic", "uses": { "swapchain": "Write@ColorAttachment" } } ] })";
    Renderer consumer(sharedDevice(), compile(consumerGraph), genericOptions());
    ASSERT_LT(consumer.plan().resourceIndex("shared"), 0) << "the plan uses 'shared'";
    for (const char* extent : {"[16, 8]", "[16, 16]"}) {
        Renderer producer(sharedDevice(), compile(producerGraph(extent)), genericOptions());
        producer.renderFrame();
        producer.waitIdle();
        if (std::string(extent) == "[16, 8]") {
            try {
                consumer.importImage("shared", producer.shareImage("shared"));
                FAIL() << "a 16x8 image imported for a 16x16 resource";
            } catch (const ExecutorError& e) {
                EXPECT_NE(std::string(e.what()).find("the image is 16x8, 1 mips, 1 layers of format R8G8B8A8_UNORM; the "
                                                     "graph declares 16x16, 1 mips, 1 layers of format R8G8B8A8_UNORM"),
                          std::string::npos)
                    << e.what();
            }
        } else {
            consumer.importImage("shared", producer.shareImage("shared"));
        }
    }
    consumer.renderFrame();
    consumer.forgetImport("shared");  // the one that fits was kept
    consumer.waitIdle();
}

}  // namespace
}  // namespace skygraph::test
