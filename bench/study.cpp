// study: the speed/accuracy sweep on one scene (scenes/default.json, procedural
// sky) at a small output. Each point: wall time per frame, GPU time (the passes' timestamps),
// and the error against a high-precision reference: RMSE and max in linear HDR, and the mean
// and max CIEDE2000 after tonemapping (Little CMS's cmsCIE2000DeltaE on sRGB -> Lab D50).
// Writes a CSV; bench/study_plot.py draws the Pareto plot; docs/tradeoffs.md reads both.
//
//   study [--size 128x96] [--out study.csv] [--device llvmpipe] [--pt-reference-spp 2048]
//         [--environment on|off] [--validate on|off] [--gltf-scene tests/passes/scenes/box_textured_glb.json]
//
// Knobs swept here: the HDR target (fp16 / fp32), each tonemap operator, cube face size and
// supersampling, IBL sample counts, cubemap against direct equirect sampling of the sky (an
// HDR equirect of the procedural sky, baked through graphs/ibl.json per point), path-tracer
// samples per pixel; and, on a glTF model (BoxTextured, textured), the raster IBL frame against
// the path tracer. References: raster points against the fp32 frame tonemapped in double
// precision (include/skygraph/shading_math.hpp); environment points against the richest bake
// (256 faces, 4x4 supersampling, 4096 samples); path-tracer points against the same tracer
// at --pt-reference-spp with an independent sample stream. Also printed: sRGB encode vs pow(1/2.2) and the two ACES fits against
// each other, in 8-bit codes, and each fit against the reference ACES RRT + ODT from OpenColorIO
// (bench/aces_reference.hpp; bench/aces_fits prints that table alone).
#include "delta_e2000.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/format.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/shading_math.hpp>

#include "aces_reference.hpp"

#include <CLI/CLI.hpp>


#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

