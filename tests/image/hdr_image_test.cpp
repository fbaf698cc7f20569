// skygraph_image: the blender-data studio lights, round trips, and every way a file can be bad.
#include <skygraph/hdr_image.hpp>
#include <skygraph/ktx2.hpp>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineOutputFile.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <stb/stb_image_write.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <fstream>
#include <functional>
#include <utility>
#include <iterator>
#include <limits>
#include <random>
#include <sys/resource.h>
#include <unistd.h>

namespace fs = std::filesystem;
using skygraph::HdrImage;
using skygraph::ImageError;

namespace {

const fs::path kStudioLights = "/usr/share/blender/datafiles/studiolights/world";

class HdrImageTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = fs::temp_directory_path() / ("skygraph_image_test_" + test);
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path dir_;
};

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

/// A smooth HDR test pattern over several orders of magnitude.
HdrImage pattern(uint32_t w, uint32_t h) {
    HdrImage img{w, h, std::vector<float>(size_t(w) * h * 4)};
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            float* p = img.rgba.data() + (size_t(y) * w + x) * 4;
            p[0] = std::pow(10.0f, -2.0f + 5.0f * float(x) / float(w));
            p[1] = 0.5f + float(y) / float(h);
            p[2] = float((x * 7 + y * 13) % 17) * 0.25f;
            p[3] = float(x % 4) / 3.0f;
        }
    return img;
}

/// Loading `path` throws ImageError whose message names the file and contains `what`.
void expectLoadError(const fs::path& path, const std::string& what) {
    try {
        (void)skygraph::loadHdrImage(path);
        ADD_FAILURE() << "loading " << path << " did not throw";
    } catch (const ImageError& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        EXPECT_EQ(e.file(), path);
    }
}

double meanLuminance(const HdrImage& img) {
    double sum = 0;
    for (size_t i = 0; i < img.rgba.size(); i += 4)
        sum += 0.2126 * img.rgba[i] + 0.7152 * img.rgba[i + 1] + 0.0722 * img.rgba[i + 2];
    return sum / double(size_t(img.width) * img.height);
}

// The CC0 studio lights of Debian's blender-data (tools/install-deps.sh installs it). Checked
// with `exrheader` (Debian package openexr): all eight are 1024x512, 32-bit float R, G, B, with
// "compression: dwa, medium scanline blocks", i.e. DWAB (written by oiiotool --compression
// dwab:300). The test asserts that premise too, so it really exercises the DWA decoder.
TEST_F(HdrImageTest, LoadsEveryBlenderStudioLightExr) {
    ASSERT_TRUE(fs::is_directory(kStudioLights)) << kStudioLights << " missing; run tools/install-deps.sh";
    int count = 0;
    for (const auto& entry : fs::directory_iterator(kStudioLights)) {
        if (entry.path().extension() != ".exr") continue;
        SCOPED_TRACE(entry.path().string());
        ++count;
        const Imf::Compression compression = Imf::InputFile(entry.path().c_str()).header().compression();
        EXPECT_TRUE(compression == Imf::DWAA_COMPRESSION || compression == Imf::DWAB_COMPRESSION);
        const HdrImage img = skygraph::loadHdrImage(entry.path());
        EXPECT_EQ(img.width, 1024u);
        EXPECT_EQ(img.height, 512u);
        ASSERT_EQ(img.rgba.size(), size_t(1024) * 512 * 4);
        EXPECT_EQ(skygraph::countNonFinite(img), 0u);
        float lo = 0, hi = 0;
        for (size_t i = 0; i < img.rgba.size(); ++i) {
            if (i % 4 == 3) {
                ASSERT_EQ(img.rgba[i], 1.0f) << "alpha at float " << i;
                continue;
            }
            lo = std::min(lo, img.rgba[i]);
            hi = std::max(hi, img.rgba[i]);
        }
        // The sources were clamped to [0, 32000] before DWA, which is lossy: measured minima are
        // about -0.004 and maxima up to 33952 (city.exr), so allow a little ringing both ways.
        EXPECT_GT(lo, -0.01f);
        EXPECT_LT(hi, 36000.0f);
        const double mean = meanLuminance(img);  // measured 0.13 (night) to 1.05 (city)
        EXPECT_GT(mean, 0.05);
        EXPECT_LT(mean, 10.0);
    }
    EXPECT_GE(count, 1) << "no .exr in " << kStudioLights;
}

TEST_F(HdrImageTest, RadianceRoundTripKeepsValuesWithinRgbePrecision) {
    const HdrImage src = pattern(67, 19);  // width >= 8: run-length encoded scanlines
    const fs::path path = dir_ / "a.hdr";
    skygraph::saveHdrImage(path, src);
    const HdrImage back = skygraph::loadHdrImage(path);
    ASSERT_EQ(back.width, src.width);
    ASSERT_EQ(back.height, src.height);
    for (size_t i = 0; i < src.rgba.size(); i += 4) {
        const float scale = std::max({src.rgba[i], src.rgba[i + 1], src.rgba[i + 2]});
        for (size_t c = 0; c < 3; ++c)  // RGBE: 8-bit mantissas sharing the largest exponent
            ASSERT_NEAR(back.rgba[i + c], src.rgba[i + c], scale / 64.0f) << "float " << i + c;
        ASSERT_EQ(back.rgba[i + 3], 1.0f);
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1) << "temp file left";
}

