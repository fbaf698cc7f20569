// An engine embedding skygraph: it registers its own pass type (VignettePass) beside the
// built-in ones, loads its own graph with it, renders headless under the Khronos validation
// layer with synchronization validation, and checks the result against the same math on the
// CPU. Exit status 0 when every pixel matches and the layer said nothing.
#include "vignette_pass.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/executor.hpp>
#include <skygraph/pass.hpp>

#include <cmath>
#include <cstdio>
#include <exception>

namespace {

using namespace skygraph;

constexpr uint32_t kSize = 64;
constexpr double kClearValue = 0.5;  // vignette.json clears hdr_color to this grey
constexpr double kStrength = 0.8;    // vignette.json's params.strength

double srgbEncode(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

/// Pixels that differ from the CPU reference by more than two 8-bit codes.
int countMismatches(const ImageData& image) {
    int bad = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            const double expected = srgbEncode(kClearValue * embed::vignetteFactor(kStrength, x, y, kSize, kSize));
            const auto px = image.pixel(x, y);
            for (int c = 0; c < 3; ++c)
                if (std::abs(px[c] - expected) > 2.0 / 255.0 && bad++ < 5)
                    std::fprintf(stderr, "pixel (%u, %u) channel %d: %.4f, expected %.4f\n", x, y, c, px[c], expected);
        }
    return bad;
}

int run(const char* outputPng) {
    PassLibrary library = PassLibrary::withBuiltins();
    library.add(embed::vignettePassType(), embed::makeVignettePass);
    GraphDesc graph = loadGraphFile(EMBED_DATA_DIR "/vignette.json", library.registry());

    CompileOptions compileOptions;
    compileOptions.outputWidth = compileOptions.outputHeight = kSize;
    compileOptions.presentReplacement = ExternalState::TransferSrc;  // headless: read back, not presented
    compileOptions.readbacks = {"swapchain"};
    CompiledGraph compiled(std::move(graph), compileOptions);

    DeviceOptions deviceOptions;
    deviceOptions.validation = true;
    const auto device = Device::create(deviceOptions);
    RendererOptions rendererOptions;
    rendererOptions.passes = &library;
    rendererOptions.shaderDir = SKYGRAPH_PACKAGE_SHADER_DIR;  // the installed package's shaders
    Renderer renderer(*device, std::move(compiled), rendererOptions);
    for (int frame = 0; frame < 3; ++frame) renderer.renderFrame();
    const ImageData image = renderer.readback();
    renderer.waitIdle();
    if (outputPng) writePng(outputPng, image);

    const int mismatches = countMismatches(image);
    const uint32_t messages = device->messageCount();
    const size_t steps = renderer.plan().passes().size();  // the plan is read through const accessors
    std::printf("embed_vignette: %ux%u on %s, shaders from %s, %zu plan steps: %d mismatching pixels, "
                "%u validation messages\n",
                image.width, image.height, device->name().c_str(), SKYGRAPH_PACKAGE_SHADER_DIR, steps, mismatches,
                messages);
    for (const auto& m : device->messages()) std::fprintf(stderr, "%s: %s\n", m.idName.c_str(), m.message.c_str());
    return mismatches == 0 && messages == 0 && image.width == kSize ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc > 1 ? argv[1] : nullptr);
    } catch (const GraphError& e) {
        std::fprintf(stderr, "%s\n", e.diagnostics().format().c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "embed_vignette: %s\n", e.what());
    }
    return 1;
}
