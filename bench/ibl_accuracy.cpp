// Accuracy of cube maps and IBL products against the double-precision truth of an analytic
// environment (tests/ibl/analytic_environment.hpp's sunSky), for bench/ibl_compare.sh:
//   ibl_accuracy input FILE.(hdr|exr) WIDTH        write the environment as an equirect map
//   ibl_accuracy ktx2 PREFIX                        score PREFIX.ktx2 (+ .prefiltered, .irradiance)
//   ibl_accuracy cmgen DIR                          score cmgen --ibl-ld faces (DIR/m<L>_<face>.exr)
//   ibl_accuracy exrenvmap FILE.exr INPUT_WIDTH     score exrenvmap's cube (6 faces stacked)
// Each scored image prints one line: product, level, size, roughness, RMSE and max of the
// relative error |got - truth| / truth over RGB. Faces of other tools are compared under
// each of 8 horizontal orientation conventions (mirrors, quarter turns about +Y) and the best
// one is reported, so a convention difference is not counted as error.
#include "analytic_environment.hpp"

#include <skygraph/hdr_image.hpp>

#include <Imath/half.h>
#include <OpenEXR/ImfEnvmap.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

using namespace skygraph;
using skygraph::test::Dir;
using skygraph::test::sunSky;

namespace {

using Faces = std::vector<HdrImage>;  // Vulkan order +X,-X,+Y,-Y,+Z,-Z

/// Reads the levels of a KTX2 file as written by saveKtx2 (RGBA16F/32F, no supercompression).
std::vector<Faces> readKtx2(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> b((std::istreambuf_iterator<char>(in)), {});
    if (b.size() < 80) throw std::runtime_error("cannot read " + path);
    auto u32 = [&](size_t o) { uint32_t v; std::memcpy(&v, &b[o], 4); return v; };
    auto u64 = [&](size_t o) { uint64_t v; std::memcpy(&v, &b[o], 8); return v; };
    const uint32_t typeSize = u32(16), width = u32(20), faces = u32(36), levels = u32(40);
    std::vector<Faces> out;
    for (uint32_t m = 0; m < levels; ++m) {
        const size_t offset = u64(80 + m * 24);
        const uint32_t n = std::max(1u, width >> m);
        Faces level;
        for (uint32_t f = 0; f < faces; ++f) {
            HdrImage img{n, n, std::vector<float>(size_t(n) * n * 4)};
            for (size_t i = 0; i < img.rgba.size(); ++i) {
                const size_t at = offset + (size_t(f) * n * n * 4 + i) * typeSize;
                if (typeSize == 4) std::memcpy(&img.rgba[i], &b[at], 4);
                else { uint16_t h; std::memcpy(&h, &b[at], 2); Imath::half x; x.setBits(h); img.rgba[i] = float(x); }
            }
            level.push_back(std::move(img));
        }
        out.push_back(std::move(level));
    }
    return out;
}

/// Direction conventions to try for other tools: d -> candidate(d) before the truth is read.
Dir orient(const Dir& d, int k) {
    Dir r = (k & 4) ? Dir(-d.x, d.y, d.z) : d;  // mirror
    for (int q = 0; q < (k & 3); ++q) r = Dir(-r.z, r.y, r.x);  // quarter turns about +Y
    return r;
}

struct Score {
    double rmse = 0.0, max = 0.0;
};

/// Relative error of `faces` against `truth(face, x, y, size)`, over every `stride`-th texel.
Score score(const Faces& faces, const std::function<Dir(int, uint32_t, uint32_t, uint32_t)>& truth, uint32_t stride) {
    const uint32_t n = faces[0].width;
    double sum = 0.0, worst = 0.0;
    size_t count = 0;
    for (int f = 0; f < 6; ++f)
        for (uint32_t y = stride / 2; y < n; y += stride)
            for (uint32_t x = stride / 2; x < n; x += stride) {
                const Dir want = truth(f, x, y, n);
                const float* got = faces[size_t(f)].pixel(x, y);
                for (int c = 0; c < 3; ++c) {
                    const double e = std::abs(got[c] - want[c]) / std::max(want[c], 1e-3);
                    sum += e * e;
                    worst = std::max(worst, e);
                    ++count;
                }
            }
    return {std::sqrt(sum / double(count)), worst};
}

Dir texelDir(int f, uint32_t x, uint32_t y, uint32_t n) { return test::texelDirection(f, x, y, n); }

/// Environment level: the truth is the texel's mean (4x4 sub-texel points).
Score scoreEnvironment(const Faces& faces, int orientation) {
    const uint32_t n = faces[0].width;
    const auto radiance = [&](const Dir& d) { return sunSky(orient(d, orientation)); };
    return score(faces, [&](int f, uint32_t x, uint32_t y, uint32_t) {
        return math::ibl::cubeTexelMean(radiance, f, int(x), int(y), int(n), 4);
    }, std::max(1u, n / 64));
}

Score scorePrefiltered(const Faces& faces, double roughness, int orientation) {
    const auto radiance = [&](const Dir& d) { return sunSky(orient(d, orientation)); };
    return score(faces, [&](int f, uint32_t x, uint32_t y, uint32_t n) {
        if (roughness <= 0.0) return math::ibl::cubeTexelMean(radiance, f, int(x), int(y), int(n), 4);
        return math::ibl::prefilteredRadiance(radiance, texelDir(f, x, y, n), roughness, 2048);
    }, std::max(1u, faces[0].width / 12));
}

int bestOrientation(const Faces& level0) {
    int best = 0;
    double bestRmse = 1e30;
    for (int k = 0; k < 8; ++k) {
        const Faces small = level0;  // scored on a coarse stride for speed
        const double r = score(small, [&](int f, uint32_t x, uint32_t y, uint32_t n) {
            return sunSky(orient(texelDir(f, x, y, n), k));
        }, std::max(1u, level0[0].width / 16)).rmse;
        if (r < bestRmse) bestRmse = r, best = k;
    }
    return best;
}

void print(const char* tool, const char* product, size_t level, uint32_t size, double roughness, Score s) {
    std::printf("%-10s %-12s level %zu  %4u^2  roughness %.3f  rmse %.5f  max %.5f\n", tool, product, level, size,
                roughness, s.rmse, s.max);
}

}  // namespace