namespace {

using namespace skygraph;
const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;

struct Options {
    uint32_t width = 128, height = 96;
    std::string out = "study.csv";
    std::string device = "llvmpipe";
    uint32_t ptReferenceSpp = 2048;
    bool environment = true;  ///< --environment off: skip the bakes (smoke runs)
    bool validate = false;    ///< --validate on: validation + sync validation; any message fails the run
    /// The glTF scene of the "glTF model" point, relative to the source tree.
    std::filesystem::path gltfScene = "tests/passes/scenes/box_textured_glb.json";
};

struct Point {
    std::string knob, setting;
    double wallMs = 0, gpuMs = 0, rmseHdr = 0, maxHdr = 0, deMean = 0, deMax = 0;
    double bakeMs = 0;  ///< the environment bake (graphs/ibl.json) the frame needs, once per environment
};

using bench::DeltaE2000;

math::ToneOperator toMath(Tonemapper t) {
    switch (t) {
        case Tonemapper::AcesNarkowicz: return math::ToneOperator::AcesNarkowicz;
        case Tonemapper::AcesHill: return math::ToneOperator::AcesHill;
        case Tonemapper::KhronosPbrNeutral: return math::ToneOperator::KhronosPbrNeutral;
        case Tonemapper::Passthrough: return math::ToneOperator::Passthrough;
    }
    return math::ToneOperator::AcesNarkowicz;
}

/// The display image of an HDR image: tonemap and sRGB encode in double, quantised to 8 bits.
std::vector<double> displayOf(const ImageData& hdr, Tonemapper op, double ev) {
    std::vector<double> out;
    for (size_t i = 0; i < hdr.rgba.size(); i += 4) {
        const auto c = math::tonemap(math::Vec3<double>(hdr.rgba[i], hdr.rgba[i + 1], hdr.rgba[i + 2]), ev, toMath(op));
        for (int k = 0; k < 3; ++k) out.push_back(std::round(math::srgbEncode(c[k]) * 255.0) / 255.0);
    }
    return out;
}

std::vector<double> rgbOf(const ImageData& img) {
    std::vector<double> out;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        for (int k = 0; k < 3; ++k) out.push_back(img.rgba[i + k]);
    return out;
}

void hdrError(const ImageData& got, const ImageData& want, Point& p) {
    double sum = 0, worst = 0;
    size_t n = 0;
    for (size_t i = 0; i < got.rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        const double d = double(got.rgba[i]) - double(want.rgba[i]);
        sum += d * d;
        worst = std::max(worst, std::abs(d));
        ++n;
    }
    p.rmseHdr = std::sqrt(sum / double(std::max<size_t>(n, 1)));
    p.maxHdr = worst;
}

double gpuMs(Renderer& r) {
    double ms = 0;
    for (const PassTiming& t : r.lastTimings()) ms += t.milliseconds;
    return ms;
}

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Every renderer here: one frame in flight so that a frame's wall time is that frame's alone
/// (the output size is each CompileOptions'). `library` must outlive the renderer.
RendererOptions rendererOptions(const PassLibrary& library) {
    RendererOptions ro;
    ro.passes = &library;
    ro.framesInFlight = 1;
    return ro;
}

/// graphs/raster.json for `scene`, with hdr_color exported: the HDR error reads it back.
CompileOptions rasterCompileOptions(const Options& o, const Scene& scene) {
    CompileOptions co;
    co.features = sceneFeatures(scene);
    co.presentReplacement = ExternalState::TransferSrc;
    co.exports = {{"hdr_color", ExternalState::TransferSrc}};
    co.outputWidth = o.width;
    co.outputHeight = o.height;
    return co;
}

struct RasterFrame {
    ImageData hdr, ldr;
    double wallMs = 0, gpuMs = 0;
};

/// The mean of `frames` frames after one untimed warm-up (pipelines, first-use costs), and
/// the last frame's images.
RasterFrame timeRasterFrames(Renderer& renderer, int frames) {
    renderer.renderFrame();
    renderer.waitIdle();
    RasterFrame f;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        renderer.renderFrame();
        renderer.waitIdle();
        f.gpuMs += gpuMs(renderer);
    }
    f.wallMs = msSince(start) / frames;
    f.gpuMs /= frames;
    f.ldr = renderer.readImage("swapchain").at(0);
    f.hdr = renderer.readImage("hdr_color").at(0);
    return f;
}

/// The recording code of every renderer here; lives as long as the program.
const PassLibrary& builtinPasses() {
    static const PassLibrary library = PassLibrary::withBuiltins();
    return library;
}

/// Hands `renderer` the environment products its plan imports, from `baker`.
void importProducts(Renderer& renderer, Renderer& baker) {
    for (const char* product : {"environment", "irradiance", "prefiltered", "brdf_lut"})
        if (renderer.plan().resourceIndex(product) >= 0) renderer.importImage(product, baker.shareImage(product));
}

/// graphs/raster.json with hdr_color in `hdrFormat`, lit by `environment`'s products,
/// rendering `frames` timed frames.
RasterFrame renderRaster(Device& device, const Options& o, const Scene& scene, VkFormat hdrFormat, int frames,
                         Renderer& environment) {
    const PassLibrary& library = builtinPasses();
    GraphDesc graph = loadGraphFile(kSource / "graphs/raster.json", library.registry());
    for (auto& r : graph.resources)
        if (r.name == "hdr_color") r.format = *findFormat(hdrFormat);
    Renderer renderer(device, CompiledGraph(std::move(graph), rasterCompileOptions(o, scene)), rendererOptions(library));
    renderer.frameData().set(scene);
    importProducts(renderer, environment);
    return timeRasterFrames(renderer, frames);
}