TEST_F(HdrImageTest, ExrRoundTripKeepsHalfPrecisionAlphaAndNonFiniteValues) {
    HdrImage src = pattern(33, 21);
    src.rgba[0] = std::numeric_limits<float>::infinity();
    src.rgba[5] = std::numeric_limits<float>::quiet_NaN();
    src.rgba[10] = -std::numeric_limits<float>::infinity();
    const fs::path path = dir_ / "a.EXR";  // extensions are matched in any case
    skygraph::saveHdrImage(path, src);
    EXPECT_EQ(Imf::InputFile(path.c_str()).header().compression(), Imf::ZIP_COMPRESSION);
    const HdrImage back = skygraph::loadHdrImage(path);
    ASSERT_EQ(back.width, src.width);
    ASSERT_EQ(back.height, src.height);
    EXPECT_EQ(skygraph::countNonFinite(back), 3u);
    EXPECT_TRUE(std::isinf(back.rgba[0]) && back.rgba[0] > 0);
    EXPECT_TRUE(std::isnan(back.rgba[5]));
    EXPECT_TRUE(std::isinf(back.rgba[10]) && back.rgba[10] < 0);
    for (size_t i = 11; i < src.rgba.size(); ++i)
        ASSERT_NEAR(back.rgba[i], src.rgba[i], std::abs(src.rgba[i]) / 1024.0f + 1e-7f) << "float " << i;
}

// A half float holds at most 65504 and rounds anything finite past it to infinity: a bright
// texel of a float image (an rgba32f bake's --cross) came back as +Inf.
TEST_F(HdrImageTest, ExrClampsFiniteValuesPastTheLargestHalf) {
    HdrImage src = pattern(4, 4);
    src.rgba[0] = 1e6f;
    src.rgba[1] = -1e6f;
    src.rgba[2] = std::numeric_limits<float>::max();
    const fs::path path = dir_ / "bright.exr";
    skygraph::saveHdrImage(path, src);
    const HdrImage back = skygraph::loadHdrImage(path);
    EXPECT_EQ(skygraph::countNonFinite(back), 0u);
    EXPECT_EQ(back.rgba[0], 65504.0f);
    EXPECT_EQ(back.rgba[1], -65504.0f);
    EXPECT_EQ(back.rgba[2], 65504.0f);
}