int main(int argc, char** argv) try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "input" && argc == 4) {
        const uint32_t w = uint32_t(std::stoul(argv[3]));
        const ImageData image = test::equirectImage(sunSky, w, w / 2);
        saveHdrImage(argv[2], HdrImage{image.width, image.height, image.rgba});
        return 0;
    }
    if (mode == "ktx2" && argc == 3) {
        const std::string prefix = argv[2];
        const auto env = readKtx2(prefix + ".ktx2");
        print("skygraph", "environment", 0, env[0][0].width, 0.0, scoreEnvironment(env[0], 0));
        const auto pre = readKtx2(prefix + ".prefiltered.ktx2");
        for (size_t m = 0; m < pre.size(); ++m) {
            const double r = double(m) / double(pre.size() - 1);  // mip / (mips - 1)
            print("skygraph", "prefiltered", m, pre[m][0].width, r, scorePrefiltered(pre[m], r, 0));
        }
        return 0;
    }
    if (mode == "cmgen" && argc == 3) {
        const char* names[6] = {"px", "nx", "py", "ny", "pz", "nz"};
        std::vector<Faces> levels;
        for (int m = 0;; ++m) {
            Faces faces;
            for (const char* face : names) {
                const std::string file = std::string(argv[2]) + "/m" + std::to_string(m) + "_" + face + ".exr";
                if (!std::ifstream(file)) break;
                faces.push_back(loadHdrImage(file));
            }
            if (faces.size() != 6) break;
            levels.push_back(std::move(faces));
        }
        if (levels.empty()) throw std::runtime_error(std::string("no cmgen faces in ") + argv[2]);
        const int k = bestOrientation(levels[0]);
        std::printf("cmgen faces under orientation %d (mirror %d, quarter turns %d)\n", k, k >> 2, k & 3);
        for (size_t m = 0; m < levels.size(); ++m) {
            // Filament: lod = r (2 - r) over levels 0 .. L-1, so r = 1 - sqrt(1 - m / (L - 1)).
            const double lod = levels.size() > 1 ? double(m) / double(levels.size() - 1) : 0.0;
            const double r = 1.0 - std::sqrt(1.0 - lod);
            print("cmgen", "prefiltered", m, levels[m][0].width, r, scorePrefiltered(levels[m], r, k));
        }
        return 0;
    }
    if (mode == "exrenvmap" && argc == 4) {
        // OpenEXR's own conventions (ImfEnvmap.h) translate each cube texel to the equirect
        // pixel exrenvmap read, and that pixel to our direction: no orientation guess.
        const HdrImage strip = loadHdrImage(argv[2]);
        const int inputWidth = std::stoi(argv[3]);
        const Imath::Box2i cubeWindow({0, 0}, {int(strip.width) - 1, int(strip.height) - 1});
        const Imath::Box2i latLongWindow({0, 0}, {inputWidth - 1, inputWidth / 2 - 1});
        const auto truthAt = [&](Imf::CubeMapFace face, float x, float y) {
            const Imath::V3f d = Imf::CubeMap::direction(face, cubeWindow, {x, y});
            const Imath::V2f p = Imf::LatLongMap::pixelPosition(latLongWindow, d);
            return sunSky(math::equirectToDirection(
                math::Vec2<double>((p.x + 0.5) / inputWidth, (p.y + 0.5) / (inputWidth / 2))));
        };
        const uint32_t n = strip.width;
        double sum = 0.0, worst = 0.0;
        size_t count = 0;
        for (int f = 0; f < 6; ++f)
            for (uint32_t y = 2; y < n; y += std::max(1u, n / 64))
                for (uint32_t x = 2; x < n; x += std::max(1u, n / 64)) {
                    const auto face = Imf::CubeMapFace(f);
                    Dir want(0.0);
                    for (int j = 0; j < 4; ++j)
                        for (int i = 0; i < 4; ++i)
                            want += truthAt(face, float(x) - 0.5f + (float(i) + 0.5f) / 4, float(y) - 0.5f + (float(j) + 0.5f) / 4) / 16.0;
                    const Imath::V2f at = Imf::CubeMap::pixelPosition(face, cubeWindow, {float(x), float(y)});
                    const float* got = strip.pixel(uint32_t(std::lround(at.x)), uint32_t(std::lround(at.y)));
                    for (int c = 0; c < 3; ++c) {
                        const double e = std::abs(got[c] - want[c]) / std::max(want[c], 1e-3);
                        sum += e * e;
                        worst = std::max(worst, e);
                        ++count;
                    }
                }
        print("exrenvmap", "environment", 0, n, 0.0, {std::sqrt(sum / double(count)), worst});
        return 0;
    }
    std::fprintf(stderr, "usage: ibl_accuracy input FILE W | ktx2 PREFIX | cmgen DIR | exrenvmap FILE.exr INPUT_WIDTH\n");
    return 2;
} catch (const std::exception& e) {
    std::fprintf(stderr, "ibl_accuracy: %s\n", e.what());
    return 1;
}
