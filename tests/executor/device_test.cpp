// Device selection, validation switches and the render command's exit statuses.
#include "executor_test_util.hpp"
#include "throwing_pass.hpp"

#include "app/render.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/staging_buffer.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

#include <unistd.h>

namespace skygraph::test {
namespace {

using app::renderCommand;
using app::RenderOptions;

TEST(DeviceSelection, ByIndexAndByName) {
    DeviceOptions o;
    o.device = "llvmpipe";
    auto byName = Device::create(o);
    EXPECT_NE(byName->name().find("llvmpipe"), std::string::npos);
    const auto list = Device::listDevices();
    ASSERT_FALSE(list.empty());
    size_t index = 0;
    while (index < list.size() && list[index].find("llvmpipe") == std::string::npos) ++index;
    ASSERT_LT(index, list.size());
    o.device = std::to_string(index);
    auto byIndex = Device::create(o);
    EXPECT_EQ(byIndex->name(), byName->name());
    EXPECT_FALSE(byIndex->validationEnabled());
}

TEST(DeviceSelection, UnknownDeviceIsAClearError) {
    DeviceOptions o;
    o.device = "no-such-gpu-9000";
    try {
        (void)Device::create(o);
        FAIL() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("no-such-gpu-9000"), std::string::npos) << what;
        EXPECT_NE(what.find("available devices"), std::string::npos) << what;
    }
}

TEST(DeviceSelection, ValidationByEnvironment) {
    setenv("SKYGRAPH_VALIDATION", "1", 1);
    DeviceOptions o;
    o.device = "llvmpipe";
    auto d = Device::create(o);
    unsetenv("SKYGRAPH_VALIDATION");
    EXPECT_TRUE(d->validationEnabled());
    EXPECT_EQ(d->messageCount(), 0u);
}

// An application's own device extensions are enabled beside skygraph's (their commands
// resolve only then), and a device without one is refused naming it.
TEST(DeviceSelection, TheApplicationsDeviceExtensionsAreEnabled) {
    DeviceOptions o;
    o.device = "llvmpipe";
    o.validation = true;
    o.applicationName = "embedding test";
    const auto plain = Device::create(o);
    EXPECT_EQ(vkGetDeviceProcAddr(plain->device(), "vkCmdBeginConditionalRenderingEXT"), nullptr);
    o.deviceExtensions = {"VK_EXT_conditional_rendering"};
    const auto extended = Device::create(o);
    EXPECT_NE(vkGetDeviceProcAddr(extended->device(), "vkCmdBeginConditionalRenderingEXT"), nullptr);
    EXPECT_EQ(extended->messageCount(), 0u);
    o.deviceExtensions = {"VK_EXT_conditional_rendering", "VK_NOPE_no_such_extension"};
    try {
        (void)Device::create(o);
        ADD_FAILURE() << "expected ExecutorError";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("lacks VK_NOPE_no_such_extension, which DeviceOptions::deviceExtensions "
                                             "asks for"),
                  std::string::npos)
            << e.what();
    }
}

