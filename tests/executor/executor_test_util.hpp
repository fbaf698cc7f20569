// Shared fixture for executor tests: one validated lavapipe device per test binary.
#pragma once

#include "generic_passes.hpp"
#include "headless_options.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/plan_format.hpp>
#include <skygraph/renderer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace skygraph::test {

inline std::string formatMessages(const Device& d);
inline std::string unexplainedPerformanceWarnings(const Device& d);

/// Owns the device every test shares, and destroys it before static destruction (tearing
/// down a Vulkan device from a static destructor hangs some drivers at exit).
class DeviceEnvironment : public ::testing::Environment {
public:
    static std::unique_ptr<Device>& slot() {
        static std::unique_ptr<Device> device;
        return device;
    }
    /// Messages no test checked (work after the last test that did) fail the binary.
    void TearDown() override {
        if (slot()) {
            EXPECT_EQ(slot()->messageCount(), 0u) << "messages no test checked:\n" << formatMessages(*slot());
            EXPECT_EQ(unexplainedPerformanceWarnings(*slot()), "") << "performance warnings no test checked";
        }
        slot().reset();
    }
};

/// Validation + synchronization validation (QUEUE_SUBMIT included) on `device`, logging each
/// message unless SKYGRAPH_TEST_QUIET is set: how the tests make their devices.
inline DeviceOptions validatedOptions(const char* device = "llvmpipe") {
    DeviceOptions o;
    o.validation = true;
    o.logMessages = std::getenv("SKYGRAPH_TEST_QUIET") == nullptr;
    o.device = device;
    return o;
}

/// The device every test shares: validatedOptions() on lavapipe unless SKYGRAPH_TEST_DEVICE
/// names another.
inline Device& sharedDevice() {
    auto& device = DeviceEnvironment::slot();
    if (!device) {
        ::testing::AddGlobalTestEnvironment(new DeviceEnvironment);
        const char* name = std::getenv("SKYGRAPH_TEST_DEVICE");
        device = Device::create(validatedOptions(name ? name : "llvmpipe"));
    }
    return *device;
}

inline std::string formatMessages(const Device& d) {
    std::string s;
    for (const auto& m : d.messages()) s += "  [" + m.idName + "] " + m.message.substr(0, 600) + "\n";
    return s;
}

/// The performance warnings on `d` that no layouts policy explains, formatted; empty when
/// every one is the layer's advice for a copy that reads in GENERAL, which plans do by
/// design: a run of reads that mixes a copy with other readers keeps one layout under
/// `fewest-barriers`, and a ReadWrite transfer is GENERAL under either policy
/// (docs/barriers.md, rules 4 and 13). Any other performance warning fails a test, and so do
/// warnings past those the device keeps.
inline std::string unexplainedPerformanceWarnings(const Device& d) {
    std::string s;
    const std::vector<ValidationMessage> kept = d.performanceWarnings();
    for (const ValidationMessage& m : kept)
        if (m.message.find("should be VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL instead of GENERAL") == std::string::npos)
            s += "  [" + m.idName + "] " + m.message.substr(0, 600) + "\n";
    if (d.performanceWarningCount() > kept.size())
        s += "  " + std::to_string(d.performanceWarningCount() - kept.size()) + " more, not kept\n";
    return s;
}

/// A test graph's JSON: `resources` (members of "resources") beside an output-sized
/// "swapchain" to present, which compileText turns into the read-back target, and `passes`
/// (elements of "passes").
inline std::string graphWithSwapchain(const std::string& name, const std::string& resources,
                                      const std::string& passes) {
    return R"({ "version": 1, "name": ")" + name + R"(", "resources": {)" + resources + ", " +
           R"("swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                      "external": true, "final": "Present" })" +
           R"(}, "passes": [)" + passes + "] }";
}

/// A graph in memory compiled for headless rendering at 16x16, with the shared device's
/// memory model: what a renderer on it runs as given (negative controls edit this plan).
inline CompiledGraph compileText(const std::string& json, FeatureValues features = {}) {
    GraphDesc graph = parseGraph(json, "<test>", PassRegistry::withBuiltins());
    CompileOptions o = sizedOptions();
    o.features = std::move(features);
    o.memory = sharedDevice().memoryModel();
    o = headless(graph, std::move(o));
    return CompiledGraph(std::move(graph), std::move(o));
}

/// Every test fixture starts with a clean message count and fails on any message.
class ExecutorTest : public ::testing::Test {
protected:
    void SetUp() override {
        // Work outside any test's own check (a suite's SetUpTestSuite, or a plain TEST on the
        // shared device) answers for its messages here, in the next test that checks.
        EXPECT_EQ(sharedDevice().messageCount(), 0u)
            << "messages from work before this test (a suite's setup, or a test that checks none):\n"
            << formatMessages(sharedDevice());
        EXPECT_EQ(unexplainedPerformanceWarnings(sharedDevice()), "")
            << "performance warnings from work before this test";
        sharedDevice().clearMessages();
    }
    void TearDown() override {
        if (expectClean_) {
            EXPECT_EQ(sharedDevice().messageCount(), 0u) << formatMessages(sharedDevice());
            EXPECT_EQ(unexplainedPerformanceWarnings(sharedDevice()), "");
        }
        sharedDevice().clearMessages();
    }
    /// For negative controls: messages are expected and checked by the test itself.
    void allowMessages() { expectClean_ = false; }

    /// Renders `frames` frames with 2 in flight and returns the last read-back.
    ImageData render(const CompiledGraph& c, uint32_t frames = 3) {
        if (std::getenv("SKYGRAPH_TEST_DUMP")) std::printf("%s\n", planToText(c.plan()).c_str());
        Renderer r(sharedDevice(), c, genericOptions(2));
        for (uint32_t i = 0; i < frames; ++i) r.renderFrame();
        ImageData img = r.readback();
        r.waitIdle();
        return img;
    }

private:
    bool expectClean_ = true;
};

#define EXPECT_PIXEL_NEAR(img, x, y, r, g, b, a)                                      \
    do {                                                                              \
        const auto px_ = (img).pixel((x), (y));                                       \
        EXPECT_NEAR(px_[0], (r), 0.01) << "pixel (" << (x) << "," << (y) << ") red";   \
        EXPECT_NEAR(px_[1], (g), 0.01) << "pixel (" << (x) << "," << (y) << ") green"; \
        EXPECT_NEAR(px_[2], (b), 0.01) << "pixel (" << (x) << "," << (y) << ") blue";  \
        EXPECT_NEAR(px_[3], (a), 0.01) << "pixel (" << (x) << "," << (y) << ") alpha"; \
    } while (0)

}  // namespace skygraph::test
