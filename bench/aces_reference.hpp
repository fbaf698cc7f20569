// The reference ACES 1.0 output transform (RRT + SDR video ODT) for skygraph's linear Rec.709
// scene values, built from OpenColorIO's built-in transforms rather than a hand-written CTL
// port, and the comparison of the two ACES fits of include/skygraph/shading_math.hpp
// against it in 8-bit codes and CIEDE2000 (docs/tradeoffs.md, "Curves in 8-bit codes").
#pragma once

#include <skygraph/shading_math.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace skygraph::aces {

using Rgb = math::Vec3<double>;

/// How display values become 8-bit codes. The fits output display-linear values that
/// skygraph sRGB-encodes, so Srgb (ACES's sRGB output transform: the same RRT + video ODT
/// tone scale, then the piecewise sRGB curve) is the like-for-like comparison. Bt1886 is the
/// Rec.709 ODT's own encoding (pure 2.4 power, black at 0): both sides are encoded with it.
enum class Encoding { Srgb, Bt1886 };

/// OCIO processors for: linear Rec.709 -> ACES2065-1 (through ACEScg, Bradford D65 -> D60),
/// ACES2065-1 -> RRT + ODT "SDR-VIDEO_1.0" -> display CIE XYZ D65 -> linear Rec.709 or an
/// encoded display. Every step is an OCIO built-in; none of the math is written here.
class Reference {
public:
    Reference();  ///< throws std::runtime_error naming the built-in OCIO lacks
    ~Reference();
    Reference(const Reference&) = delete;
    Reference& operator=(const Reference&) = delete;

    /// Linear Rec.709 (D65) scene value -> ACES2065-1 (AP0, D60).
    Rgb toAces(const Rgb& rec709) const;
    /// ACES2065-1 -> display-linear Rec.709, unclamped (the ODT leaves out-of-gamut values).
    Rgb displayLinearFromAces(const Rgb& aces) const;
    /// Linear Rec.709 scene value -> display-linear Rec.709, unclamped.
    Rgb displayLinear(const Rgb& rec709) const;
    /// Linear Rec.709 scene value -> encoded display value, OCIO's display transform
    /// ("DISPLAY - CIE-XYZ-D65_to_sRGB" or "..._to_REC.1886-REC.709"), unclamped.
    Rgb encoded(const Rgb& rec709, Encoding e) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// skygraph's own encode of a fit's display-linear output: the same curve OCIO's display
/// transform applies (sRGB piecewise, or the 2.4 power of BT.1886 with black at 0).
double encode(double linear, Encoding e);

/// A named scene colour (linear Rec.709) swept over the exposure ramp.
struct Swatch {
    std::string name, group;
    Rgb rgb;
};
/// Grey; pure R, G, B; ColorChecker dark skin, light skin, blue sky, foliage (the published
/// sRGB values of the 2005 chart, decoded to linear).
std::vector<Swatch> swatches();

/// Scene multipliers 2^-8 .. 2^8 (the study's grey ramp), `perStop` steps per stop.
std::vector<double> exposureRamp(int perStop);

using Fit = std::function<Rgb(const Rgb&)>;

struct FitError {
    double maxCodes = 0, meanCodes = 0;  ///< |fit - reference| in 8-bit codes, over channels and samples
    double maxDe = 0, meanDe = 0;        ///< CIEDE2000 of the 8-bit sRGB display colours
    std::string worstCodesAt, worstDeAt;  ///< "swatch x=..." of the worst sample
};

/// One fit against the reference over every swatch of `group` ("" for all) times `ramp`.
/// Reference values are clamped to [0, 1] before quantising, as the CTL ODT clamps and any
/// 8-bit output must; codes are round(255 v).
FitError compare(const Reference& ref, const Fit& fit, const std::vector<Swatch>& swatches, const std::string& group,
                 const std::vector<double>& ramp, Encoding e);

/// The fits as skygraph ships them (tonemap() at 0 EV), plus Narkowicz with its author's
/// 0.6 pre-exposure ("for the original ACES curve multiply input by 0.6"), for comparison.
struct NamedFit {
    std::string name;
    Fit fit;
};
std::vector<NamedFit> fits();

/// The table study prints: each fit x swatch group x encoding.
void printFitTable(const Reference& ref, int perStop);

}  // namespace skygraph::aces