// Float channels are read at float precision (no trip through half), from a data window that
// does not start at (0, 0).
TEST_F(HdrImageTest, ExrFloatChannelsKeepFullPrecisionAndAnyDataWindow) {
    const fs::path path = dir_ / "float.exr";
    const Imath::Box2i window({10, 20}, {13, 22});  // 4 x 3
    std::vector<float> rgb(4 * 3 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = 1e6f + float(i) * 0.0625f;  // beyond half range
    {
        Imf::Header header(window, window);
        for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c)
            frame.insert(std::string(1, "RGB"[c]),
                         Imf::Slice::Make(Imf::FLOAT, rgb.data() + c, window, 12, 48));
        Imf::OutputFile out(path.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(3);
    }
    const HdrImage img = skygraph::loadHdrImage(path);
    ASSERT_EQ(img.width, 4u);
    ASSERT_EQ(img.height, 3u);
    for (size_t i = 0; i < 12; ++i) {
        for (size_t c = 0; c < 3; ++c) ASSERT_EQ(img.rgba[i * 4 + c], rgb[i * 3 + c]) << i;
        ASSERT_EQ(img.rgba[i * 4 + 3], 1.0f);  // no A channel: opaque
    }
}

// OpenEXR's image is its display window; the data window may cover part of it (the rest is
// transparent black) or more (overscan, not part of the image). An equirect cropped to its
// data window was stretched over the sphere, and overscan was baked into the sky.
TEST_F(HdrImageTest, ExrIsReadAsItsDisplayWindow) {
    const auto write = [&](const fs::path& path, const Imath::Box2i& display, const Imath::Box2i& data, float base) {
        const int w = data.max.x - data.min.x + 1, h = data.max.y - data.min.y + 1;
        std::vector<float> r(size_t(w) * size_t(h));
        for (size_t i = 0; i < r.size(); ++i) r[i] = base + float(i);
        Imf::Header header(display, data);
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer frame;
        frame.insert("R", Imf::Slice::Make(Imf::FLOAT, r.data(), data, sizeof(float), sizeof(float) * size_t(w)));
        Imf::OutputFile out(path.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(h);
    };
    // Data at (1, 1) to (2, 1) of a 4 x 2 display window.
    write(dir_ / "inside.exr", Imath::Box2i({0, 0}, {3, 1}), Imath::Box2i({1, 1}, {2, 1}), 10.0f);
    const HdrImage inside = skygraph::loadHdrImage(dir_ / "inside.exr");
    ASSERT_EQ(inside.width, 4u);
    ASSERT_EQ(inside.height, 2u);
    for (uint32_t y = 0; y < 2; ++y)
        for (uint32_t x = 0; x < 4; ++x) {
            const bool data = y == 1 && (x == 1 || x == 2);
            EXPECT_EQ(inside.rgba[(y * 4 + x) * 4], data ? 10.0f + float(x - 1) : 0.0f) << x << "," << y;
            EXPECT_EQ(inside.rgba[(y * 4 + x) * 4 + 3], data ? 1.0f : 0.0f) << x << "," << y;
        }
    // Data from (-1, -1) to (2, 1) over a 2 x 1 display window at (0, 0): the overscan goes.
    write(dir_ / "overscan.exr", Imath::Box2i({0, 0}, {1, 0}), Imath::Box2i({-1, -1}, {2, 1}), 100.0f);
    const HdrImage overscan = skygraph::loadHdrImage(dir_ / "overscan.exr");
    ASSERT_EQ(overscan.width, 2u);
    ASSERT_EQ(overscan.height, 1u);
    EXPECT_EQ(overscan.rgba[0], 100.0f + 5.0f);  // data row 1 (y = 0), column 1 (x = 0) of 4
    EXPECT_EQ(overscan.rgba[4], 100.0f + 6.0f);
}

// The display window's size is checked from the header, like the data window's: a file of
// a few bytes of pixels that claims a display window past the limit is refused before any
// pixel is read. Its last pixel block is cut off, which the size check must come before.
TEST_F(HdrImageTest, ExrDisplayWindowPastTheLimitIsRefusedFromTheHeader) {
    const fs::path path = dir_ / "wide_display.exr";
    const int wide = int(skygraph::kMaxHdrImageWidth) + 1;
    {
        const Imath::Box2i data({0, 0}, {1, 0});
        Imf::Header header(Imath::Box2i({0, 0}, {wide - 1, 0}), data);
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        std::vector<float> r = {1.0f, 2.0f};
        Imf::FrameBuffer frame;
        frame.insert("R", Imf::Slice::Make(Imf::FLOAT, r.data(), data, sizeof(float), 2 * sizeof(float)));
        Imf::OutputFile out(path.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(1);
    }
    fs::resize_file(path, fs::file_size(path) - 4);
    try {
        (void)skygraph::loadHdrImage(path);
        FAIL() << "a display window of " << wide << " columns was read";
    } catch (const skygraph::ImageError& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(wide) + "x1 exceeds the limit"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
}

TEST_F(HdrImageTest, ExrLuminanceOnlyAndLuminanceChromaFilesBecomeRgb) {
    const fs::path grey = dir_ / "y.exr";
    std::vector<float> y = {0.25f, 2.0f, 8.0f, 0.0f};
    {
        Imf::Header header(2, 2);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer frame;
        frame.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(y.data()), 4, 8));
        Imf::OutputFile out(grey.c_str(), header);
        out.setFrameBuffer(frame);
        out.writePixels(2);
    }
    const HdrImage g = skygraph::loadHdrImage(grey);
    for (size_t i = 0; i < 4; ++i)
        for (size_t c = 0; c < 3; ++c) EXPECT_EQ(g.rgba[i * 4 + c], y[i]);

    const fs::path yca = dir_ / "yca.exr";  // luminance + subsampled chroma (RY, BY)
    std::vector<Imf::Rgba> px(16 * 16, Imf::Rgba(0.8f, 0.4f, 0.2f, 1.0f));
    {
        Imf::RgbaOutputFile out(yca.c_str(), 16, 16, Imf::WRITE_YCA);
        out.setFrameBuffer(px.data(), 1, 16);
        out.writePixels(16);
    }
    EXPECT_NE(Imf::InputFile(yca.c_str()).header().channels().findChannel("RY"), nullptr);
    const HdrImage c = skygraph::loadHdrImage(yca);
    EXPECT_NEAR(c.rgba[0], 0.8f, 0.02f);
    EXPECT_NEAR(c.rgba[1], 0.4f, 0.02f);
    EXPECT_NEAR(c.rgba[2], 0.2f, 0.02f);
}

TEST_F(HdrImageTest, CountNonFiniteCountsNanAndBothInfinities) {
    HdrImage img{1, 2, {0, 1, NAN, INFINITY, -INFINITY, 1e38f, -0.0f, 3}};
    EXPECT_EQ(skygraph::countNonFinite(img), 3u);
    EXPECT_EQ(skygraph::countNonFinite(HdrImage{}), 0u);
}

TEST_F(HdrImageTest, SavingBadImagesOrToBadPlacesThrowsAndLeavesNothing) {
    const fs::path nowhere = dir_ / "no_such_dir" / "x.exr";
    EXPECT_THROW(skygraph::saveHdrImage(nowhere, pattern(4, 4)), ImageError);
    EXPECT_THROW(skygraph::saveHdrImage(dir_ / "no_such_dir" / "x.hdr", pattern(4, 4)), ImageError);
    EXPECT_THROW(skygraph::saveHdrImage(dir_ / "zero.exr", HdrImage{}), ImageError);
    EXPECT_THROW(skygraph::saveHdrImage(dir_ / "short.hdr", HdrImage{2, 2, {1, 2, 3}}), ImageError);
    EXPECT_THROW(skygraph::saveHdrImage(dir_ / "x.png", pattern(4, 4)), ImageError);
    EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(HdrImageTest, FailedSaveKeepsThePreviousFile) {
    const fs::path path = dir_ / "keep.exr";
    skygraph::saveHdrImage(path, pattern(8, 8));
    const std::string before = readBytes(path);
    EXPECT_THROW(skygraph::saveHdrImage(path, HdrImage{8, 8, {}}), ImageError);
    EXPECT_EQ(readBytes(path), before);
}

// A write cut short (a full disk; here a file size limit, with SIGXFSZ ignored so that the
// write fails with EFBIG instead of ending the process) is an error naming the output, never a
// half file under its name, and the previous file stays. stb's writers report no such failure
// on their own.
TEST_F(HdrImageTest, AWriteCutShortLeavesThePreviousFileAndNamesTheOutput) {
    HdrImage big = pattern(64, 64);  // noise: over 4 KiB in every format, compressed or not
    std::mt19937 random(7);
    for (float& v : big.rgba) v = std::uniform_real_distribution<float>(0.0f, 100.0f)(random);
    const HdrImage small = pattern(2, 2);
    skygraph::Ktx2Texture bigTexture{skygraph::Ktx2Format::Rgba32Float, {{big}}};
    skygraph::Ktx2Texture smallTexture{skygraph::Ktx2Format::Rgba32Float, {{small}}};
    const std::vector<std::pair<fs::path, std::function<void(const fs::path&, bool)>>> writers{
        {dir_ / "x.hdr", [&](const fs::path& p, bool large) { skygraph::saveHdrImage(p, large ? big : small); }},
        {dir_ / "x.exr", [&](const fs::path& p, bool large) { skygraph::saveHdrImage(p, large ? big : small); }},
        {dir_ / "x.ktx2", [&](const fs::path& p, bool large) { skygraph::saveKtx2(p, large ? bigTexture : smallTexture); }},
    };
    for (const auto& [path, write] : writers) {
        SCOPED_TRACE(path.string());
        write(path, false);
        const std::string before = readBytes(path);
        ASSERT_LT(before.size(), 4096u);
        const auto previousSignal = std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit{}, cut{};
        ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &limit), 0);
        cut = {4096, limit.rlim_max};
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &cut), 0);
        std::string message;
        try {
            write(path, true);
        } catch (const ImageError& e) {
            message = e.what();
        }
        ::setrlimit(RLIMIT_FSIZE, &limit);
        std::signal(SIGXFSZ, previousSignal);
        EXPECT_NE(message.find("'" + path.string() + "': cannot write: "), std::string::npos) << message;
        EXPECT_NE(message.find("File too large"), std::string::npos) << message;
        EXPECT_EQ(message.find("partial"), std::string::npos) << message;  // the temporary is not the user's
        EXPECT_EQ(readBytes(path), before);
    }
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"x.exr", "x.hdr", "x.ktx2"}));
}