// The layer's QUEUE_SUBMIT setting travels through VK_LAYER_ENABLES, which the application
// gets back as it was: unset, or its own value (the setting is only added for the creation).
// The negative controls of hazards between submits (NegativeControl.DroppedSemaphoreWait*)
// show that the layer still has it.
TEST(DeviceSelection, ValidationLeavesTheEnvironmentAsItWas) {
    DeviceOptions o;
    o.device = "llvmpipe";
    o.validation = true;
    const char* before = std::getenv("VK_LAYER_ENABLES");
    const std::optional<std::string> saved = before ? std::optional<std::string>(before) : std::nullopt;
    unsetenv("VK_LAYER_ENABLES");
    {
        auto d = Device::create(o);
        EXPECT_EQ(std::getenv("VK_LAYER_ENABLES"), nullptr);
    }
    setenv("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT", 1);
    {
        auto d = Device::create(o);
        const char* now = std::getenv("VK_LAYER_ENABLES");
        EXPECT_STREQ(now ? now : "(unset)", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT");
    }
    if (saved) setenv("VK_LAYER_ENABLES", saved->c_str(), 1);
    else unsetenv("VK_LAYER_ENABLES");
}

/// Sets an environment variable for its lifetime, then puts back what was there (or nothing).
class ScopedVariable {
public:
    ScopedVariable(const char* name, const char* value) : name_(name) {
        if (const char* previous = std::getenv(name)) previous_ = previous;
        setenv(name, value, 1);
    }
    ~ScopedVariable() {
        if (previous_) setenv(name_, previous_->c_str(), 1);
        else unsetenv(name_);
    }
    ScopedVariable(const ScopedVariable&) = delete;
    ScopedVariable& operator=(const ScopedVariable&) = delete;

private:
    const char* name_;
    std::optional<std::string> previous_;
};

// A machine without a Vulkan driver (the loader reads the driver variables at each
// vkCreateInstance, so pointing both at nothing stands for one): the loader answers
// VK_ERROR_INCOMPATIBLE_DRIVER, which the message keeps, and says what is missing and how to
// get it rather than leaving the result's name to be looked up.
TEST(DeviceSelection, NoVulkanDriverIsSaidAsSuchWithHowToInstallOne) {
    const char* nowhere = "/nonexistent/skygraph-no-such-driver.json";
    std::optional<ScopedVariable> icdFiles(std::in_place, "VK_ICD_FILENAMES", nowhere);
    std::optional<ScopedVariable> driverFiles(std::in_place, "VK_DRIVER_FILES", nowhere);
    try {
        (void)Device::create(validatedOptions());
        ADD_FAILURE() << "a device was made without a driver";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        for (const std::string& expected :
             std::vector<std::string>{"VK_ERROR_INCOMPATIBLE_DRIVER", "no Vulkan driver was found",
                                      "VK_DRIVER_FILES is set to '" + std::string(nowhere) + "'",
                                      "apt install mesa-vulkan-drivers", "set VK_ICD_FILENAMES"})
            EXPECT_NE(what.find(expected), std::string::npos) << expected << " in: " << what;
    }
    driverFiles.reset();
    icdFiles.reset();
    EXPECT_NO_THROW((void)Device::create(validatedOptions())) << "the driver variables are back as they were";
}

// finish() destroys the device while validation listens: a handle still alive then (here a
// semaphore made and never destroyed, the negative control) is reported and counted, and a
// device whose objects were all destroyed finishes silent. Twice is the same as once.
TEST(DeviceFinish, AnObjectStillAliveIsCountedAndACleanDeviceIsSilent) {
    const DeviceOptions o = validatedOptions();
    auto clean = Device::create(o);
    VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore destroyed = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateSemaphore(clean->device(), &sci, nullptr, &destroyed), VK_SUCCESS);
    vkDestroySemaphore(clean->device(), destroyed, nullptr);
    clean->finish();
    EXPECT_EQ(clean->messageCount(), 0u);
    EXPECT_EQ(clean->device(), VK_NULL_HANDLE);

    auto leaking = Device::create(o);
    VkSemaphore leaked = VK_NULL_HANDLE;
    ASSERT_EQ(vkCreateSemaphore(leaking->device(), &sci, nullptr, &leaked), VK_SUCCESS);
    EXPECT_EQ(leaking->messageCount(), 0u);
    leaking->finish();
    EXPECT_EQ(leaking->messageCount(), 1u);
    EXPECT_TRUE(leaking->hasMessage("VUID-vkDestroyDevice-device-00378"));
    leaking->finish();
    EXPECT_EQ(leaking->messageCount(), 1u);
}

