// Per-pass frame timings through the framework (see gpu_frames.hpp).
#include "gpu_frames.hpp"

#include "gpu_vk.hpp"
#include "renderer_access.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

namespace skygraph::gpubench {
namespace {

/// The fewest bytes a pass moves through memory if it touches every texel of each usage's
/// subresources once: reads for Read/ReadWrite (attachments only when loaded), writes for
/// Write/ReadWrite (attachments only when stored). Texture reads of small, cached inputs
/// (an environment map) and buffers are counted the same way; clears count their writes.
double bytesOfPass(const PlannedPass& pass, const Plan& plan, const GraphDesc& graph, uint32_t width,
                   uint32_t height) {
    double bytes = 0;
    for (const PlannedUsage& u : pass.usages) {
        const ResourceDesc& r = graph.resources[plan.resources()[u.resource].decl];
        double size = 0;
        if (r.isImage()) {
            const auto [w, h] = r.extent.resolve(width, height);
            for (uint32_t m = u.range.baseMip; m < u.range.baseMip + u.range.mipCount; ++m)
                size += double(std::max(1u, w >> m)) * double(std::max(1u, h >> m)) * r.format.bytesPerTexel;
            size *= u.range.layerCount;
        } else {
            size = static_cast<double>(r.sizeBytes);
        }
        const bool attachment = isAttachmentStage(u.usage.stage);
        const bool clearPass = pass.type == "Clear";
        if (!clearPass && readsContents(u.usage.access) && (!attachment || u.load == LoadOp::Load)) bytes += size;
        if (clearPass || (writesContents(u.usage.access) && (!attachment || u.store == StoreOp::Store)))
            bytes += size;
    }
    return bytes;
}

std::string attachmentOps(const PlannedPass& pass, const Plan& plan, const GraphDesc& graph) {
    static constexpr const char* kLoad[] = {"Load", "Clear", "DontCare"};
    static constexpr const char* kStore[] = {"Store", "DontCare", "None"};
    std::string text;
    for (const PlannedUsage& u : pass.usages) {
        if (!isAttachmentStage(u.usage.stage)) continue;
        const ResourceDesc& r = graph.resources[plan.resources()[u.resource].decl];
        if (!text.empty()) text += "; ";
        text += r.name + " " + std::string(r.format.name) + " " + kLoad[int(u.load)] + "/" + kStore[int(u.store)];
    }
    return text;
}

/// An equirect sky with real HDR range: a horizon-to-zenith gradient, a darker ground and a
/// small sun about 2000 times brighter than the sky, so the filtering passes see the
/// contrast an HDRI has. Row 0 is the zenith.
ImageData proceduralSky(const ResourceDesc& r) {
    const auto [w, h] = r.extent.resolve(1, 1);
    ImageData image;
    image.width = w;
    image.height = h;
    image.format = r.format.format;
    image.rgba.resize(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y) {
        const double elevation = 1.5707963 - 3.1415927 * (y + 0.5) / h;  // +pi/2 at the top
        for (uint32_t x = 0; x < w; ++x) {
            const double azimuth = 6.2831853 * (x + 0.5) / w;
            const double up = std::max(0.0, std::sin(elevation));
            double rgb[3] = {0.3 + 0.5 * up, 0.45 + 0.6 * up, 0.7 + 1.2 * up};
            if (elevation < 0) rgb[0] = rgb[1] = rgb[2] = 0.08 + 0.02 * std::cos(8 * azimuth);
            const double sunDistance = std::hypot(elevation - 0.7, (azimuth - 2.0) * std::cos(elevation));
            if (sunDistance < 0.03) rgb[0] = rgb[1] = rgb[2] = 2000.0;
            float* px = &image.rgba[(size_t(y) * w + x) * 4];
            for (int c = 0; c < 3; ++c) px[c] = static_cast<float>(rgb[c]);
            px[3] = 1.0f;
        }
    }
    return image;
}

/// A graph file's JSON for a named variant of gpu_frames.hpp; throws std::invalid_argument for
/// an unknown name or a graph without what the variant changes.
GraphDesc loadGraph(const FrameCase& c, const PassRegistry& registry) {
    if (c.variant.empty() || c.variant == "compute-tonemap") return loadGraphFile(c.graph, registry);
    if (c.variant != "unorm-swapchain")
        throw std::invalid_argument("unknown graph variant '" + c.variant + "' (unorm-swapchain, compute-tonemap)");
    std::ifstream in(c.graph);
    if (!in) throw std::runtime_error("cannot read " + c.graph.string());
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json graph = nlohmann::json::parse(text.str());
    auto& resources = graph.at("resources");
    if (!resources.contains("swapchain"))
        throw std::invalid_argument(c.graph.string() + "@unorm-swapchain: the graph has no resource 'swapchain'");
    resources["swapchain"]["format"] = "B8G8R8A8_UNORM";  // TonemappingPass then encodes sRGB in the shader
    graph["name"] = graph.value("name", std::string("graph")) + "@unorm-swapchain";
    return parseGraph(graph.dump(2), c.graph.string() + "@unorm-swapchain", registry);
}

/// The procedural sky at 1024x512, texel centres: `skygraph render` bakes the same sky
/// (tools/app/procedural_environment.cpp) with its sun's texels supersampled, which changes
/// no pass's cost.
HdrImage proceduralSkyImage() {
    HdrImage image;
    image.width = 1024;
    image.height = 512;
    image.rgba.reserve(size_t(image.width) * image.height * 4);
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const auto c = math::proceduralSky(
                math::equirectToDirection(glm::dvec2((x + 0.5) / image.width, (y + 0.5) / image.height)));
            image.rgba.insert(image.rgba.end(), {float(c.x), float(c.y), float(c.z), 1.0f});
        }
    return image;
}

/// A scene's environment, as `skygraph render` uses it (tools/app/render.cpp): its file, or
/// the procedural sky as an equirect; the graph's "equirect" takes the image's extent and pixels, and graphs/ibl.json beside the
/// graph bakes, once and untimed, the products the plan imports (environment, irradiance,
/// prefiltered, brdf_lut), which the measured renderer then samples.
class EnvironmentFile {
public:
    EnvironmentFile(const Scene* scene, GraphDesc& graph) {
        if (!scene || !scene->environment) return;
        image_ = scene->environment->procedural ? proceduralSkyImage() : loadHdrImage(scene->environment->file);
        for (ResourceDesc& r : graph.resources)
            if (r.name == "equirect") r.extent = Extent{false, 1, image_->width, image_->height};
    }

