// The reference ACES transform (bench/aces_reference.hpp, OpenColorIO built-ins) held to
// values derived independently from the ACES 1.0 CTL's published constants (ampas/aces-dev,
// transforms/ctl/lib and transforms/ctl/README-MATRIX.md), and each fit's error against it
// pinned to what docs/tradeoffs.md reports, so that a change to a fit or to the chain shows.
#include "aces_reference.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace skygraph::aces {
namespace {

const Reference& reference() {
    static const Reference r;
    return r;
}

// ACESlib.Tonescales.ctl: the RRT maps ACES 0.18 to OCES 4.8 (RRT_PARAMS.midPoint) and the
// 48-nit ODT maps OCES 4.8 to 4.8 cd/m^2 (ODT_48nits.midPoint). ACESlib.ODT_Common.ctl:
// linCV = (Y - 0.02) / (48 - 0.02), then the dim-surround Y^0.9811. A neutral stays neutral
// (the RRT's glow, red modifier and saturation and the ODT's saturation leave greys alone).
const double kGrey18Display = std::pow((4.8 - 0.02) / (48.0 - 0.02), 0.9811);  // 0.104064

TEST(AcesReference, MidGreyMatchesTheCtlTonescale) {
    const Rgb out = reference().displayLinearFromAces(Rgb(0.18));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[k], kGrey18Display, 2e-5) << "channel " << k;
    // Rec.709 and ACES2065-1 share neutrals (Bradford maps D65 white to D60 white).
    EXPECT_NEAR(reference().displayLinear(Rgb(0.18)).g, kGrey18Display, 2e-5);
    // In codes: sRGB 0.356 (91 of 255), BT.1886 0.390 (99 of 255).
    EXPECT_NEAR(reference().encoded(Rgb(0.18), Encoding::Srgb).g, math::srgbEncode(kGrey18Display), 2e-5);
    EXPECT_NEAR(reference().encoded(Rgb(0.18), Encoding::Bt1886).g, std::pow(kGrey18Display, 1 / 2.4), 2e-5);
}

TEST(AcesReference, BlackAndHighlightsFollowTheOdtEnds) {
    // Below the ODT's minPoint the tonescale returns CINEMA_BLACK, which Y_2_linCV maps to 0.
    EXPECT_NEAR(reference().displayLinear(Rgb(0.0)).g, 0.0, 1e-6);
    // Above maxPoint (OCES for ACES 0.18 * 2^6.5) the slope is 0.04 > 0: past display white.
    EXPECT_GT(reference().displayLinearFromAces(Rgb(1000.0)).g, 1.0);
    EXPECT_LT(reference().displayLinearFromAces(Rgb(0.18 * std::pow(2.0, 6.0))).g, 1.0);
}

TEST(AcesReference, Rec709ToAp0IsTheCtlMatricesWithBradford) {
    // README-MATRIX.md, written as textbook rows; glm takes columns, hence the transposes.
    const glm::dmat3 ap0ToXyz = glm::transpose(glm::dmat3(0.9525523959, 0.0, 0.0000936786, 0.3439664498, 0.7281660966,
                                                          -0.0721325464, 0.0, 0.0, 1.0088251844));
    const glm::dmat3 xyzToRec709 = glm::transpose(glm::dmat3(3.2409699419, -1.5373831776, -0.4986107603, -0.9692436363,
                                                             1.8759675015, 0.0415550574, 0.0556300797, -0.2039769589,
                                                             1.0569715142));
    const glm::dmat3 d60ToD65 = glm::transpose(
        glm::dmat3(0.987224, -0.00611327, 0.0159533, -0.00759836, 1.00186, 0.00533002, 0.00307257, -0.00509595, 1.08168));
    const glm::dmat3 rec709ToAp0 = glm::inverse(ap0ToXyz) * glm::inverse(d60ToD65) * glm::inverse(xyzToRec709);
    for (int c = 0; c < 3; ++c) {
        Rgb in(0.0);
        in[c] = 1.0;
        const Rgb got = reference().toAces(in), want = rec709ToAp0 * in;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 3e-4) << "Rec.709 primary " << c << ", AP0 channel " << k;
    }
}

TEST(AcesReference, EncodingsAgreeWithSkygraphsCurves) {
    // The reference's display transforms and the fits' encode must be the same curves, or the
    // fit errors would include an encoding difference.
    for (double x : {0.001, 0.01, 0.0031308, 0.1, 0.5, 0.9}) {
        const Rgb lin = reference().displayLinear(Rgb(x));
        for (Encoding e : {Encoding::Srgb, Encoding::Bt1886})
            EXPECT_NEAR(reference().encoded(Rgb(x), e).g, encode(lin.g, e), 1e-4) << "x = " << x;
    }
}

struct Pin {
    const char* fit;
    const char* group;
    Encoding encoding;
    double maxCodes, meanCodes, maxDe, meanDe;
};

// The numbers docs/tradeoffs.md reports (study, 32 steps per stop). Codes may move by one
// (float rounding at a code boundary), the rest by 5 %.
const Pin kPins[] = {
    {"Narkowicz", "", Encoding::Srgb, 255, 33.54, 64.76, 10.65},
    {"Narkowicz", "", Encoding::Bt1886, 255, 34.3, 64.76, 10.65},
    {"Narkowicz", "grey", Encoding::Srgb, 52, 16.45, 20.29, 4.85},
    {"Hill", "", Encoding::Srgb, 25, 0.84, 3.76, 0.57},
    {"Hill", "", Encoding::Bt1886, 34, 0.91, 3.76, 0.57},
    {"Hill", "grey", Encoding::Srgb, 2, 0.41, 0.56, 0.10},
    {"Narkowicz x0.6", "", Encoding::Srgb, 255, 24.91, 64.76, 7.16},
    {"Narkowicz x0.6", "grey", Encoding::Srgb, 15, 4.81, 5.96, 1.39},
    {"Narkowicz x0.6", "skin", Encoding::Srgb, 22, 4.52, 6.11, 1.85},
};

TEST(AcesReference, FitErrorsAreTheDocumentedOnes) {
    const auto all = swatches();
    const auto ramp = exposureRamp(32);
    const auto named = fits();
    for (const Pin& p : kPins) {
        const auto f = std::find_if(named.begin(), named.end(), [&](const NamedFit& n) { return n.name == p.fit; });
        ASSERT_NE(f, named.end()) << p.fit;
        const FitError e = compare(reference(), f->fit, all, p.group, ramp, p.encoding);
        SCOPED_TRACE(std::string(p.fit) + " on '" + p.group + "'");
        EXPECT_NEAR(e.maxCodes, p.maxCodes, 1.0) << "at " << e.worstCodesAt;
        EXPECT_NEAR(e.meanCodes, p.meanCodes, 0.05 * p.meanCodes);
        EXPECT_NEAR(e.maxDe, p.maxDe, 0.05 * p.maxDe) << "at " << e.worstDeAt;
        EXPECT_NEAR(e.meanDe, p.meanDe, 0.05 * p.meanDe);
    }
}

}  // namespace
}  // namespace skygraph::aces