/// The procedural sky (sun disc included, 400x the sky) in double, as a w x h equirect map:
/// an HDR environment whose truth is known at every direction.
ImageData skyEquirect(uint32_t w, uint32_t h) {
    ImageData img;
    img.width = w;
    img.height = h;
    img.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const auto d = math::equirectToDirection(glm::dvec2((x + 0.5) / w, (y + 0.5) / h));
            const auto c = math::proceduralSky(d);
            img.rgba.insert(img.rgba.end(), {float(c.x), float(c.y), float(c.z), 1.0f});
        }
    return img;
}

struct EnvironmentKnobs {
    uint32_t faceSize = 256, supersample = 2, samples = 1024;
    bool cubemap = true;  ///< the skybox samples the cube; false: the equirect map directly
};

/// graphs/ibl.json baked with `k` (cube faces of k.faceSize, the mip passes beyond its chain
/// dropped) on `map`; the returned renderer holds the products.
std::unique_ptr<Renderer> bakeStudyEnvironment(Device& device, const ImageData& map, const EnvironmentKnobs& k,
                                               double& bakeMs) {
    const PassLibrary& library = builtinPasses();
    GraphDesc ibl = loadGraphFile(kSource / "graphs/ibl.json", library.registry());
    uint32_t levels = 1;
    while ((k.faceSize >> levels) > 0) ++levels;
    for (auto& r : ibl.resources) {
        if (r.name == "equirect") r.extent = Extent{false, 1, map.width, map.height};
        if (r.name == "environment") r.extent = Extent{false, 1, k.faceSize, k.faceSize};
    }
    std::erase_if(ibl.passes, [&](const PassDesc& p) {
        return p.name.rfind("environment_mip", 0) == 0 && std::stoul(p.name.substr(15)) >= levels;
    });
    for (auto& p : ibl.passes) {
        if (p.name == "equirect_to_cube") p.params["supersample"] = k.supersample;
        if (p.name == "irradiance" || p.name == "prefilter") p.params["samples"] = k.samples;
    }
    RendererOptions bo;
    bo.framesInFlight = 1;
    bo.passes = &library;
    auto baker = std::make_unique<Renderer>(device, CompiledGraph(std::move(ibl), CompileOptions{}), bo);
    baker->setExternalImage("equirect", map);
    const auto start = std::chrono::steady_clock::now();
    baker->renderFrame();
    baker->waitIdle();
    bakeMs = msSince(start);
    return baker;
}

/// `map` baked with `k`, then graphs/raster.json (fp32 target) lit and backed by its products.
RasterFrame renderWithEnvironment(Device& device, const Options& o, Scene scene, const ImageData& map,
                                  const EnvironmentKnobs& k, double& bakeMs) {
    const PassLibrary& library = builtinPasses();
    const std::unique_ptr<Renderer> baker = bakeStudyEnvironment(device, map, k, bakeMs);
    scene.environment = SceneEnvironment{false, "study-sky.hdr", 0.0,
                                         k.cubemap ? EnvironmentSampling::Cubemap : EnvironmentSampling::Equirect};
    GraphDesc graph = loadGraphFile(kSource / "graphs/raster.json", library.registry());
    for (auto& r : graph.resources) {
        if (r.name == "hdr_color") r.format = *findFormat(VK_FORMAT_R32G32B32A32_SFLOAT);
        if (r.name == "equirect") r.extent = Extent{false, 1, map.width, map.height};
        if (r.name == "environment") r.extent = Extent{false, 1, k.faceSize, k.faceSize};
    }
    Renderer renderer(device, CompiledGraph(std::move(graph), rasterCompileOptions(o, scene)), rendererOptions(library));
    renderer.frameData().set(scene);
    importProducts(renderer, *baker);
    if (renderer.plan().resourceIndex("equirect") >= 0) renderer.setExternalImage("equirect", map);
    return timeRasterFrames(renderer, 4);
}