    /// Bakes the products `plan` imports with `library`'s passes and hands them and the
    /// equirect image to `renderer`. Does nothing without an environment.
    void install(Device& device, const std::filesystem::path& graphFile, const GraphDesc& graph,
                 const PassLibrary& library, Renderer& renderer) {
        if (!image_) return;
        GraphDesc ibl = loadGraphFile(graphFile.parent_path() / "ibl.json", library.registry());
        std::set<std::string, std::less<>> products;
        for (const PlannedResource& r : renderer.plan().resources()) {
            const ResourceDesc& d = graph.resources[r.decl];
            const ResourceDesc* produced = ibl.findResource(d.name);
            if (d.external && d.name != "equirect" && produced && produced->isExported()) products.insert(d.name);
        }
        if (renderer.plan().resourceIndex("equirect") >= 0) renderer.setExternalImage("equirect", pixels());
        if (products.empty()) return;
        for (ResourceDesc& r : ibl.resources)
            if (r.name == "equirect") r.extent = Extent{false, 1, image_->width, image_->height};
        CompileOptions co;
        co.outputs = products;
        RendererOptions ro;
        ro.framesInFlight = 1;
        ro.passes = &library;
        baker_ = std::make_unique<Renderer>(device, CompiledGraph(std::move(ibl), co), ro);
        baker_->setExternalImage("equirect", pixels());
        baker_->renderFrame();
        baker_->waitIdle();
        for (const auto& name : products) renderer.importImage(name, baker_->shareImage(name));
    }

    /// Whether the environment image fills the graph resource `name`.
    [[nodiscard]] bool provides(const std::string& name) const { return image_ && name == "equirect"; }

private:
    [[nodiscard]] ImageData pixels() const {
        ImageData d;
        d.width = image_->width;
        d.height = image_->height;
        d.format = VK_FORMAT_R32G32B32A32_SFLOAT;
        d.rgba = image_->rgba;
        return d;
    }

    std::optional<HdrImage> image_;
    std::unique_ptr<Renderer> baker_;  // owns the products the measured renderer samples
};

}  // namespace

