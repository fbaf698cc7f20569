#include "equirect_resample.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace skygraph::app {
namespace {

/// For each output index along one axis: the input indices it reads and their weights.
struct Taps {
    std::vector<std::vector<std::pair<uint32_t, float>>> of;
};

Taps tapsFor(uint32_t in, uint32_t out, bool wrap) {
    Taps t;
    t.of.resize(out);
    const double scale = double(in) / out;
    for (uint32_t i = 0; i < out; ++i) {
        auto& taps = t.of[i];
        if (scale >= 1.0) {  // shrink: the covered fraction of each input texel
            const double lo = i * scale, hi = (i + 1) * scale;
            for (auto k = uint32_t(lo); k < std::min<double>(std::ceil(hi), in); ++k) {
                const double cover = std::min<double>(hi, k + 1) - std::max<double>(lo, k);
                if (cover > 0.0) taps.emplace_back(k, float(cover / scale));
            }
            continue;
        }
        const double x = (i + 0.5) * scale - 0.5;  // grow: between the two nearest centres
        const auto k0 = int64_t(std::floor(x));
        const auto f = float(x - double(k0));
        const auto at = [&](int64_t k) {
            if (wrap) return uint32_t(((k % in) + in) % in);
            return uint32_t(std::clamp<int64_t>(k, 0, in - 1));
        };
        taps.emplace_back(at(k0), 1.0f - f);
        taps.emplace_back(at(k0 + 1), f);
    }
    return t;
}

}  // namespace

HdrImage resampleEquirect(const HdrImage& from, uint32_t width, uint32_t height) {
    const Taps across = tapsFor(from.width, width, true), down = tapsFor(from.height, height, false);
    HdrImage rows;  // width x from.height
    rows.width = width;
    rows.height = from.height;
    rows.rgba.assign(size_t(width) * from.height * 4, 0.0f);
    for (uint32_t y = 0; y < from.height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            for (const auto& [k, w] : across.of[x])
                for (int c = 0; c < 4; ++c) rows.rgba[(size_t(y) * width + x) * 4 + c] += w * from.pixel(k, y)[c];
    HdrImage out;
    out.width = width;
    out.height = height;
    out.rgba.assign(size_t(width) * height * 4, 0.0f);
    for (uint32_t y = 0; y < height; ++y)
        for (const auto& [k, w] : down.of[y])
            for (uint32_t x = 0; x < width; ++x)
                for (int c = 0; c < 4; ++c) out.rgba[(size_t(y) * width + x) * 4 + c] += w * rows.pixel(x, k)[c];
    return out;
}

}  // namespace skygraph::app
