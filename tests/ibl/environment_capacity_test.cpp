// An environment bake the device cannot hold is named where its size comes from. A cube sized
// for the view is the least of what the environment file's width holds, what the view
// resolves and what the frame graph declares: the file is named when its width set the size,
// else the frame graph's declaration. A cube built at the size the environment graph declares
// is that graph's resource, and resources each within the device's limits that are too large
// only together are that graph's too. Each fails on lavapipe (its memory cap is 1 GiB) before
// anything is allocated, and validation stays silent.
#include "executor_test_util.hpp"

#include "app/render.hpp"
#include "read_file.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include <unistd.h>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;

/// `graph` with its cube `name` declared `face` texels a side.
std::string withCubeFace(std::string graph, const std::string& name, uint32_t face) {
    const std::regex declared("\"" + name + R"(":\s*\{[^}]*?"extent":\s*(\[\s*\d+,\s*\d+\s*\]))");
    std::smatch m;
    if (!std::regex_search(graph, m, declared)) {
        ADD_FAILURE() << "no " << name << " extent to resize";
        return graph;
    }
    const std::string size = std::to_string(face);
    return graph.replace(static_cast<size_t>(m.position(1)), static_cast<size_t>(m.length(1)), "[" + size + ", " + size + "]");
}

/// `graph` with its `environment` cube declared `face` texels a side (the shipped graphs
/// declare 256).
std::string withEnvironmentFace(std::string graph, uint32_t face) { return withCubeFace(std::move(graph), "environment", face); }

/// The memory cap a renderer holds all of a plan's resources to (docs/reliability.md, "Faults",
/// an extent too large): half the device's largest device-local heap.
VkDeviceSize memoryCap(const Device& device) {
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(device.physicalDevice(), &memory);
    VkDeviceSize largest = 0;
    for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
        if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            largest = std::max(largest, memory.memoryHeaps[i].size);
    return largest / 2;
}

/// The bytes of an R16G16B16A16_SFLOAT cube `face` texels a side with `mips` levels.
VkDeviceSize rgba16fCubeBytes(uint32_t face, uint32_t mips) {
    VkDeviceSize texels = 0;
    for (uint32_t mip = 0; mip < mips; ++mip) texels += VkDeviceSize(std::max(face >> mip, 1u)) * std::max(face >> mip, 1u);
    return texels * 6 * 8;
}

class EnvironmentCapacity : public ExecutorTest {
protected:
    EnvironmentCapacity() {
        dir_ = fs::temp_directory_path() / ("skygraph_environment_capacity_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        // As wide as an image may be (16384) and 2 texels tall: 256 KiB of pixels, whose
        // width alone asks a view-sized cube of 8192^2.
        const uint32_t width = 16384, height = 2;
        saveHdrImage(dir_ / "wide.hdr", HdrImage{width, height, std::vector<float>(size_t(width) * height * 4, 0.5f)});
        declareFrameEnvironment(16384);
        options_.sceneText = R"({"camera": {"fov_y_deg": 40},
            "environment": {"file": ")" + (dir_ / "wide.hdr").string() + R"(", "sampling": "cubemap"}})";
        options_.environmentGraphText = withEnvironmentFace(shippedGraph("ibl.json"), 16384);
        options_.width = 64;
        options_.height = 4096;  // 4096 / tan(20 degrees): a face of 16384 resolves its pixels
        options_.device = "llvmpipe";
    }
    ~EnvironmentCapacity() override { fs::remove_all(dir_); }

    /// The frame graph's `environment` declared `face` texels a side: the largest cube the
    /// view may ask for.
    void declareFrameEnvironment(uint32_t face) { options_.graphText = withEnvironmentFace(shippedGraph("raster.json"), face); }

    static std::string shippedGraph(const char* name) {
        return files::readFile(fs::path(SKYGRAPH_SOURCE_DIR) / "graphs" / name).value();
    }

    /// The diagnostics of the bake's failure, which must be `Error`.
    template <typename Error>
    std::vector<Diagnostic> bakeFailure() {
        app::FrameInputs inputs = app::loadFrameInputs(options_);
        const Plan plan = compile(inputs.graph, inputs.compile);
        try {
            (void)app::bakeFrameEnvironment(sharedDevice(), plan, inputs, options_);
            ADD_FAILURE() << "the bake was accepted";
        } catch (const Error& e) {
            return e.diagnostics().items();
        }
        return {};
    }

    fs::path dir_;
    app::RenderOptions options_;
};

/// One diagnostic, naming the environment cube at its declaration in `graph` and not the file.
void expectNamedAtDeclaration(const std::vector<Diagnostic>& d, const std::string& graph) {
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].file, graph);
    EXPECT_EQ(d[0].jsonPath, "resources.environment");
    EXPECT_EQ(d[0].message.find("wide.hdr"), std::string::npos) << "the file is not to blame: " << d[0].message;
    EXPECT_NE(d[0].message.find("resource 'environment' needs"), std::string::npos) << d[0].message;
}