FrameResult measureFrames(Device& device, const FrameCase& c) {
    static const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = loadGraph(c, library.registry());
    std::optional<Scene> scene;
    if (!c.scene.empty()) scene = loadSceneFile(c.scene);
    EnvironmentFile environment(scene ? &*scene : nullptr, graph);
    CompileOptions co;
    if (scene) co.features = sceneFeatures(*scene);
    if (c.variant == "compute-tonemap") {
        if (std::none_of(graph.features.begin(), graph.features.end(),
                         [](const FeatureDecl& f) { return f.name == "compute_tonemap"; }))
            throw std::invalid_argument(c.graph.string() + "@compute-tonemap: the graph has no feature 'compute_tonemap'");
        co.features["compute_tonemap"] = true;
    }
    co.presentReplacement = ExternalState::TransferSrc;
    co.outputWidth = c.width;
    co.outputHeight = c.height;
    CompiledGraph compiled(graph, co);
    // No read-back copy unless a picture is asked for: the frame is the plan's passes alone.
    // The picture is the Present target the plan writes (a graph may declare one per feature).
    if (!c.png.empty()) {
        for (const ResourceDesc& r : graph.resources)
            if (r.final == ExternalState::Present && compiled.plan().resourceIndex(r.name) >= 0)
                co.readbacks.insert(r.name);
        compiled = CompiledGraph(graph, co);
    }
    const Plan& plan = compiled.plan();
    FrameResult result;
    for (const auto& culled : plan.culled()) result.culled.push_back(culled.name + ": " + culled.reason);
    std::map<std::string, PassResult> byName;
    std::vector<std::string> order;
    for (const PlannedPass& p : plan.passes()) {
        byName[std::string(p.name)] = {std::string(p.name), std::string(p.type), bytesOfPass(p, plan, graph, c.width, c.height),
                          attachmentOps(p, plan, graph), 0, 0, 0};
        order.emplace_back(p.name);
    }

    RendererOptions ro;
    ro.framesInFlight = 1;
    ro.passes = &library;
    Renderer renderer(device, std::move(compiled), ro);
    if (scene) renderer.frameData().set(*scene);
    environment.install(device, c.graph, graph, library, renderer);
    for (const std::string& name : c.proceduralExternals) {
        const auto it = std::find_if(graph.resources.begin(), graph.resources.end(),
                                     [&](const ResourceDesc& r) { return r.name == name; });
        if (it == graph.resources.end() || environment.provides(name)) continue;  // another run's, or the file's
        if (!it->isImage() || !it->external)
            throw ExecutorError(c.graph.string() + ": procedural sky for '" + name + "': not an external image");
        renderer.setExternalImage(name, proceduralSky(*it));
        result.proceduralExternals.push_back(name);
    }

    for (uint32_t i = 0; i < c.warmupFrames; ++i) renderer.renderFrame();
    renderer.waitIdle();
    std::map<std::string, std::vector<double>> samples;
    for (uint32_t i = 0; i < c.frames; ++i) {
        renderer.renderFrame();
        renderer.waitIdle();  // one frame at a time: each pass's timestamps are its own frame's
        for (const PassTiming& t : renderer.lastTimings()) samples[t.pass].push_back(t.milliseconds);
    }
    for (const std::string& name : order) {
        PassResult r = byName[name];
        const auto& s = samples[name];
        r.medianMs = median(s);
        r.p10Ms = quantile(s, 0.1);
        r.p90Ms = quantile(s, 0.9);
        result.passes.push_back(r);
    }
    // The same plan recorded without the per-pass timestamps, timed as a whole. A plan on
    // several queues is several command buffers whose queues may overlap: it is timed on the
    // host from renderFrame() to the end of waitIdle(), one frame at a time.
    std::vector<double> frameMs;
    result.hostTimed = renderer.plan().submits().size() > 1;
    if (result.hostTimed) {
        for (uint32_t i = 0; i < c.frames; ++i) {
            const auto start = std::chrono::steady_clock::now();
            renderer.renderFrame();
            renderer.waitIdle();
            frameMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        }
    } else {
        GpuTimer timer(device);
        for (uint32_t i = 0; i < c.frames; ++i)
            frameMs.push_back(timer.time([&](VkCommandBuffer cmd) { RendererAccess::recordInto(renderer, cmd, 0); }));
    }
    result.frameMedianMs = median(frameMs);
    if (!c.png.empty()) {
        renderer.renderFrame();  // recordInto left slot 0's contents; a full frame fills the read-back
        writePng(c.png, renderer.readback());
    }
    result.frames = c.frames;
    return result;
}

}  // namespace skygraph::gpubench
