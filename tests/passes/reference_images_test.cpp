// Whole frames of the shipped scenes through `skygraph render`'s code path (renderCommand, with
// validation and synchronization validation on), against reviewed reference PNGs in
// tests/passes/reference/. Tolerance: no channel more than 4 codes off, and at most 0.5% of the
// channel values more than 1 code off (lavapipe's LLVM may round transcendental functions
// differently across versions). On failure the test writes the frame and a diff image (|a - b|
// x 16) next to the build's test binaries and names them. SKYGRAPH_UPDATE_REFERENCE=1 rewrites
// the references: look at every image before committing it.
#include "app/render.hpp"

#include <skygraph/image_data.hpp>
#include <skygraph/pass.hpp>

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = SKYGRAPH_SOURCE_DIR;

struct RgbaImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

RgbaImage readPng(const fs::path& path) {
    int w = 0, h = 0, comp = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.string().c_str(), &w, &h, &comp, 4), stbi_image_free);
    if (!data) return {};
    return {w, h, std::vector<uint8_t>(data.get(), data.get() + size_t(w) * h * 4)};
}

struct Case {
    std::string name;       ///< the output's name
    std::string scene;      ///< <scene>.json, relative to the source tree
    std::string sampling;   ///< "": as in the file; else the environment's sampling is replaced
    std::string reference;  ///< reference/<reference>.png; empty: <name>
};

// Names the case in test listings (gtest would print the struct's bytes, padding included).
void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class ReferenceImages : public ::testing::TestWithParam<Case> {};

TEST_P(ReferenceImages, MatchTheReviewedFrame) {
    const Case& c = GetParam();
    const fs::path out = fs::path(SKYGRAPH_BINARY_DIR) / "reference-out";
    fs::create_directories(out);
    fs::path scene = kSource / (c.scene + ".json");
    if (!c.sampling.empty()) {  // the same scene, sampled the other way
        std::ifstream in(scene);
        std::string text((std::istreambuf_iterator<char>(in)), {});
        const std::string from = "\"sampling\": \"equirect\"";
        ASSERT_NE(text.find(from), std::string::npos) << scene;
        text.replace(text.find(from), from.size(), "\"sampling\": \"" + c.sampling + "\"");
        scene = out / (c.name + ".scene.json");
        std::ofstream(scene) << text;
    }
    static const PassLibrary library = PassLibrary::withBuiltins();
    app::RenderOptions o;
    o.graph = kSource / "graphs/raster.json";
    o.scene = scene;
    o.width = 96;
    o.height = 64;
    o.frames = 2;
    o.output = out / (c.name + ".png");
    o.validate = true;
    o.passes = &library;
    ASSERT_EQ(app::renderCommand(o), 0) << "render failed or validation reported messages";

    const fs::path reference = kSource / "tests/passes/reference" / ((c.reference.empty() ? c.name : c.reference) + ".png");
    if (const char* update = std::getenv("SKYGRAPH_UPDATE_REFERENCE"); update && std::string_view(update) == "1")
        fs::copy_file(o.output, reference, fs::copy_options::overwrite_existing);
    const RgbaImage want = readPng(reference), got = readPng(o.output);
    ASSERT_GT(want.width, 0) << "no reference image " << reference;
    ASSERT_EQ(got.width, want.width);
    ASSERT_EQ(got.height, want.height);
    int worst = 0;
    size_t beyondOne = 0, values = 0;
    RgbaImage diff{got.width, got.height, std::vector<uint8_t>(got.rgba.size(), 255)};
    for (size_t i = 0; i < got.rgba.size(); ++i) {
        if (i % 4 == 3) continue;
        const int d = std::abs(int(got.rgba[i]) - int(want.rgba[i]));
        worst = std::max(worst, d);
        beyondOne += d > 1;
        ++values;
        diff.rgba[i] = uint8_t(std::min(255, d * 16));
    }
    const bool ok = worst <= 4 && beyondOne * 200 <= values;
    if (!ok) {
        ImageData d;
        d.width = uint32_t(diff.width);
        d.height = uint32_t(diff.height);
        d.rgba.resize(diff.rgba.size());
        for (size_t i = 0; i < diff.rgba.size(); ++i) d.rgba[i] = diff.rgba[i] / 255.0f;
        writePng(out / (c.name + ".diff.png"), d);
    }
    EXPECT_TRUE(ok) << c.name << ": worst " << worst << " codes, " << beyondOne << " of " << values
                    << " values more than 1 code off; frame " << o.output << ", diff "
                    << (out / (c.name + ".diff.png")) << ", reference " << reference;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ReferenceImages,
                         ::testing::Values(Case{"default", "scenes/default", "", ""},
                                           Case{"sky_only", "scenes/sky_only", "", ""},
                                           Case{"studio_equirect", "scenes/studio", "", ""},
                                           Case{"studio_cubemap", "scenes/studio", "cubemap", ""},
                                           // glTF from Debian's assimp-testmodels: one box, three containers
                                           Case{"box_textured_gltf", "tests/passes/scenes/box_textured_gltf", "", ""},
                                           Case{"box_textured_glb", "tests/passes/scenes/box_textured_glb", "", "box_textured"},
                                           Case{"box_textured_embedded", "tests/passes/scenes/box_textured_embedded", "", "box_textured"},
                                           Case{"clearcoat", "tests/passes/scenes/clearcoat", "", ""},
                                           Case{"engine", "scenes/engine", "", ""}),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

}  // namespace
}  // namespace skygraph::test
