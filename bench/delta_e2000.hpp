// CIEDE2000 between sRGB-encoded colours, via Little CMS (sRGB -> Lab D50, relative
// colorimetric): the colour difference that study and aces_fits report after tonemapping.
#pragma once

#include <lcms2.h>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace skygraph::bench {

/// Owns one Little CMS transform; not copyable (the transform would be freed twice).
class DeltaE2000 {
public:
    DeltaE2000() {
        cmsHPROFILE srgb = cmsCreate_sRGBProfile();
        cmsHPROFILE lab = cmsCreateLab4Profile(nullptr);
        transform_ = cmsCreateTransform(srgb, TYPE_RGB_DBL, lab, TYPE_Lab_DBL, INTENT_RELATIVE_COLORIMETRIC, 0);
        cmsCloseProfile(srgb);
        cmsCloseProfile(lab);
    }
    ~DeltaE2000() { cmsDeleteTransform(transform_); }
    DeltaE2000(const DeltaE2000&) = delete;
    DeltaE2000& operator=(const DeltaE2000&) = delete;

    /// Between two sRGB-encoded RGB triples in [0, 1].
    [[nodiscard]] double operator()(const double a[3], const double b[3]) const {
        cmsCIELab la, lb;
        cmsDoTransform(transform_, a, &la, 1);
        cmsDoTransform(transform_, b, &lb, 1);
        return cmsCIE2000DeltaE(&la, &lb, 1, 1, 1);
    }

    /// (mean, max) over the pixels; `a` and `b` hold sRGB-encoded RGB in [0, 1] per pixel.
    [[nodiscard]] std::pair<double, double> compare(const std::vector<double>& a, const std::vector<double>& b) const {
        double sum = 0, worst = 0;
        const size_t n = std::min(a.size(), b.size()) / 3;
        for (size_t i = 0; i < n; ++i) {
            const double de = (*this)(&a[3 * i], &b[3 * i]);
            sum += de;
            worst = std::max(worst, de);
        }
        return {sum / double(std::max<size_t>(n, 1)), worst};
    }

private:
    cmsHTRANSFORM transform_;
};

}  // namespace skygraph::bench