// What is made from a device destroys its Vulkan objects with that device, so finish() refuses
// while any of it lives, naming each kind and how many, and leaves the device working; it
// destroys the device once they are gone.
TEST(DeviceFinish, IsRefusedWhileWhatWasMadeFromTheDeviceLives) {
    auto device = Device::create(validatedOptions());
    const std::string graph = graphWithSwapchain(
        "owned", R"("t": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
        R"({ "name": "draw", "type": "Generic", "uses": { "t": "Write@ColorAttachment" } },
           { "name": "show", "type": "Generic", "uses": { "t": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })");
    {
        GraphDesc parsed = parseGraph(graph, "<test>", PassRegistry::withBuiltins());
        CompileOptions options = sizedOptions();
        options.memory = device->memoryModel();  // the plan as this device's renderer runs it
        options = headless(parsed, std::move(options));
        Renderer renderer(*device, CompiledGraph(std::move(parsed), std::move(options)), genericOptions(1));
        const auto staging = StagingBuffer::create(*device, 256);
        const auto another = StagingBuffer::create(*device, 256);
        try {
            device->finish();
            ADD_FAILURE() << "finish() destroyed the device under a renderer";
        } catch (const ExecutorError& e) {
            EXPECT_STREQ(e.what(), "Device::finish(): made from this device and still alive: 1 Renderer and "
                                   "2 StagingBuffers; destroy those first");
        }
        EXPECT_NE(device->device(), VK_NULL_HANDLE);
        renderer.renderFrame();
        renderer.waitIdle();
    }
    device->finish();
    EXPECT_EQ(device->device(), VK_NULL_HANDLE);
    EXPECT_EQ(device->messageCount(), 0u) << formatMessages(*device);
    // Nothing is made from it afterwards (before, the loader ended the process in vkCreateBuffer).
    try {
        (void)StagingBuffer::create(*device, 256);
        ADD_FAILURE() << "a StagingBuffer was made from a finished device";
    } catch (const ExecutorError& e) {
        EXPECT_STREQ(e.what(), "cannot make a StagingBuffer from a Device after Device::finish(): its device is "
                               "destroyed");
    }
    GraphDesc parsed = parseGraph(graph, "<test>", PassRegistry::withBuiltins());
    CompileOptions options = headless(parsed, sizedOptions());
    try {
        Renderer renderer(*device, CompiledGraph(std::move(parsed), std::move(options)), genericOptions(1));
        ADD_FAILURE() << "a Renderer was made from a finished device";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("destroyed"), std::string::npos) << e.what();
    }
}

// Destroying the Device first would end the process inside the Vulkan loader when the rest
// destroys its objects; the destructor ends it with the cause instead.
TEST(DeviceFinishDeathTest, DestroyingTheDeviceFirstSaysWhatWasStillAlive) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");  // the parent has Vulkan threads
    DeviceOptions o;
    o.device = "llvmpipe";
    EXPECT_DEATH(
        {
            auto device = Device::create(o);
            const auto staging = StagingBuffer::create(*device, 256);
            device.reset();
        },
        "Device destroyed while still alive, made from it: 1 StagingBuffer; destroy those before the Device");
}

/// Generic's recording code, then a vkCmdSetViewport of no viewports: a call validation
/// reports (VUID-vkCmdSetViewport-viewportCount-arraylength) and the driver records as nothing.
class ReportedPass : public AfterGeneric {
public:
    using AfterGeneric::AfterGeneric;

protected:
    void afterGeneric(const RecordContext& context) override { vkCmdSetViewport(context.cmd, 0, 0, nullptr); }
};

// A render whose frames validation reports on exits 1 and writes no image (the control, the
// same graph as Generic, writes it); the message is on stderr.
TEST(RenderCommand, AValidationMessageFailsTheRenderAndWritesNothing) {
    PassLibrary library = PassLibrary::genericOnly();
    PassTypeInfo info;
    info.name = "Reported";
    info.acceptsAnyUsage = true;
    library.add(std::move(info), [](const PassDesc& desc) {
        return std::make_unique<ReportedPass>((*PassLibrary::genericOnly().factory("Generic"))(desc));
    });
    const auto dir = std::filesystem::temp_directory_path() / ("skygraph_render_reported_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const char* type : {"Generic", "Reported"}) {
        SCOPED_TRACE(type);
        RenderOptions o;
        o.graphText = graphWithSwapchain(
            "reported", R"("t": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" })",
            std::string(R"({ "name": "draw", "type": "Generic", "uses": { "t": "Write@ColorAttachment" } },
                           { "name": "show", "type": ")") + type +
                R"(", "uses": { "t": "Read@Fragment", "swapchain": "Write@ColorAttachment" } })");
        o.passes = &library;
        o.width = o.height = 16;
        o.frames = 1;
        o.validate = true;
        o.device = "llvmpipe";
        o.output = dir / (std::string(type) + ".png");
        const bool reported = std::string_view(type) == "Reported";
        EXPECT_EQ(renderCommand(o), reported ? 1 : 0);
        EXPECT_EQ(std::filesystem::exists(o.output), !reported);
    }
    std::filesystem::remove_all(dir);
}