// The encoders give the bytes the savers write, for a caller that writes several files
// together; they write nothing themselves.
TEST_F(HdrImageTest, EncodedBytesAreWhatASaveWrites) {
    const HdrImage image = pattern(8, 4);
    const skygraph::Ktx2Texture texture{skygraph::Ktx2Format::Rgba16Float, {{image}}};
    for (const char* name : {"x.hdr", "x.exr"}) {
        SCOPED_TRACE(name);
        const std::string bytes = skygraph::encodeHdrImage(dir_ / name, image);
        EXPECT_FALSE(fs::exists(dir_ / name));
        skygraph::saveHdrImage(dir_ / name, image);
        EXPECT_EQ(readBytes(dir_ / name), bytes);
    }
    const std::string ktx2 = skygraph::encodeKtx2(dir_ / "x.ktx2", texture);
    skygraph::saveKtx2(dir_ / "x.ktx2", texture);
    EXPECT_EQ(readBytes(dir_ / "x.ktx2"), ktx2);
    try {
        (void)skygraph::encodeHdrImage(dir_ / "x.png", image);
        ADD_FAILURE() << "encoded a PNG";
    } catch (const ImageError& e) {
        EXPECT_EQ(e.file(), dir_ / "x.png");
    }
    EXPECT_EQ(skygraph::loadExr(dir_ / "x.exr").rgba.size(), image.rgba.size());
}

TEST_F(HdrImageTest, MissingEmptyAndDirectoryInputsNameTheFile) {
    expectLoadError(dir_ / "missing.hdr", "no such file");
    expectLoadError(dir_ / "missing.exr", "no such file");
    writeBytes(dir_ / "empty.hdr", "");
    expectLoadError(dir_ / "empty.hdr", "empty file");
    writeBytes(dir_ / "empty.exr", "");
    expectLoadError(dir_ / "empty.exr", "empty file");
    fs::create_directory(dir_ / "dir.exr");
    expectLoadError(dir_ / "dir.exr", "not a regular file");
    writeBytes(dir_ / "image.tga", "x");
    expectLoadError(dir_ / "image.tga", "unknown image extension");
}

