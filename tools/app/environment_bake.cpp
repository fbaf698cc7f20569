// bakeEnvironment: graphs/ibl.json compiled for the products asked for (the compiler culls the
// passes of the others), run once on the equirect image. bakeAndReadBack: the cubemap
// command's sizes, formats and sample counts applied to the graph first, and every level of
// the products read back afterwards.
#include "environment_bake.hpp"

#include "environment_graph.hpp"
#include "printable_name.hpp"
#include "shipped_names.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/format.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/shading_math.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace skygraph::app {
namespace {

using namespace shipped;
using Clock = std::chrono::steady_clock;

double msBetween(Clock::time_point from, Clock::time_point to) {
    return std::chrono::duration<double, std::milli>(to - from).count();
}
double msSince(Clock::time_point t) { return msBetween(t, Clock::now()); }

ResourceDesc& resource(GraphDesc& graph, std::string_view name) {
    for (auto& r : graph.resources)
        if (r.name == name) return r;
    throw std::invalid_argument("the environment graph has no resource '" + std::string(name) + "'");
}

void setFormat(ResourceDesc& r, VkFormat format) { r.format = *findFormat(format); }

/// Sizes, formats and sample counts of graphs/ibl.json for this bake; returns the products to
/// build: the environment cube and those asked for.
std::set<std::string, std::less<>> configure(GraphDesc& graph, const BakeOptions& o) {
    static const std::vector<std::string_view> known{kIrradiance, kPrefiltered, kBrdfLut};
    std::set<std::string, std::less<>> products{std::string(kEnvironment)};
    for (const auto& p : o.products) {
        if (std::find(known.begin(), known.end(), p) == known.end())
            throw std::invalid_argument("unknown product '" + p + "'; expected " + std::string(kIrradiance) + ", " +
                                        std::string(kPrefiltered) + ", " + std::string(kBrdfLut));
        products.insert(p);
    }
    // Mip 0 of the prefiltered cube is the mirror; half the environment's size is the
    // shipped graph's choice (a quarter of the texels to convolve at the sharpest rough mips).
    const uint32_t prefiltered = o.prefilteredSize ? o.prefilteredSize : std::max(o.size / 2, 32u);
    resource(graph, kEnvironment);  // both must exist: the error names the one missing
    resource(graph, kPrefiltered);
    resizeEnvironmentGraph(graph, EnvironmentSizes{o.size, prefiltered});
    const VkFormat colour = o.float32 ? VK_FORMAT_R32G32B32A32_SFLOAT : VK_FORMAT_R16G16B16A16_SFLOAT;
    for (std::string_view name : {kEnvironment, kIrradiance, kPrefiltered}) setFormat(resource(graph, name), colour);
    setFormat(resource(graph, kBrdfLut), o.float32 ? VK_FORMAT_R32G32_SFLOAT : VK_FORMAT_R16G16_SFLOAT);
    for (auto& pass : graph.passes)
        if (pass.type == kIrradiancePass || pass.type == kPrefilterPass) pass.params[std::string(kSamplesParam)] = o.samples;
        else if (pass.type == kEquirectToCubemapPass) pass.params[std::string(kSupersampleParam)] = o.supersample;
    return products;
}

}  // namespace

ImageData toImageData(HdrImage image) {
    ImageData data;
    data.width = image.width;
    data.height = image.height;
    data.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    data.rgba = std::move(image.rgba);
    return data;
}

