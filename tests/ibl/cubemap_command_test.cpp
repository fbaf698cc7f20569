// `skygraph cubemap` end to end: an analytic environment as .exr in, KTX2 files out, read by
// ktx-parse under node (an independent reader, installed by tools/install-deps.sh) and
// checked against the double references; bad inputs fail cleanly and write nothing.
#include "analytic_environment.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/ktx2.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <sys/wait.h>
#include <unistd.h>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kCli = SKYGRAPH_CLI;
const fs::path kKtxParse = SKYGRAPH_KTX_PARSE_DIR;
const fs::path kReader = fs::path(SKYGRAPH_SOURCE_DIR) / "tests/ibl/read_ktx2.mjs";

struct CommandRun {
    int status = -1;
    std::string output;  // stdout and stderr
};

CommandRun run(const std::string& command) {
    const fs::path log = fs::temp_directory_path() / ("skygraph-ibl-" + std::to_string(::getpid()) + ".log");
    const int raw = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    fs::remove(log);
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, text.str()};
}

json readKtx2(const fs::path& file) {
    const CommandRun r = run("node '" + kReader.string() + "' '" + kKtxParse.string() + "' '" + file.string() + "'");
    if (r.status != 0) throw std::runtime_error("ktx-parse could not read " + file.string() + ":\n" + r.output);
    return json::parse(r.output);
}

class CubemapCommand : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(fs::exists(kKtxParse / "package.json"))
            << "ktx-parse is missing at " << kKtxParse << ": run tools/install-deps.sh";
        dir_ = fs::temp_directory_path() / ("skygraph-cubemap-test-" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        const ImageData image = equirectImage(polynomialSky, 256, 128);
        HdrImage hdr{image.width, image.height, image.rgba};
        saveExr(dir_ / "sky.exr", hdr);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(CubemapCommand, WritesKtx2CubesThatAnIndependentReaderDecodes) {
    const CommandRun r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" +
                      (dir_ / "sky.ktx2").string() + "' --size 32 --samples 256 --cross '" +
                      (dir_ / "cross.exr").string() + "' --validate");
    ASSERT_EQ(r.status, 0) << r.output;

    const json env = readKtx2(dir_ / "sky.ktx2");
    EXPECT_EQ(env["vkFormat"], 97);  // VK_FORMAT_R16G16B16A16_SFLOAT
    EXPECT_EQ(env["typeSize"], 2);
    EXPECT_EQ(env["pixelWidth"], 32);
    EXPECT_EQ(env["pixelHeight"], 32);
    EXPECT_EQ(env["pixelDepth"], 0);
    EXPECT_EQ(env["layerCount"], 0);
    EXPECT_EQ(env["faceCount"], 6);
    EXPECT_EQ(env["levelCount"], 6);  // 32 .. 1
    EXPECT_EQ(env["supercompressionScheme"], 0);
    EXPECT_EQ(env["dfd"]["colorModel"], 1);        // RGBSDA
    EXPECT_EQ(env["dfd"]["transferFunction"], 1);  // linear
    EXPECT_EQ(env["dfd"]["bytesPlane0"], 8);
    ASSERT_EQ(env["dfd"]["samples"].size(), 4u);
    const int channelIds[4] = {0, 1, 2, 15};
    for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(env["dfd"]["samples"][c]["bitOffset"], 16 * c);
        EXPECT_EQ(env["dfd"]["samples"][c]["bitLength"], 15);
        EXPECT_EQ(env["dfd"]["samples"][c]["channelType"], 0xC0 | channelIds[c]) << "float, signed";
    }
    EXPECT_EQ(env["orientation"], "rd");
    for (int m = 0; m < 6; ++m) {
        const int size = 32 >> m;
        EXPECT_EQ(env["levels"][m]["byteLength"], size * size * 8 * 6) << "level " << m;
        for (int face = 0; face < 6; ++face) {
            const Dir want = math::ibl::cubeTexelMean(polynomialSky, face, size / 2, size / 2, size, 8);
            for (int c = 0; c < 3; ++c) {
                const double got = env["levels"][m]["centres"][face][c];
                // Mips are box means: coarser levels drift from the centre texel's own mean.
                EXPECT_NEAR(got, want[c], m == 0 ? 3e-3 : 0.02 * (1 << m)) << "level " << m << " face " << face;
            }
        }
    }

    const json irradiance = readKtx2(dir_ / "sky.irradiance.ktx2");
    EXPECT_EQ(irradiance["faceCount"], 6);
    for (int face = 0; face < 6; ++face) {
        const int size = irradiance["pixelWidth"];
        const Dir want = polynomialSkyIrradiance(texelDirection(face, uint32_t(size / 2), uint32_t(size / 2), uint32_t(size)));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(double(irradiance["levels"][0]["centres"][face][c]), want[c], 0.02 * want[c]) << "face " << face;
    }

    const json prefiltered = readKtx2(dir_ / "sky.prefiltered.ktx2");
    EXPECT_EQ(prefiltered["pixelWidth"], 32);  // max(size / 2, 32)
    EXPECT_EQ(prefiltered["levelCount"], 6);  // one roughness per mip: 0, 0.2 .. 1
    const json brdf = readKtx2(dir_ / "sky.brdf.ktx2");
    EXPECT_EQ(brdf["vkFormat"], 83);  // VK_FORMAT_R16G16_SFLOAT
    EXPECT_EQ(brdf["faceCount"], 1);
    EXPECT_EQ(brdf["dfd"]["samples"].size(), 2u);

    const HdrImage cross = loadHdrImage(dir_ / "cross.exr");
    ASSERT_EQ(cross.width, 4u * 32);
    ASSERT_EQ(cross.height, 3u * 32);
    // +Z sits in the middle of the cross, +Y above it.
    EXPECT_NEAR(cross.pixel(48, 48)[0], double(env["levels"][0]["centres"][4][0]), 1e-3);
    EXPECT_NEAR(cross.pixel(48, 16)[1], double(env["levels"][0]["centres"][2][1]), 1e-3);
}