// A scene may name an environment file whose name holds control characters: the message is
// one line that shows them escaped, and file() keeps the path as it is.
TEST_F(HdrImageTest, AFileNamedWithControlCharactersIsShownEscaped) {
    const fs::path odd = dir_ / "sky\a\n\x1b.exr";
    writeBytes(odd, "");
    try {
        (void)skygraph::loadHdrImage(odd);
        FAIL() << "an empty file loaded";
    } catch (const ImageError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what, "'" + dir_.string() + "/sky\\u0007\\u000a\\u001b.exr': empty file; expected an OpenEXR image");
        EXPECT_EQ(e.file(), odd);
    }
}

TEST_F(HdrImageTest, TruncatedFilesGiveACleanError) {
    const std::vector<fs::path> sources = {kStudioLights / "studio.exr", dir_ / "rle.hdr", dir_ / "flat.hdr",
                                           dir_ / "zip.exr"};
    skygraph::saveHdrImage(dir_ / "rle.hdr", pattern(64, 32));
    skygraph::saveHdrImage(dir_ / "flat.hdr", pattern(5, 32));  // width < 8: uncompressed pixels
    skygraph::saveHdrImage(dir_ / "zip.exr", pattern(64, 64));
    for (const fs::path& src : sources) {
        SCOPED_TRACE(src.string());
        const std::string bytes = readBytes(src);
        ASSERT_GT(bytes.size(), 100u);
        const fs::path cut = dir_ / ("half_" + src.filename().string());
        writeBytes(cut, bytes.substr(0, bytes.size() / 2));
        expectLoadError(cut, "truncated");
    }
    writeBytes(dir_ / "header_only.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 16\n");
    expectLoadError(dir_ / "header_only.hdr", "truncated");
    writeBytes(dir_ / "cut_header.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n");
    expectLoadError(dir_ / "cut_header.hdr", "header");
}