HdrImage loadEnvironmentImage(const std::filesystem::path& file, float largest) {
    HdrImage image = loadHdrImage(file);
    // Every command that bakes or renders a sky says so, not only `cubemap`.
    if (image.width != 2 * image.height)
        spdlog::warn("'{}' is {}x{}, not 2:1; it is read as an equirect map all the same",
                     printableName(file.string()), image.width, image.height);
    if (const size_t bad = countNonFinite(image))
        throw ImageError(file, std::to_string(bad) + " pixel values are NaN or infinite; an environment must be finite");
    // Radiance is never negative, but filters (an EXR's denoiser, its resampling) leave small
    // negative colours behind: the bakes' sums would take them as light taken away.
    size_t clamped = 0, negative = 0;
    for (size_t i = 0; i < image.rgba.size(); ++i) {
        float& v = image.rgba[i];
        if (i % 4 < 3 && v < 0.0f) {
            v = 0.0f;
            ++negative;
        } else if (std::abs(v) > largest) {
            v = std::copysign(largest, v);
            ++clamped;
        }
    }
    if (clamped)
        spdlog::warn("'{}': {} pixel values past +-{} (the products' largest) are clamped to it",
                     printableName(file.string()), clamped, largest);
    if (negative)
        spdlog::warn("'{}': {} colour values below 0 are clamped to 0: radiance is never negative",
                     printableName(file.string()), negative);
    return image;
}

namespace {

/// Compiles `graph` for `products`, makes its renderer and uploads `equirect`: a bake ready
/// to render its one frame.
EnvironmentBake prepareBake(Device& device, GraphDesc graph, const HdrImage& equirect,
                            const std::set<std::string, std::less<>>& products, const PassLibrary* passes,
                            const BakeStepCallback& onStep, std::shared_ptr<ShaderCompiler> shaders) {
    const auto step = [&](const char* name) {
        if (onStep) onStep(name);
    };
    const auto start = Clock::now();
    if (!setEquirectExtent(graph, equirect.width, equirect.height))
        throw ExecutorError("the environment graph '" + graph.name + "' has no resource '" + std::string(kEquirect) +
                            "'");
    CompileOptions co;
    co.outputs = products;
    co.memory = device.memoryModel();  // what the renderer compiles with: it would compile again
    co.queueFamilies = device.queueFamilies();
    CompiledGraph compiled(std::move(graph), co);
    step("compile");
    RendererOptions ro;
    ro.framesInFlight = 1;
    ro.passes = passes;
    ro.shaderCompiler = std::move(shaders);
    EnvironmentBake bake;
    bake.renderer = std::make_unique<Renderer>(device, std::move(compiled), ro);
    bake.renderer->setExternalImage(std::string(kEquirect), toImageData(equirect));
    step("upload");
    bake.setupMs = msSince(start);
    return bake;
}

}  // namespace

EnvironmentBake bakeEnvironment(Device& device, GraphDesc graph, const HdrImage& equirect,
                                const std::set<std::string, std::less<>>& products, const PassLibrary* passes,
                                const BakeStepCallback& onStep, std::shared_ptr<ShaderCompiler> shaders) {
    EnvironmentBake bake = prepareBake(device, std::move(graph), equirect, products, passes, onStep, std::move(shaders));
    const auto gpuStart = Clock::now();
    bake.renderer->renderFrame();
    bake.renderer->waitIdle();
    bake.gpuMs = msSince(gpuStart);
    if (onStep) onStep("passes");
    return bake;
}

