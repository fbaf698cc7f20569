// TonemappingComputePass against TonemappingPass on lavapipe under validation +
// synchronization validation (ExecutorTest fails on any message). Both run in one frame on
// the same fp32 HDR image; the fragment pass writes B8G8R8A8_SRGB (hardware sRGB encode), the
// compute pass R8G8B8A8_UNORM (shader encode), and the pictures must agree within one 8-bit
// code for every operator and exposure, hostile inputs included. Negative controls show the
// comparison notices a one-stop exposure error.
#include "pass_test_util.hpp"

#include <skygraph/pass.hpp>
#include <skygraph/scene.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

namespace skygraph::test {
namespace {

const std::filesystem::path kSource = SKYGRAPH_SOURCE_DIR;
constexpr uint32_t kWidth = 37, kHeight = 19;  // not multiples of 16: edge tiles are partial

/// Both passes on one input; `fragmentParams` / `computeParams` are the passes' params objects.
std::string bothPassesGraph(const std::string& fragmentParams, const std::string& computeParams) {
    const std::string extent = "[" + std::to_string(kWidth) + ", " + std::to_string(kHeight) + "]";
    return R"({
  "version": 1, "name": "tonemap_both",
  "resources": {
    "hdr":  {"type": "image2d", "format": "R32G32B32A32_SFLOAT", "extent": )" + extent + R"(,
             "external": true, "initial": "ShaderRead"},
    "fragment": {"type": "image2d", "format": "B8G8R8A8_SRGB", "extent": )" + extent + R"(,
                 "external": true, "final": "TransferSrc"},
    "compute":  {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": )" + extent + R"(,
                 "external": true, "final": "TransferSrc"}
  },
  "passes": [
    {"name": "tonemap", "type": "TonemappingPass", "params": )" + fragmentParams + R"(,
     "uses": {"hdr": "Read@Fragment", "fragment": "Write@ColorAttachment"}},
    {"name": "tonemap_compute", "type": "TonemappingComputePass", "params": )" + computeParams + R"(,
     "uses": {"hdr": "Read@Compute", "compute": "Write@Compute"}}
  ]
})";
}

/// Row 0: +-inf, NaN, huge, negative and tiny values beside ordinary ones; the other rows a
/// log ramp from 1e-4 to 1e3 with the channels apart, so every output code range is hit.
ImageData testInput() {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float hostile[] = {inf, nan, -1e4f, 65504.0f, 1e38f, -inf, 0.0f, 1e-30f, -0.0f, 3e-8f};
    ImageData img;
    img.width = kWidth;
    img.height = kHeight;
    img.format = VK_FORMAT_R32G32B32A32_SFLOAT;
    for (uint32_t y = 0; y < kHeight; ++y)
        for (uint32_t x = 0; x < kWidth; ++x) {
            const uint32_t i = y * kWidth + x;
            if (y == 0) {
                const float h = hostile[x % std::size(hostile)];
                img.rgba.insert(img.rgba.end(), {h, x % 3 ? 0.18f : h, x % 2 ? h : 2.0f, 1.0f});
                continue;
            }
            const float t = float(i) / float(kWidth * kHeight);
            const float v = std::pow(10.0f, -4.0f + 7.0f * t);
            img.rgba.insert(img.rgba.end(), {v, v * 0.5f, v * (1.0f + float(x % 5)), 1.0f});
        }
    return img;
}

struct Comparison {
    double worstCodes = 0;
    int pixelsOverOneCode = 0;
};

/// Largest difference in 8-bit codes over every pixel and colour channel (the read-back is
/// byte / 255 for both formats, in RGBA order).
Comparison compare(const ImageData& a, const ImageData& b) {
    Comparison c;
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    for (uint32_t y = 0; y < std::min(a.height, b.height); ++y)
        for (uint32_t x = 0; x < std::min(a.width, b.width); ++x) {
            double worst = 0;
            for (int ch = 0; ch < 3; ++ch) {
                const float va = a.pixel(x, y)[ch], vb = b.pixel(x, y)[ch];
                EXPECT_TRUE(std::isfinite(va) && std::isfinite(vb)) << "pixel " << x << "," << y;
                worst = std::max(worst, std::abs(double(va) - double(vb)) * 255.0);
            }
            c.worstCodes = std::max(c.worstCodes, worst);
            if (worst > 1.0 + 1e-3) ++c.pixelsOverOneCode;
        }
    return c;
}