TEST_F(HdrImageTest, GarbageAndWrongFormatsGiveACleanError) {
    std::mt19937 rng(7);
    std::string noise(4096, '\0');
    for (char& c : noise) c = char(rng());
    writeBytes(dir_ / "noise.hdr", noise);
    expectLoadError(dir_ / "noise.hdr", "not a Radiance HDR image");
    writeBytes(dir_ / "noise.exr", noise);
    expectLoadError(dir_ / "noise.exr", "not an OpenEXR image");
    // A valid EXR signature followed by noise.
    writeBytes(dir_ / "magic_noise.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + noise);
    expectLoadError(dir_ / "magic_noise.exr", "magic_noise.exr");
    // A valid RGBE header whose run-length data contains a zero count (stb_image would spin).
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 16\n";
    const std::string ones(300, '\x01');
    writeBytes(dir_ / "zero_run.hdr", header + std::string("\x02\x02\x00\x10\x00", 5) + ones);
    expectLoadError(dir_ / "zero_run.hdr", "corrupt data");
    writeBytes(dir_ / "long_run.hdr", header + std::string("\x02\x02\x00\x10\xff\x01", 6) + ones);
    expectLoadError(dir_ / "long_run.hdr", "corrupt data");
    writeBytes(dir_ / "bad_format.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 16\n" + noise);
    expectLoadError(dir_ / "bad_format.hdr", "XYZE .hdr files (FORMAT=32-bit_rle_xyze) are not supported");
    writeBytes(dir_ / "zero.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 16\n");
    expectLoadError(dir_ / "zero.hdr", "zero size");
    writeBytes(dir_ / "huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 99999999999999999999 +X 4\n");
    expectLoadError(dir_ / "huge.hdr", "size 4x9223372036854775807 exceeds the limit");
    // Sizes past 32 bits are refused as the header says them: stb keeps their low 32 bits, which
    // made 2^32 + 8 rows of 16 load as a 16x8 image, and 2^32 + 1 rows of 8 as 8x1.
    const std::string pixels(size_t(128) * 4, '\x80');
    for (const char* size : {"-Y 4294967304 +X 16", "-Y 8 +X 4294967312", "-Y 4294967297 +X 8", "+X 4294967304 -Y 16"}) {
        writeBytes(dir_ / "wrapped.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + std::string(size) + "\n" + pixels);
        expectLoadError(dir_ / "wrapped.hdr", "exceeds the limit 16384x");
    }
    // A signature the readers do not take, said as such (not "not a Radiance image (it is one)").
    writeBytes(dir_ / "crlf.hdr", "#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 2 +X 16\r\n" + noise);
    expectLoadError(dir_ / "crlf.hdr", "must end its line with a newline alone");
    writeBytes(dir_ / "magic_only.exr", std::string("\x76\x2f\x31\x01", 4));
    expectLoadError(dir_ / "magic_only.exr", "not a valid OpenEXR file: truncated or corrupt header");
    // Run-length rows, then one without: stb reads the whole image again from there, so the
    // row the pixels run out in counts from the first.
    std::string rows = header;
    for (int row = 0; row < 1; ++row) {
        rows += std::string("\x02\x02\x00\x10", 4);
        for (int channel = 0; channel < 4; ++channel) rows += std::string("\x90\x01", 2);  // a run of 16
    }
    writeBytes(dir_ / "rle_then_flat.hdr", rows + std::string(16 * 4, '\x01'));
    expectLoadError(dir_ / "rle_then_flat.hdr", "ends in row 1 of 2");
}

// The version field's deep-data flag is only a claim: after the EXR signature, garbage or
// nothing at all (with that flag set or an unknown version) makes no valid OpenEXR file, and
// only a file whose header says its part is deep is refused as a deep image.
TEST_F(HdrImageTest, OnlyAnExrWhoseHeaderSaysDeepIsRefusedAsDeep) {
    const std::string signature("\x76\x2f\x31\x01", 4);
    const std::string deepFlag("\x02\x08\0\0", 4);  // version 2 with the non-image (deep) flag
    writeBytes(dir_ / "deep_flag_garbage.exr", signature + deepFlag + std::string(300, 'x'));
    expectLoadError(dir_ / "deep_flag_garbage.exr", "not a valid OpenEXR file: truncated or corrupt header");
    writeBytes(dir_ / "deep_flag_only.exr", signature + deepFlag);
    expectLoadError(dir_ / "deep_flag_only.exr", "not a valid OpenEXR file: truncated or corrupt header");
    writeBytes(dir_ / "unknown_version.exr", signature + std::string("\x07\x08\x01\x00", 4) + std::string(300, 'x'));
    expectLoadError(dir_ / "unknown_version.exr", "not a valid OpenEXR file: unknown version field 0x00010807");
    for (const char* name : {"deep_flag_garbage.exr", "deep_flag_only.exr", "unknown_version.exr"}) {
        try {
            (void)skygraph::loadHdrImage(dir_ / name);
        } catch (const ImageError& e) {
            EXPECT_EQ(std::string(e.what()).find("deep OpenEXR images"), std::string::npos) << e.what();
        }
    }

    // A real deep scanline file, of 4x4 pixels with no samples.
    const fs::path deep = dir_ / "deep.exr";
    {
        Imf::Header header(4, 4);
        header.setType(Imf::DEEPSCANLINE);
        header.compression() = Imf::ZIPS_COMPRESSION;
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        Imf::DeepScanLineOutputFile out(deep.c_str(), header);
        std::vector<unsigned> counts(16, 0);
        std::vector<float*> depths(16, nullptr);
        Imf::DeepFrameBuffer frame;
        frame.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()), sizeof(unsigned),
                                                4 * sizeof(unsigned)));
        frame.insert("Z", Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(depths.data()), sizeof(float*),
                                         4 * sizeof(float*), sizeof(float)));
        out.setFrameBuffer(frame);
        out.writePixels(4);
    }
    expectLoadError(deep, "deep OpenEXR images are not supported");
}

// stb_image reads RGBE pixels only; a valid XYZE file is refused as the format it is, not as a
// corrupt header. Another FORMAT is named as unknown.
TEST_F(HdrImageTest, XyzeHdrIsRefusedAsUnsupportedNotAsCorrupt) {
    const std::string pixels(2 * 4 * 4, '\x80');  // flat: narrower than 8, so no run-length rows
    writeBytes(dir_ / "xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\nEXPOSURE=1\n\n-Y 2 +X 4\n" + pixels);
    expectLoadError(dir_ / "xyze.hdr",
                    "XYZE .hdr files (FORMAT=32-bit_rle_xyze) are not supported; only FORMAT=32-bit_rle_rgbe is");
    try {
        (void)skygraph::loadHdrImage(dir_ / "xyze.hdr");
    } catch (const ImageError& e) {
        EXPECT_EQ(std::string(e.what()).find("corrupt or truncated header"), std::string::npos) << e.what();
    }
    writeBytes(dir_ / "other.hdr", "#?RADIANCE\nFORMAT=24-bit_rgb\n\n-Y 2 +X 4\n" + pixels);
    expectLoadError(dir_ / "other.hdr", "unknown pixel format FORMAT=24-bit_rgb; expected FORMAT=32-bit_rle_rgbe");
    // The same pixels under an RGBE header still load.
    writeBytes(dir_ / "rgbe.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1\n\n-Y 2 +X 4\n" + pixels);
    EXPECT_EQ(skygraph::loadHdrImage(dir_ / "rgbe.hdr").width, 4u);
}