constexpr const char* kPathTraceGraph = R"({
  "version": 1, "name": "study_pathtrace",
  "resources": {
    "accumulation": {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": "output",
                     "external": true, "final": "General"}
  },
  "passes": [
    {"name": "NAME", "type": "PathTracePass", "params": {"samples_per_frame": SPF, "max_bounces": 4},
     "uses": {"accumulation": "ReadWrite@Compute"}}
  ]
})";

struct PathTraceRun {
    std::vector<std::pair<uint32_t, ImageData>> images;  // (spp, mean)
    std::vector<double> wallMs, gpuMs;                   // cumulative, per image
};

/// Samples a frame that reach `spp` exactly, at most 64 (the shipped graph's setting).
uint32_t samplesPerFrameFor(uint32_t spp) { return std::gcd(64u, spp); }

/// The path tracer named `name` (which seeds its samples) at `samplesPerFrame`, read back at
/// each spp of `checkpoints` (multiples of it).
PathTraceRun pathTrace(Device& device, const Options& o, const Scene& scene, const char* name, uint32_t samplesPerFrame,
                       const std::vector<uint32_t>& checkpoints) {
    const PassLibrary library = PassLibrary::withBuiltins();
    std::string text = kPathTraceGraph;
    text.replace(text.find("SPF"), 3, std::to_string(samplesPerFrame));
    text.replace(text.find("NAME"), 4, name);
    const GraphDesc graph = parseGraph(text, "study_pathtrace.json", library.registry());
    CompileOptions co;
    co.outputWidth = o.width;
    co.outputHeight = o.height;
    Renderer renderer(device, CompiledGraph(graph, co), rendererOptions(library));
    renderer.frameData().set(scene);
    PathTraceRun run;
    double wall = 0, gpu = 0;
    uint32_t spp = 0;
    for (const uint32_t target : checkpoints) {
        while (spp < target) {
            const auto start = std::chrono::steady_clock::now();
            renderer.renderFrame();
            renderer.waitIdle();
            wall += msSince(start);
            gpu += gpuMs(renderer);
            spp += samplesPerFrame;
        }
        run.images.emplace_back(spp, renderer.readImage("accumulation").at(0));
        run.wallMs.push_back(wall);
        run.gpuMs.push_back(gpu);
    }
    return run;
}

/// The path-traced truth of `scene` lit by `map`: graphs/pathtrace.json as shipped, with
/// environment_file on and up to 64 samples a frame, after exactly `spp` samples.
ImageData pathTracedTruth(Device& device, const Options& o, Scene scene, const ImageData& map, uint32_t spp,
                          double& wallMs) {
    const PassLibrary library = PassLibrary::withBuiltins();
    GraphDesc graph = loadGraphFile(kSource / "graphs/pathtrace.json", library.registry());
    for (auto& r : graph.resources)
        if (r.name == "equirect") r.extent = Extent{false, 1, map.width, map.height};
    for (auto& p : graph.passes)
        if (p.name == "pathtrace_equirect") p.params["samples_per_frame"] = samplesPerFrameFor(spp);
    scene.environment = SceneEnvironment{false, "study-sky.hdr", 0.0, EnvironmentSampling::Equirect};
    CompileOptions co;
    co.features = {{"environment_file", true}};
    co.presentReplacement = ExternalState::TransferSrc;
    co.outputWidth = o.width;
    co.outputHeight = o.height;
    Renderer renderer(device, CompiledGraph(graph, co), rendererOptions(library));
    renderer.setExternalImage("equirect", map);
    renderer.frameData().set(scene);
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t n = 0; n < spp; n += samplesPerFrameFor(spp)) renderer.renderFrame();
    renderer.waitIdle();
    wallMs = msSince(start);
    return renderer.readImage("accumulation").at(0);
}