TEST_F(CubemapCommand, Float32OutputAndOnlyTheProductsAskedFor) {
    const CommandRun r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" +
                             (dir_ / "f.ktx2").string() + "' --size 32 --samples 16 --format rgba32f --products brdf --validate");
    ASSERT_EQ(r.status, 0) << r.output;
    const json env = readKtx2(dir_ / "f.ktx2");
    EXPECT_EQ(env["vkFormat"], 109);  // VK_FORMAT_R32G32B32A32_SFLOAT
    EXPECT_EQ(env["typeSize"], 4);
    const Dir want = math::ibl::cubeTexelMean(polynomialSky, 4, 16, 16, 32, 8);
    EXPECT_NEAR(double(env["levels"][0]["centres"][4][0]), want.x, 2e-3);
    const json brdf = readKtx2(dir_ / "f.brdf.ktx2");
    EXPECT_EQ(brdf["vkFormat"], 103);  // VK_FORMAT_R32G32_SFLOAT
    EXPECT_FALSE(fs::exists(dir_ / "f.irradiance.ktx2"));
    EXPECT_FALSE(fs::exists(dir_ / "f.prefiltered.ktx2"));
}

// A sky brighter than a half float holds is clamped to 65504 for rgba16f cubes, not written as
// infinity into every mip and filtered product; rgba32f cubes keep it.
TEST_F(CubemapCommand, ValuesPastTheLargestHalfAreClampedOnlyForHalfFloatCubes) {
    const HdrImage bright{64, 32, std::vector<float>(64 * 32 * 4, 1.0e30f)};
    saveHdrImage(dir_ / "bright.hdr", bright);
    const CommandRun half = run("'" + kCli.string() + "' cubemap '" + (dir_ / "bright.hdr").string() + "' -o '" +
                                (dir_ / "h.ktx2").string() + "' --size 32 --samples 16 --validate");
    ASSERT_EQ(half.status, 0) << half.output;
    EXPECT_NE(half.output.find("pixel values past +-65504"), std::string::npos) << half.output;
    for (const char* file : {"h.ktx2", "h.irradiance.ktx2", "h.prefiltered.ktx2"}) {
        const json cube = readKtx2(dir_ / file);
        for (const json& level : cube["levels"])
            for (const json& centre : level["centres"])
                for (int c = 0; c < 3; ++c) {
                    ASSERT_TRUE(centre[c].is_number()) << file << ": " << centre;  // infinity reads as null
                    EXPECT_NEAR(double(centre[c]), 65504.0, 65504.0 * 2e-3) << file;
                }
    }
    const CommandRun full = run("'" + kCli.string() + "' cubemap '" + (dir_ / "bright.hdr").string() + "' -o '" +
                                (dir_ / "f.ktx2").string() +
                                "' --size 32 --samples 16 --format rgba32f --products brdf --validate");
    ASSERT_EQ(full.status, 0) << full.output;
    EXPECT_EQ(full.output.find("clamped"), std::string::npos) << full.output;
    EXPECT_NEAR(double(readKtx2(dir_ / "f.ktx2")["levels"][0]["centres"][4][0]), 1.0e30, 1.0e30 * 1e-2);
}