// Radiance's EXPOSURE= and COLORCORR= are multipliers already applied to the pixels, and
// cumulative: the reader divides by their product (per channel for COLORCORR) to give
// radiance. A value that is not a positive number is a corrupt header, named with its line.
TEST_F(HdrImageTest, RadianceExposureAndColourCorrectionAreDividedOut) {
    std::string pixels;
    for (int i = 0; i < 4 * 2; ++i) pixels += "\x80\x80\x80\x81";  // (1, 1, 1) in RGBE: 128 * 2^(129-136)
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n";
    writeBytes(dir_ / "plain.hdr", header + "\n-Y 2 +X 4\n" + pixels);
    EXPECT_EQ(skygraph::loadHdrImage(dir_ / "plain.hdr").rgba[0], 1.0f);
    writeBytes(dir_ / "exposed.hdr", header + "EXPOSURE=2\nEXPOSURE= 2.0\nCOLORCORR=1 2 0.5\n\n-Y 2 +X 4\n" + pixels);
    const HdrImage exposed = skygraph::loadHdrImage(dir_ / "exposed.hdr");
    for (size_t i = 0; i < 8; ++i) {
        EXPECT_EQ(exposed.rgba[i * 4 + 0], 0.25f);
        EXPECT_EQ(exposed.rgba[i * 4 + 1], 0.125f);
        EXPECT_EQ(exposed.rgba[i * 4 + 2], 0.5f);
        EXPECT_EQ(exposed.rgba[i * 4 + 3], 1.0f);
    }
    writeBytes(dir_ / "zero.hdr", header + "EXPOSURE=0\n\n-Y 2 +X 4\n" + pixels);
    expectLoadError(dir_ / "zero.hdr", "corrupt header line 'EXPOSURE=0': EXPOSURE= takes a positive number");
    // An exposure that divides out past a float's range gives the largest float, not infinity
    // (which the environment loaders refused as a non-finite pixel); lines multiplying past a
    // double's range are a corrupt header.
    writeBytes(dir_ / "dim.hdr", header + "EXPOSURE=1e-40\n\n-Y 2 +X 4\n" + pixels);
    const HdrImage dim = skygraph::loadHdrImage(dir_ / "dim.hdr");
    for (size_t i = 0; i < 8; ++i) EXPECT_EQ(dim.rgba[i * 4], std::numeric_limits<float>::max());
    writeBytes(dir_ / "vanishing.hdr", header + "EXPOSURE=1e-200\nEXPOSURE=1e-200\n\n-Y 2 +X 4\n" + pixels);
    expectLoadError(dir_ / "vanishing.hdr", "its EXPOSURE= and COLORCORR= lines multiply to 0, past the range");
    writeBytes(dir_ / "short.hdr", header + "COLORCORR=1 2\n\n-Y 2 +X 4\n" + pixels);
    expectLoadError(dir_ / "short.hdr", "corrupt header line 'COLORCORR=1 2': COLORCORR= takes 3 positive numbers");
}