class TonemapCompute : public ExecutorTest {
protected:
    void SetUp() override {
        ExecutorTest::SetUp();
        library_ = PassLibrary::withBuiltins();
    }

    std::unique_ptr<Renderer> makeRenderer(const std::string& fragmentParams, const std::string& computeParams) {
        const GraphDesc graph = parseGraph(bothPassesGraph(fragmentParams, computeParams), "tonemap_both.json",
                                           library_.registry());
        RendererOptions ro;
        ro.passes = &library_;
        ro.framesInFlight = 1;
        auto renderer = std::make_unique<Renderer>(sharedDevice(), CompiledGraph(graph, outputSize()), ro);
        renderer->setExternalImage("hdr", testInput());
        return renderer;
    }

    Comparison renderAndCompare(Renderer& renderer) {
        renderer.renderFrame();
        renderer.waitIdle();
        return compare(renderer.readImage("fragment").at(0), renderer.readImage("compute").at(0));
    }

    /// Both outputs are read with Renderer::readImage, so the plan copies nothing per frame.
    static CompileOptions outputSize() {
        CompileOptions co;
        co.outputWidth = kWidth;
        co.outputHeight = kHeight;
        return co;
    }

    PassLibrary library_;
};

// Operator and exposure from the scene, as in a rendered frame (a debug view forces
// passthrough through the same path).
TEST_F(TonemapCompute, MatchesTheFragmentPassForEveryOperatorAndExposure) {
    auto renderer = makeRenderer("{}", "{}");
    double worst = 0;
    for (const Tonemapper op : {Tonemapper::AcesNarkowicz, Tonemapper::AcesHill, Tonemapper::KhronosPbrNeutral,
                                Tonemapper::Passthrough})
        for (const double ev : {-20.0, -4.0, 0.0, 1.5, 6.0, 40.0}) {
            Scene s;
            s.tonemapper = op;
            s.exposureEv = ev;
            renderer->frameData().set(s);
            const Comparison c = renderAndCompare(*renderer);
            EXPECT_LE(c.worstCodes, 1.0 + 1e-3) << "operator " << toString(op) << ", EV " << ev;
            EXPECT_EQ(c.pixelsOverOneCode, 0) << "operator " << toString(op) << ", EV " << ev;
            worst = std::max(worst, c.worstCodes);
        }
    std::printf("compute vs fragment tonemapping: worst %.3f 8-bit codes\n", worst);
}