/// 8-bit code differences of curves over a log sweep of linear values.
void printCurveTable() {
    int worstGamma = 0;
    double atGamma = 0;
    int worstFits = 0;
    double atFits = 0;
    for (double lg = -8.0; lg <= 8.0; lg += 1.0 / 256) {
        const double x = std::pow(2.0, lg);
        if (x <= 1.0) {
            const int srgb = int(std::lround(math::srgbEncode(x) * 255));
            const int gamma = int(std::lround(std::pow(x, 1.0 / 2.2) * 255));
            if (std::abs(srgb - gamma) > worstGamma) worstGamma = std::abs(srgb - gamma), atGamma = x;
        }
        const math::Vec3<double> grey(x);
        const auto n = math::tonemap(grey, 0.0, math::ToneOperator::AcesNarkowicz);
        const auto h = math::tonemap(grey, 0.0, math::ToneOperator::AcesHill);
        const int cn = int(std::lround(math::srgbEncode(n.r) * 255)), ch = int(std::lround(math::srgbEncode(h.r) * 255));
        if (std::abs(cn - ch) > worstFits) worstFits = std::abs(cn - ch), atFits = x;
    }
    std::printf("curves, 8-bit codes (grey ramp 2^-8..2^8, 256 steps per stop):\n");
    std::printf("  sRGB encode vs pow(x, 1/2.2): worst %d codes at x = %.4g\n", worstGamma, atGamma);
    std::printf("  ACES Narkowicz vs ACES Hill (after sRGB encode): worst %d codes at x = %.4g\n", worstFits, atFits);
}