TEST(RenderCommand, WritesPngAndReportsUserErrors) {
    // Unique per process: ctest runs test binaries of several build trees in parallel.
    const auto dir = std::filesystem::temp_directory_path() /
                     ("skygraph_render_cmd_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    RenderOptions o;
    o.graph = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json";
    o.width = 32;
    o.height = 16;
    o.frames = 3;
    o.validate = true;
    o.device = "llvmpipe";
    o.output = dir / "out.png";
    std::filesystem::remove(o.output);
    EXPECT_EQ(renderCommand(o), 0);
    ASSERT_TRUE(std::filesystem::exists(o.output));
    std::ifstream in(o.output, std::ios::binary);
    char magic[8] = {};
    in.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG");

    // HDR output of the same target, by extension.
    RenderOptions exr = o;
    exr.output = dir / "out.exr";
    EXPECT_EQ(renderCommand(exr), 0);
    const HdrImage loaded = loadHdrImage(exr.output);
    EXPECT_EQ(loaded.width, 32u);
    EXPECT_EQ(loaded.height, 16u);

    RenderOptions bad = o;
    bad.graph = dir / "missing.json";
    bad.output = dir / "missing.png";
    EXPECT_EQ(renderCommand(bad), 1);
    EXPECT_FALSE(std::filesystem::exists(bad.output)) << "nothing half-written";

    RenderOptions badFeature = o;
    badFeature.features["no_such_feature"] = true;
    badFeature.output = dir / "feature.png";
    EXPECT_EQ(renderCommand(badFeature), 1);
    EXPECT_FALSE(std::filesystem::exists(badFeature.output));
    std::filesystem::remove_all(dir);
}

// A resource the device cannot hold is named where the graph declares it (file, JSON path),
// before anything is allocated: at 16384^2, raster.json's hdr_color (RGBA16F) needs 2 GiB,
// over lavapipe's memory cap of 1 GiB. What does fit renders as before.
class RenderCapacity : public ExecutorTest {};

TEST_F(RenderCapacity, AResourceTooLargeIsNamedAtItsDeclaration) {
    RenderOptions o;
    o.graph = std::filesystem::path(SKYGRAPH_SOURCE_DIR) / "graphs" / "raster.json";
    o.width = o.height = 16384;
    o.frames = 1;
    app::FrameInputs inputs = app::loadFrameInputs(o);
    inputs.compile.presentReplacement = ExternalState::TransferSrc;  // headless, as `render` compiles it
    try {
        (void)app::renderFrames(sharedDevice(), CompiledGraph(inputs.graph, inputs.compile), inputs, o);
        FAIL() << "16384x16384 was accepted";
    } catch (const GraphError& e) {
        const std::vector<Diagnostic>& d = e.diagnostics().items();
        ASSERT_EQ(d.size(), 1u) << e.what();
        EXPECT_EQ(d[0].file, o.graph.string());
        EXPECT_EQ(d[0].jsonPath, "resources.hdr_color");
        EXPECT_NE(d[0].message.find("resource 'hdr_color' needs 2.00 GiB, over the memory cap"), std::string::npos)
            << d[0].message;
        EXPECT_NE(d[0].message.find("(its extent follows the output, 16384x16384)"), std::string::npos)
            << d[0].message;
    }
    o.width = o.height = 16;
    inputs = app::loadFrameInputs(o);
    inputs.compile.presentReplacement = ExternalState::TransferSrc;
    const app::RenderedFrames frames =
        app::renderFrames(sharedDevice(), CompiledGraph(inputs.graph, inputs.compile), inputs, o);
    EXPECT_EQ(frames.renderer->frameCount(), 1u);
}

// The image writers fail as hdr_image.hpp's savers do: an ImageError that names the file.
TEST(ImageOutput, WritersThrowImageErrorNamingTheFile) {
    ImageData pixels;
    pixels.width = pixels.height = 2;
    pixels.rgba.assign(16, 0.5f);
    const std::filesystem::path nowhere = std::filesystem::temp_directory_path() /
                                          ("skygraph_no_such_dir_" + std::to_string(::getpid())) / "out";
    for (const std::string extension : {".png", ".hdr", ".exr"}) {
        const std::filesystem::path file = nowhere.string() + extension;
        try {
            if (extension == ".png") writePng(file, pixels);
            else writeHdr(file, pixels);
            FAIL() << "wrote " << file;
        } catch (const ImageError& e) {
            EXPECT_EQ(e.file(), file);
        }
    }
    const std::filesystem::path empty = std::filesystem::temp_directory_path() / "skygraph_empty_image.png";
    try {
        writePng(empty, ImageData{});
        FAIL() << "wrote an empty image";
    } catch (const ImageError& e) {
        EXPECT_EQ(e.file(), empty);
    }
    EXPECT_FALSE(std::filesystem::exists(empty));
}

}  // namespace
}  // namespace skygraph::test