TEST(Ktx2Writer, RefusesInconsistentLevelsAndLeavesNoFile) {
    const fs::path path = fs::temp_directory_path() / ("skygraph-ktx2-" + std::to_string(::getpid()) + ".ktx2");
    Ktx2Texture texture;
    texture.levels = {{HdrImage{4, 4, std::vector<float>(64)}}, {HdrImage{3, 2, std::vector<float>(24)}}};
    EXPECT_THROW(saveKtx2(path, texture), ImageError) << "level 1 of a 4x4 texture must be 2x2";
    texture.levels = {std::vector<HdrImage>(5, HdrImage{4, 4, std::vector<float>(64)})};
    EXPECT_THROW(saveKtx2(path, texture), ImageError) << "5 faces";
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
}

// A cube past what the device can hold is named by the option that sized it (the input file,
// for an equirect too large, is named the same way by the command; lavapipe's cap needs a
// 12000x6000 file to reach, too large for a test).
TEST_F(CubemapCommand, ACubeTheDeviceCannotHoldIsNamedByItsOption) {
    const fs::path out = dir_ / "out.ktx2";
    const CommandRun r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" +
                             out.string() + "' --size 4096 --format rgba32f --products none");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("error: --size 4096: resource 'environment' needs "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST_F(CubemapCommand, BadInputFailsWithTheFileNamedAndWritesNothing) {
    const fs::path out = dir_ / "out.ktx2";
    CommandRun r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "missing.exr").string() + "' -o '" + out.string() + "'");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("missing.exr"), std::string::npos) << r.output;

    {  // a truncated file: the first half of a valid one
        std::ifstream in(dir_ / "sky.exr", std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(dir_ / "truncated.exr", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
    }
    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "truncated.exr").string() + "' -o '" + out.string() + "'");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("truncated.exr"), std::string::npos) << r.output;

    std::ofstream(dir_ / "corrupt.hdr") << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\nnot pixels";
    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "corrupt.hdr").string() + "' -o '" + out.string() + "'");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("corrupt.hdr"), std::string::npos) << r.output;

    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" + (dir_ / "out.png").string() + "'");
    EXPECT_EQ(r.status, 1) << "a non-.ktx2 output is a problem with the input, as render's: " << r.output;
    EXPECT_NE(r.output.find("out.png': cannot write: its extension must be .ktx2"), std::string::npos) << r.output;
    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" + out.string() + "' --size 48");
    EXPECT_EQ(r.status, 2) << r.output;
    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" + out.string() +
            "' --products none,brdf");
    EXPECT_EQ(r.status, 2) << "'none' with a product is misuse: " << r.output;
    EXPECT_NE(r.output.find("'none' is the cube alone"), std::string::npos) << r.output;
    // --cross through a link to -o's file: the cross replaced the cube, and the command said
    // it had written both.
    fs::create_symlink("out.ktx2", dir_ / "cross.hdr");
    r = run("'" + kCli.string() + "' cubemap '" + (dir_ / "sky.exr").string() + "' -o '" + out.string() +
            "' --size 32 --cross '" + (dir_ / "cross.hdr").string() + "'");
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("cross.hdr': cannot write: it is the same file as '" + out.string() + "'"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out)) << "nothing written";
    fs::remove(dir_ / "cross.hdr");

    for (const auto& entry : fs::directory_iterator(dir_))
        EXPECT_NE(entry.path().extension(), ".ktx2") << "nothing written: " << entry.path();
}

}  // namespace
}  // namespace skygraph::test