// Operator and exposure from the params (no scene): both passes read them the same way.
TEST_F(TonemapCompute, ParamsGiveTheSamePictureAsTheFragmentPass) {
    for (const char* op : {"aces_narkowicz", "aces_hill", "khronos_pbr_neutral", "passthrough"}) {
        const std::string params = std::string(R"({"operator": ")") + op + R"(", "exposure_ev": 2.5})";
        auto renderer = makeRenderer(params, params);
        const Comparison c = renderAndCompare(*renderer);
        EXPECT_LE(c.worstCodes, 1.0 + 1e-3) << op;
        EXPECT_EQ(c.pixelsOverOneCode, 0) << op;
    }
}

// Negative controls: the same comparison must fail for a compute pass one stop off, and for
// a different tone curve.
TEST_F(TonemapCompute, ComparisonCatchesAWrongExposureOrOperator) {
    {
        auto renderer = makeRenderer(R"({"exposure_ev": 0.0})", R"({"exposure_ev": 1.0})");
        const Comparison c = renderAndCompare(*renderer);
        std::printf("one stop apart: worst %.1f codes, %d pixels over one code\n", c.worstCodes, c.pixelsOverOneCode);
        EXPECT_GT(c.worstCodes, 10.0);
        EXPECT_GT(c.pixelsOverOneCode, int(kWidth * kHeight) / 4);
    }
    {
        auto renderer = makeRenderer(R"({"operator": "aces_narkowicz"})", R"({"operator": "aces_hill"})");
        EXPECT_GT(renderAndCompare(*renderer).pixelsOverOneCode, 0);
    }
}

// Outputs the compute pass cannot write: the loader refuses formats that cannot be storage
// images at all (sRGB); the pass refuses storage formats its shader does not write. BGRA,
// which has no GLSL format qualifier, is written through the view's format.
TEST_F(TonemapCompute, RefusesAnOutputItCannotStore) {
    const auto withOutputFormat = [](const std::string& format) {
        std::string text = bothPassesGraph("{}", "{}");
        const std::string from = R"("format": "R8G8B8A8_UNORM")";
        return text.replace(text.find(from), from.size(), R"("format": ")" + format + R"(")");
    };
    EXPECT_THROW((void)parseGraph(withOutputFormat("R8G8B8A8_SRGB"), "srgb.json", library_.registry()), GraphError);
    {
        const GraphDesc bgra = parseGraph(withOutputFormat("B8G8R8A8_UNORM"), "bgra.json", library_.registry());
        RendererOptions ro;
        ro.passes = &library_;
        Renderer renderer(sharedDevice(), CompiledGraph(bgra, outputSize()), ro);  // lavapipe writes it
        renderer.renderFrame();
        renderer.waitIdle();
    }

    // The loader refuses it in a file; a graph built in code reaches the pass as it is.
    try {
        (void)parseGraph(withOutputFormat("R16G16_SFLOAT"), "rg16f.json", library_.registry());
        FAIL() << "the loader accepted an R16G16_SFLOAT output";
    } catch (const GraphError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("rg16f.json: passes["), std::string::npos) << what;
        EXPECT_NE(what.find("pass 'tonemap_compute', resource 'compute'"), std::string::npos) << what;
        EXPECT_NE(what.find("not R16G16_SFLOAT"), std::string::npos) << what;
    }
    GraphDesc graph = parseGraph(withOutputFormat("R16G16B16A16_SFLOAT"), "rg16f.json", library_.registry());
    for (ResourceDesc& r : graph.resources)
        if (r.name == "compute") r.format = *findFormat("R16G16_SFLOAT");
    RendererOptions ro;
    ro.passes = &library_;
    try {
        Renderer renderer(sharedDevice(), CompiledGraph(graph, outputSize()), ro);
        FAIL() << "an R16G16_SFLOAT output was accepted";
    } catch (const ExecutorError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("pass 'tonemap_compute'"), std::string::npos) << what;
        EXPECT_NE(what.find("resource 'compute'"), std::string::npos) << what;
        EXPECT_NE(what.find("R16G16_SFLOAT"), std::string::npos) << what;
    }
}

/// graphs/raster.json for `scene` with compute_tonemap set; the Present target read back.
ImageData renderRaster(const Scene& scene, bool computeTonemap, uint32_t w, uint32_t h) {
    return renderRasterFrame(scene, w, h, 1, {{"compute_tonemap", computeTonemap}});
}

// The shipped frame: feature compute_tonemap on (swapchain_storage, R8G8B8A8_UNORM) gives the
// picture of the default render-pass path (swapchain, B8G8R8A8_SRGB) within one code.
TEST_F(TonemapCompute, RasterJsonWithComputeTonemapMatchesTheDefaultFrame) {
    const Scene scene = loadSceneFile(kSource / "scenes/default.json");
    const ImageData fragment = renderRaster(scene, false, 64, 40);
    const ImageData compute = renderRaster(scene, true, 64, 40);
    const Comparison c = compare(fragment, compute);
    std::printf("raster.json compute_tonemap on vs off: worst %.3f codes\n", c.worstCodes);
    EXPECT_LE(c.worstCodes, 1.0 + 1e-3);
    EXPECT_EQ(c.pixelsOverOneCode, 0);
}

}  // namespace
}  // namespace skygraph::test