int run(const Options& o) {
    DeviceOptions dopt;
    dopt.device = o.device;
    dopt.validation = o.validate;
    auto device = Device::create(dopt);
    const DeltaE2000 deltaE;
    Scene scene = loadSceneFile(kSource / "scenes/default.json");
    std::vector<Point> points;

    // The HDR target and each operator: the fp32 frame tonemapped in double is the reference.
    // The procedural sky lights the scene through the shipped bake, as in `skygraph render`.
    double skyBake = 0;
    const std::unique_ptr<Renderer> sky = bakeStudyEnvironment(*device, skyEquirect(1024, 512), {}, skyBake);
    const RasterFrame reference = renderRaster(*device, o, scene, VK_FORMAT_R32G32B32A32_SFLOAT, 1, *sky);
    for (const VkFormat format : {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT})
        for (const Tonemapper op : {Tonemapper::AcesNarkowicz, Tonemapper::AcesHill, Tonemapper::KhronosPbrNeutral,
                                    Tonemapper::Passthrough}) {
            scene.tonemapper = op;
            const RasterFrame f = renderRaster(*device, o, scene, format, 8, *sky);
            Point p{"raster hdr target + operator",
                    std::string(format == VK_FORMAT_R16G16B16A16_SFLOAT ? "fp16 " : "fp32 ") +
                        std::string(toString(op))};
            p.wallMs = f.wallMs;
            p.gpuMs = f.gpuMs;
            hdrError(f.hdr, reference.hdr, p);
            std::tie(p.deMean, p.deMax) = deltaE.compare(rgbOf(f.ldr), displayOf(reference.hdr, op, scene.exposureEv));
            points.push_back(p);
        }
    scene.tonemapper = Tonemapper::AcesNarkowicz;

    // The environment: cube face size, supersampling, IBL sample counts, cubemap against
    // direct equirect sampling. Reference: the richest bake (256 faces, 4x4 supersampling,
    // 4096 samples) of the same map; every point renders into fp32 so only its knob differs.
    if (o.environment) {
        const ImageData map = skyEquirect(1024, 512);
        double refBake = 0;
        const RasterFrame envReference = renderWithEnvironment(*device, o, scene, map, {256, 4, 4096, true}, refBake);
        struct EnvPoint {
            const char* knob;
            EnvironmentKnobs k;
        };
        const EnvPoint envPoints[] = {
            {"cube face size", {32, 2, 1024, true}},   {"cube face size", {64, 2, 1024, true}},
            {"cube face size", {128, 2, 1024, true}},  {"cube face size", {256, 2, 1024, true}},
            {"cube supersample", {128, 1, 1024, true}}, {"cube supersample", {128, 4, 1024, true}},
            {"IBL samples", {256, 2, 64, true}},       {"IBL samples", {256, 2, 256, true}},
            {"IBL samples", {256, 2, 4096, true}},     {"sky sampling", {256, 2, 1024, false}},
        };
        for (const EnvPoint& e : envPoints) {
            double bake = 0;
            const RasterFrame f = renderWithEnvironment(*device, o, scene, map, e.k, bake);
            Point p{e.knob, std::string(e.k.cubemap ? "cube " : "equirect sky + cube ") + std::to_string(e.k.faceSize) +
                                " ss" + std::to_string(e.k.supersample) + " n" + std::to_string(e.k.samples)};
            p.wallMs = f.wallMs;
            p.gpuMs = f.gpuMs;
            p.bakeMs = bake;
            hdrError(f.hdr, envReference.hdr, p);
            std::tie(p.deMean, p.deMax) =
                deltaE.compare(rgbOf(f.ldr), displayOf(envReference.hdr, scene.tonemapper, scene.exposureEv));
            points.push_back(p);
        }
        std::printf("environment reference bake: %.0f ms wall\n", refBake);
        // The rasterized IBL frame (the richest bake) against the path-traced truth of the same
        // scene and map: what the split sum, no shadows and no interreflection cost.
        double truthMs = 0;
        const ImageData truth = pathTracedTruth(*device, o, scene, map, o.ptReferenceSpp, truthMs);
        Point p{"raster IBL vs path-traced truth", "cube 256 ss4 n4096 vs " + std::to_string(o.ptReferenceSpp) + " spp"};
        p.wallMs = envReference.wallMs;
        p.gpuMs = envReference.gpuMs;
        p.bakeMs = refBake;
        hdrError(envReference.hdr, truth, p);
        std::tie(p.deMean, p.deMax) = deltaE.compare(rgbOf(envReference.ldr), displayOf(truth, scene.tonemapper, scene.exposureEv));
        points.push_back(p);
        std::printf("path-traced truth with the map: %u spp in %.0f ms wall\n", o.ptReferenceSpp, truthMs);

        // The same comparison on a real model: glTF BoxTextured, its texture sampled by both.
        Scene model = loadSceneFile(kSource / o.gltfScene);
        model.tonemapper = scene.tonemapper;
        double modelBake = 0, modelTruthMs = 0;
        const RasterFrame modelRaster = renderWithEnvironment(*device, o, model, map, {256, 4, 4096, true}, modelBake);
        const ImageData modelTruth = pathTracedTruth(*device, o, model, map, o.ptReferenceSpp, modelTruthMs);
        Point g{"glTF model: raster IBL vs path-traced truth",
                o.gltfScene.filename().string() + ": cube 256 ss4 n4096 vs " + std::to_string(o.ptReferenceSpp) + " spp"};
        g.wallMs = modelRaster.wallMs;
        g.gpuMs = modelRaster.gpuMs;
        g.bakeMs = modelBake;
        hdrError(modelRaster.hdr, modelTruth, g);
        std::tie(g.deMean, g.deMax) =
            deltaE.compare(rgbOf(modelRaster.ldr), displayOf(modelTruth, model.tonemapper, model.exposureEv));
        points.push_back(g);
        std::printf("path-traced truth of %s: %u spp in %.0f ms wall\n", o.gltfScene.string().c_str(),
                    o.ptReferenceSpp, modelTruthMs);
    }

    // Path-tracer samples per pixel against the same tracer at the reference count, named
    // apart: the pass name seeds the tracer, so the reference's samples are independent of the sweep's.
    const PathTraceRun ref = pathTrace(*device, o, scene, "pathtrace_reference", samplesPerFrameFor(o.ptReferenceSpp),
                                       {o.ptReferenceSpp});
    const ImageData& ptReference = ref.images.back().second;
    const auto refDisplay = displayOf(ptReference, Tonemapper::AcesNarkowicz, scene.exposureEv);
    const PathTraceRun sweep = pathTrace(*device, o, scene, "pathtrace_sweep", 1, {1, 4, 16, 64, 256});
    for (size_t i = 0; i < sweep.images.size(); ++i) {
        Point p{"path tracer spp", std::to_string(sweep.images[i].first)};
        p.wallMs = sweep.wallMs[i];
        p.gpuMs = sweep.gpuMs[i];
        hdrError(sweep.images[i].second, ptReference, p);
        std::tie(p.deMean, p.deMax) =
            deltaE.compare(displayOf(sweep.images[i].second, Tonemapper::AcesNarkowicz, scene.exposureEv), refDisplay);
        points.push_back(p);
    }

    std::ofstream csv(o.out);
    csv << "knob,setting,wall_ms,gpu_ms,bake_ms,rmse_hdr,max_hdr,de2000_mean,de2000_max\n";
    std::printf("%-30s %-28s %9s %9s %9s %10s %10s %8s %8s\n", "knob", "setting", "wall_ms", "gpu_ms", "bake_ms", "rmse_hdr",
                "max_hdr", "dE_mean", "dE_max");
    for (const Point& p : points) {
        csv << p.knob << ',' << p.setting << ',' << p.wallMs << ',' << p.gpuMs << ',' << p.bakeMs << ',' << p.rmseHdr << ',' << p.maxHdr
            << ',' << p.deMean << ',' << p.deMax << '\n';
        std::printf("%-30s %-28s %9.2f %9.2f %9.1f %10.3g %10.3g %8.3f %8.3f\n", p.knob.c_str(), p.setting.c_str(),
                    p.wallMs, p.gpuMs, p.bakeMs, p.rmseHdr, p.maxHdr, p.deMean, p.deMax);
    }
    if (!csv) throw std::runtime_error("cannot write " + o.out);
    std::printf("path-tracer reference: %u spp in %.0f ms wall\n", o.ptReferenceSpp, ref.wallMs.back());
    printCurveTable();
    aces::printFitTable(aces::Reference(), 32);
    if (o.validate && device->messageCount() > 0) {
        for (const auto& m : device->messages()) std::fprintf(stderr, "[%s] %s\n", m.idName.c_str(), m.message.c_str());
        throw std::runtime_error(std::to_string(device->messageCount()) + " validation messages");
    }
    std::printf("wrote %s (%zu points)\n", o.out.c_str(), points.size());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"study: the speed/accuracy sweep (docs/tradeoffs.md)"};
    Options o;
    std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
    app.add_option("--size", size, "Output WIDTHxHEIGHT")->capture_default_str();
    app.add_option("--out", o.out, "The CSV to write")->capture_default_str();
    app.add_option("--device", o.device, "Physical device: index or name substring")->capture_default_str();
    app.add_option("--pt-reference-spp", o.ptReferenceSpp, "Samples per pixel of the path tracer's reference")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    const auto onOff = [](bool& flag) {
        return [&flag](const std::string& v) { flag = v == "on"; };
    };
    app.add_option_function<std::string>("--environment", onOff(o.environment),
                                          "off: skip the environment bakes (smoke runs); default on")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option_function<std::string>("--validate", onOff(o.validate),
                                         "on: validation with synchronization validation, any message fails; default off")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--gltf-scene", o.gltfScene, "The glTF scene of the \"glTF model\" point, relative to the source tree")
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    if (std::sscanf(size.c_str(), "%ux%u", &o.width, &o.height) != 2 || o.width == 0 || o.height == 0) {
        std::fprintf(stderr, "study: --size '%s' is not a size like 128x96\n", size.c_str());
        return 2;
    }
    try {
        return run(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "study: %s\n", e.what());
        return 1;
    }
}