EnvironmentBaker::EnvironmentBaker(Device& device, GraphDesc graph, uint32_t width, uint32_t height,
                                   std::set<std::string, std::less<>> products, const PassLibrary* passes,
                                   bool background, uint32_t renderers, std::shared_ptr<ShaderCompiler> shaders)
    : width_(width), height_(height), staging_(device, rgba32fBytes(width, height)), products_(std::move(products)), background_(background) {
    if (renderers < 2 || renderers > 3)
        throw std::invalid_argument("EnvironmentBaker: 2 or 3 renderers, not " + std::to_string(renderers));
    if (!setEquirectExtent(graph, width, height))
        throw ExecutorError("the environment graph '" + graph.name + "' has no resource '" + std::string(kEquirect) +
                            "'");
    if (std::none_of(graph.features.begin(), graph.features.end(),
                     [](const FeatureDecl& f) { return f.name == kStreamedEquirectFeature; }))
        throw ExecutorError("the environment graph '" + graph.name + "' has no feature '" +
                            std::string(kStreamedEquirectFeature) + "' (an UploadPass of '" + std::string(kEquirect) +
                            "' for re-bakes)");
    // The upload keeps the queue the graph gives it (the transfer queue); the bake's passes
    // run beside the frames on the compute queue.
    for (PassDesc& pass : graph.passes)
        if (!background) pass.queue = QueueKind::Graphics;
        else if (pass.queue == QueueKind::Graphics) pass.queue = QueueKind::Compute;
    CompileOptions co;
    co.features[std::string(kStreamedEquirectFeature)] = true;
    co.outputs = products_;
    co.memory = device.memoryModel();
    co.queueFamilies = device.queueFamilies();
    const CompiledGraph compiled(std::move(graph), co);
    RendererOptions ro;
    ro.framesInFlight = 1;
    ro.passes = passes;
    ro.timestamps = false;  // nothing reads them, and reading them on lavapipe waits for the frames' work
    ro.shaderCompiler = std::move(shaders);
    for (uint32_t i = 0; i < renderers; ++i) renderers_.push_back(std::make_unique<Renderer>(device, compiled, ro));
}

SharedImage EnvironmentBaker::swappedIn(const std::string& name) const {
    return swapped_ ? renderers_[*swapped_]->shareImage(name) : SharedImage();
}

bool EnvironmentBaker::start(const HdrImage& equirect) {
    if (pending_) return false;
    const auto begin = Clock::now();
    if (equirect.width != width_ || equirect.height != height_ || equirect.rgba.size() * sizeof(float) != stagingBytes())
        throw ExecutorError("the environment bake takes a " + std::to_string(width_) + "x" + std::to_string(height_) +
                            " equirect, not " + std::to_string(equirect.width) + "x" +
                            std::to_string(equirect.height));
    const bool started = start(staging_.stage(equirect.rgba));
    lastStartMs_ = msSince(begin);  // the copy included
    return started;
}

bool EnvironmentBaker::start(std::shared_ptr<const StagingBuffer> pixels) {
    if (pending_) return false;
    const auto begin = Clock::now();
    Renderer& r = *renderers_[next_];
    // Its products were last sampled by frames before the previous swap (with three
    // renderers, the one before); the bake's first submit, on the graphics queue, orders its
    // writes after all of them.
    r.stageUpload(std::string(kEquirect), std::move(pixels));
    if (background_) {
        r.renderFrameInBackground();
    } else {
        r.renderFrame();
        r.waitIdle();
    }
    pending_ = true;
    lastStartMs_ = msSince(begin);
    return true;
}

bool EnvironmentBaker::swapInWhenFinished(Renderer& frame) {
    if (!pending_) return false;
    Renderer& r = *renderers_[next_];
    if (!r.finishBackgroundFrame()) return false;
    for (const auto& name : products_) frame.importImage(name, r.shareImage(name));
    pending_ = false;
    swapped_ = next_;
    next_ = (next_ + 1) % renderers_.size();
    return true;
}

BakeResult bakeAndReadBack(const HdrImage& equirect, const BakeOptions& options) {
    const auto start = Clock::now();
    static const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = parseGraph(options.graphText, std::string(kCubemapGraphName), library.registry());
    const std::set<std::string, std::less<>> products = configure(graph, options);
    DeviceOptions deviceOptions;
    deviceOptions.device = options.device;
    deviceOptions.validation = options.validate;
    auto device = Device::create(deviceOptions);
    const auto bakeStart = Clock::now();
    EnvironmentBake bake = bakeEnvironment(*device, std::move(graph), equirect, products, &library, options.onStep);
    BakeResult result;
    result.setupMs = msBetween(start, bakeStart) + bake.setupMs;
    result.gpuMs = bake.gpuMs;
    result.passTimings = bake.renderer->lastTimings();
    for (const auto& name : products) result.products[name] = bake.renderer->readImage(name);
    result.validationMessages = device->messageCount();
    if (options.onStep) options.onStep("read back");
    return result;
}

}  // namespace skygraph::app
