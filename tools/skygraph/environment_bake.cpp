// bakeEnvironment: graphs/ibl.json sized from the options and the input, products not asked
// for un-exported (so the compiler culls their passes), one frame, every level read back.
#include "environment_bake.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/environment_graph.hpp>
#include <skygraph/format.hpp>
#include <skygraph/pass.hpp>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace skygraph::cli {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

ResourceDesc& resource(GraphDesc& graph, const std::string& name) {
    for (auto& r : graph.resources)
        if (r.name == name) return r;
    throw std::invalid_argument("the environment graph has no resource '" + name + "'");
}

void setFormat(ResourceDesc& r, VkFormat format) { r.format = *findFormat(format); }

/// Sizes, formats and outputs of graphs/ibl.json for this bake.
void configure(GraphDesc& graph, const HdrImage& equirect, const BakeOptions& o) {
    static const std::vector<std::string> known{"irradiance", "prefiltered", "brdf_lut"};
    for (const auto& p : o.products)
        if (std::find(known.begin(), known.end(), p) == known.end())
            throw std::invalid_argument("unknown product '" + p + "'; expected irradiance, prefiltered, brdf_lut");
    resource(graph, "equirect").extent = Extent{false, 1, equirect.width, equirect.height};
    // Mip 0 of the prefiltered cube is the mirror; half the environment's size is the
    // shipped graph's choice (a quarter of the texels to convolve at the sharpest rough mips).
    const uint32_t prefiltered = o.prefilteredSize ? o.prefilteredSize : std::max(o.size / 2, 32u);
    resource(graph, "environment");  // both must exist: the error names the one missing
    resource(graph, "prefiltered");
    resizeEnvironmentGraph(graph, EnvironmentSizes{o.size, prefiltered});
    const VkFormat colour = o.float32 ? VK_FORMAT_R32G32B32A32_SFLOAT : VK_FORMAT_R16G16B16A16_SFLOAT;
    for (const char* name : {"environment", "irradiance", "prefiltered"}) setFormat(resource(graph, name), colour);
    setFormat(resource(graph, "brdf_lut"), o.float32 ? VK_FORMAT_R32G32_SFLOAT : VK_FORMAT_R16G16_SFLOAT);
    for (const auto& name : known)
        if (std::find(o.products.begin(), o.products.end(), name) == o.products.end()) {
            ResourceDesc& r = resource(graph, name);
            r.external = false;  // no longer an output: the compiler culls its writers
            r.final = ExternalState::None;
        }
    for (auto& pass : graph.passes)
        if (pass.type == "IrradiancePass" || pass.type == "PrefilterPass") pass.params["samples"] = o.samples;
        else if (pass.type == "EquirectToCubemapPass") pass.params["supersample"] = o.supersample;
}

ImageData toImageData(const HdrImage& image) {
    ImageData data;
    data.width = image.width;
    data.height = image.height;
    data.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    data.rgba = image.rgba;
    return data;
}

}  // namespace

BakeResult bakeEnvironment(const HdrImage& equirect, const BakeOptions& options) {
    const auto step = [&](const char* name) {
        if (options.onStep) options.onStep(name);
    };
    const auto start = Clock::now();
    static const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = parseGraph(options.graphText, "graphs/ibl.json", library.registry());
    configure(graph, equirect, options);
    CompiledGraph compiled(std::move(graph), CompileOptions{});
    step("compile");
    DeviceOptions deviceOptions;
    deviceOptions.device = options.device;
    deviceOptions.validation = options.validate;
    auto device = Device::create(deviceOptions);
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    Renderer renderer(*device, std::move(compiled), ro);
    renderer.setExternalImage("equirect", toImageData(equirect));
    step("upload");
    BakeResult result;
    result.setupMs = msSince(start);
    const auto gpuStart = Clock::now();
    renderer.renderFrame();
    renderer.waitIdle();
    result.gpuMs = msSince(gpuStart);
    result.passTimings = renderer.lastTimings();
    step("passes");
    result.products["environment"] = renderer.readImage("environment");
    for (const auto& name : options.products) result.products[name] = renderer.readImage(name);
    result.validationMessages = device->messageCount();
    step("read back");
    return result;
}

}  // namespace skygraph::cli