TEST_F(EnvironmentCapacity, AViewSizedCubeTooLargeNamesTheEnvironmentFile) {
    const std::vector<Diagnostic> d = bakeFailure<SceneError>();
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].jsonPath, "environment.file");
    EXPECT_NE(d[0].message.find("wide.hdr' (16384x2) is too large for this device to bake: resource 'environment'"),
              std::string::npos)
        << d[0].message;
    EXPECT_NE(d[0].message.find("over the memory cap"), std::string::npos) << d[0].message;
}

TEST_F(EnvironmentCapacity, AViewSizedCubeCappedByTheFrameGraphNamesItsDeclaration) {
    declareFrameEnvironment(8192);  // the file's width holds 8192 too: the declaration caps it
    expectNamedAtDeclaration(bakeFailure<GraphError>(), "<built-in raster.json>");  // the frame graph
}

TEST_F(EnvironmentCapacity, ACubeAtItsDeclaredSizeNamesTheEnvironmentGraph) {
    options_.fitEnvironmentToView = false;  // built at 16384^2, as declared
    const std::vector<Diagnostic> d = bakeFailure<GraphError>();
    expectNamedAtDeclaration(d, "<built-in ibl.json>");  // not the scene
    ASSERT_FALSE(d.empty());
    EXPECT_NE(d[0].message.find("over the memory cap"), std::string::npos) << d[0].message;
}

// The environment cube and the prefiltered cube, each within every limit of the device and
// each over half the memory cap, so that the bake's resources together are over it: no one
// resource is to blame, and the environment graph is named. Built with the built-in passes
// (an object in the scene makes the frame sample the prefiltered cube, so the bake builds it).
TEST_F(EnvironmentCapacity, ResourcesTooLargeOnlyTogetherNameTheEnvironmentGraph) {
    const PassLibrary library = PassLibrary::withBuiltins();
    options_.passes = &library;
    options_.fitEnvironmentToView = false;  // both cubes built as the environment graph declares them
    options_.sceneText = R"({"camera": {"fov_y_deg": 40},
        "environment": {"file": ")" + (dir_ / "wide.hdr").string() + R"(", "sampling": "cubemap"},
        "objects": [{"type": "sphere", "center": [0, 0, -3], "radius": 1,
                     "material": {"base_color": [0.8, 0.8, 0.8], "metallic": 1, "roughness": 0.5, "ao": 1}}]})";
    const VkDeviceSize cap = memoryCap(sharedDevice());
    ASSERT_GT(cap, 0u);
    // Each cube about 0.6 of the cap: (4/3) x 6 faces x 8 bytes is 64 bytes a texel of mip 0.
    const uint32_t face = uint32_t(std::sqrt(0.6 * double(cap) / 64.0)) / 32 * 32;
    const uint32_t prefilteredMips = 6;  // as graphs/ibl.json declares
    const VkDeviceSize environmentBytes = rgba16fCubeBytes(face, uint32_t(std::log2(face)) + 1);
    const VkDeviceSize prefilteredBytes = rgba16fCubeBytes(face, prefilteredMips);
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(sharedDevice().physicalDevice(), &properties);
    // Two cubes of the largest side a graph and the device allow must be able to pass the cap
    // (lavapipe's, a gigabyte, they do); a device with a larger heap cannot run this case.
    ASSERT_LE(face, std::min<uint32_t>(16384, properties.limits.maxImageDimensionCube))
        << "the memory cap of " << cap << " bytes takes cubes of " << face << " texels a side";
    ASSERT_LE(environmentBytes, cap);
    ASSERT_LE(prefilteredBytes, cap);
    ASSERT_GT(environmentBytes + prefilteredBytes, cap);
    options_.environmentGraphText =
        withCubeFace(withEnvironmentFace(shippedGraph("ibl.json"), face), "prefiltered", face);

    const uint64_t allocatedBefore = sharedDevice().allocatedBytes();
    const std::vector<Diagnostic> d = bakeFailure<GraphError>();
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].file, "<built-in ibl.json>");  // not the scene, nor the frame graph
    EXPECT_EQ(d[0].jsonPath, "");                 // no one resource's declaration
    EXPECT_EQ(d[0].message.rfind("the environment bake: the plan's resources need ", 0), 0u) << d[0].message;
    EXPECT_NE(d[0].message.find("over the memory cap"), std::string::npos) << d[0].message;
    EXPECT_NE(d[0].message.find("nothing was allocated"), std::string::npos) << d[0].message;
    EXPECT_EQ(d[0].message.find("resource '"), std::string::npos) << d[0].message;
    EXPECT_EQ(sharedDevice().allocatedBytes(), allocatedBefore);
}

}  // namespace
}  // namespace skygraph::test