// The resolution line orders the pixels eight ways (Radiance's file format): scanlines along Y
// down ("-Y", the standard) or up ("+Y"), pixels along X right ("+X") or left ("-X"), or
// transposed, scanlines along X ("+X W -Y H"). stb_image reads only "-Y H +X W"; every order
// loads as the same image, top row first.
TEST_F(HdrImageTest, EveryRadianceScanlineOrderLoadsTheSameImage) {
    constexpr uint32_t kW = 4, kH = 2;
    // Distinct red per pixel: (64 + 16 x + 4 y) / 128.
    const auto pixel = [](uint32_t x, uint32_t y) {
        return std::string{char(64 + 16 * x + 4 * y), '\x40', '\x40', '\x81'};
    };
    struct Order {
        const char* line;
        uint32_t scanlines, perScanline;
        std::function<std::pair<uint32_t, uint32_t>(uint32_t, uint32_t)> at;  // (scanline, pixel) -> (x, y)
    };
    const Order orders[] = {
        {"-Y 2 +X 4", kH, kW, [](uint32_t i, uint32_t j) { return std::pair{j, i}; }},
        {"+Y 2 +X 4", kH, kW, [](uint32_t i, uint32_t j) { return std::pair{j, kH - 1 - i}; }},
        {"-Y 2 -X 4", kH, kW, [](uint32_t i, uint32_t j) { return std::pair{kW - 1 - j, i}; }},
        {"+Y 2 -X 4", kH, kW, [](uint32_t i, uint32_t j) { return std::pair{kW - 1 - j, kH - 1 - i}; }},
        {"+X 4 -Y 2", kW, kH, [](uint32_t i, uint32_t j) { return std::pair{i, j}; }},
        {"+X 4 +Y 2", kW, kH, [](uint32_t i, uint32_t j) { return std::pair{i, kH - 1 - j}; }},
        {"-X 4 -Y 2", kW, kH, [](uint32_t i, uint32_t j) { return std::pair{kW - 1 - i, j}; }},
        {"-X 4 +Y 2", kW, kH, [](uint32_t i, uint32_t j) { return std::pair{kW - 1 - i, kH - 1 - j}; }},
    };
    for (const Order& o : orders) {
        std::string pixels;
        for (uint32_t i = 0; i < o.scanlines; ++i)
            for (uint32_t j = 0; j < o.perScanline; ++j) pixels += pixel(o.at(i, j).first, o.at(i, j).second);
        writeBytes(dir_ / "order.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + std::string(o.line) + "\n" + pixels);
        const HdrImage image = skygraph::loadHdrImage(dir_ / "order.hdr");
        ASSERT_EQ(image.width, kW) << o.line;
        ASSERT_EQ(image.height, kH) << o.line;
        for (uint32_t y = 0; y < kH; ++y)
            for (uint32_t x = 0; x < kW; ++x)
                EXPECT_EQ(image.rgba[(y * kW + x) * 4], float(64 + 16 * x + 4 * y) / 128.0f)
                    << o.line << " at (" << x << ", " << y << ")";
    }
}

// stb_image ends the header at a line that starts with NUL as at an empty one. The check that
// ended it only at the empty line walked a valid row after "R", while stb read its pixels from
// after "-Y 1 +X 16": a run-length row whose first dump of 16 ends at the end of the file,
// where stb reads zero counts forever.
TEST_F(HdrImageTest, AHeaderEndedByALineStartingWithNulIsCheckedWhereStbEndsIt) {
    std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n" + std::string("\0\n", 2) + "-Y 1 +X 16\n" +
                        std::string("\x02\x02\x00\x10\x10\n", 6) + "\n" + "R\n" + std::string("\x02\x02\x00\x10", 4);
    for (int channel = 0; channel < 4; ++channel) bytes += std::string("\x90\x01", 2);  // a run of 16
    writeBytes(dir_ / "nul_line.hdr", bytes);
    expectLoadError(dir_ / "nul_line.hdr", "truncated: the pixel data ends in row 0 of 1");
}

TEST_F(HdrImageTest, PngRenamedToHdrOrExrIsRefusedAsPng) {
    const std::vector<uint8_t> pixels(8 * 8 * 4, 128);
    ASSERT_TRUE(stbi_write_png((dir_ / "p.hdr").c_str(), 8, 8, 4, pixels.data(), 32));
    expectLoadError(dir_ / "p.hdr", "it is a PNG image");
    fs::copy_file(dir_ / "p.hdr", dir_ / "p.exr");
    expectLoadError(dir_ / "p.exr", "it is a PNG image");
    skygraph::saveHdrImage(dir_ / "e.exr", pattern(4, 4));
    fs::rename(dir_ / "e.exr", dir_ / "e.hdr");
    expectLoadError(dir_ / "e.hdr", "it is an OpenEXR image");
}

// A header that claims 100000 x 100000 (160 GB as RGBA float) must be refused from the header,
// before any allocation: the load runs in a child whose address space is capped at 512 MiB
// above what it already uses, and must end with our error, which names the file and says
// `expected`.
void loadUnderMemoryCap(const fs::path& path, const std::string& expected) {
    rlimit limit{};
    getrlimit(RLIMIT_AS, &limit);
    std::ifstream statm("/proc/self/statm");
    size_t pages = 0;
    statm >> pages;
    limit.rlim_cur = rlim_t(pages) * rlim_t(sysconf(_SC_PAGESIZE)) + (rlim_t(512) << 20);
    setrlimit(RLIMIT_AS, &limit);
    try {
        (void)skygraph::loadHdrImage(path);
    } catch (const ImageError& e) {
        const std::string what = e.what();
        std::exit(what.find(expected) != std::string::npos &&
                          what.find(path.string()) != std::string::npos
                      ? 0
                      : 3);
    } catch (...) {
        std::exit(4);
    }
    std::exit(5);
}

TEST_F(HdrImageTest, HugeHeaderIsRefusedBeforeAllocating) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const fs::path hdr = dir_ / "huge.hdr";
    writeBytes(hdr, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n" + std::string(64, '\x02'));
    EXPECT_EXIT(loadUnderMemoryCap(hdr, "100000x100000 exceeds the limit 16384x16384"), ::testing::ExitedWithCode(0), "");

    // An EXR header with a 100000 x 100000 data window and no pixel data.
    const fs::path exr = dir_ / "huge.exr";
    {
        Imf::Header header(100000, 100000);
        header.compression() = Imf::NO_COMPRESSION;
        header.channels().insert("R", Imf::Channel(Imf::HALF));
        Imf::OutputFile out(exr.c_str(), header);
    }
    EXPECT_EXIT(loadUnderMemoryCap(exr, "100000x100000 exceeds the limit 16384x16384"), ::testing::ExitedWithCode(0), "");

    // Within the limit, 16384 x 8192 (2 GiB as RGBA float), and still no pixel data: refused
    // as truncated before the pixels are allocated.
    const fs::path claim = dir_ / "claim.exr";
    {
        Imf::Header header(16384, 8192);
        header.compression() = Imf::ZIP_COMPRESSION;
        header.channels().insert("R", Imf::Channel(Imf::HALF));
        Imf::OutputFile out(claim.c_str(), header);
    }
    ASSERT_LT(fs::file_size(claim), 1u << 20);
    EXPECT_EXIT(loadUnderMemoryCap(claim, "truncated"), ::testing::ExitedWithCode(0), "");
}

}  // namespace
