#include "aces_reference.hpp"
#include "delta_e2000.hpp"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace skygraph::aces {
namespace OCIO = OCIO_NAMESPACE;

namespace {

// The ODT of ACES 1.0's Rec.709 and sRGB 100-nit dim-surround outputs (the ACES OCIO
// configs' "ACES 1.0 - SDR Video" view), ending in display-linear CIE XYZ D65.
constexpr const char* kOutput = "ACES-OUTPUT - ACES2065-1_to_CIE-XYZ-D65 - SDR-VIDEO_1.0";

OCIO::TransformRcPtr builtin(const char* style, bool inverse = false) {
    auto t = OCIO::BuiltinTransform::Create();
    try {
        t->setStyle(style);
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("OpenColorIO ") + OCIO::GetVersion() + " has no built-in transform '" +
                                 style + "': " + e.what());
    }
    t->setDirection(inverse ? OCIO::TRANSFORM_DIR_INVERSE : OCIO::TRANSFORM_DIR_FORWARD);
    return t;
}

// XYZ D65 -> linear Rec.709 from built-ins only: the Bradford D65 -> D60 of the inverse
// AP0 utility and the D60 -> D65 of the AP1 -> Rec.709 utility cancel exactly.
std::vector<OCIO::TransformRcPtr> xyzToLinearRec709() {
    return {builtin("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD", true), builtin("ACEScg_to_ACES2065-1", true),
            builtin("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD")};
}

OCIO::ConstCPUProcessorRcPtr processor(const std::vector<OCIO::TransformRcPtr>& chain) {
    static const OCIO::ConstConfigRcPtr config = OCIO::Config::CreateRaw();
    auto group = OCIO::GroupTransform::Create();
    for (const auto& t : chain) group->appendTransform(t);
    // No optimisation: the reference must be the transforms as defined, not an approximation.
    return config->getProcessor(group)->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_NONE);
}

Rgb process(const OCIO::ConstCPUProcessorRcPtr& p, const Rgb& in) {
    float px[3] = {float(in.r), float(in.g), float(in.b)};
    p->applyRGB(px);
    return {px[0], px[1], px[2]};
}

int code(double v) { return int(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); }

std::string at(const Swatch& s, double m) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s x%.3g", s.name.c_str(), m);
    return buf;
}

}  // namespace

struct Reference::Impl {
    OCIO::ConstCPUProcessorRcPtr toAces, fromAces, linear, srgb, bt1886;
};

Reference::Reference() : impl_(std::make_unique<Impl>()) {
    // Linear Rec.709 -> ACEScg (inverse of the AP1 -> Rec.709 utility) -> ACES2065-1.
    const std::vector<OCIO::TransformRcPtr> in = {builtin("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", true),
                                                  builtin("ACEScg_to_ACES2065-1")};
    auto withOutput = [&](std::vector<OCIO::TransformRcPtr> head, const std::vector<OCIO::TransformRcPtr>& tail) {
        head.push_back(builtin(kOutput));
        head.insert(head.end(), tail.begin(), tail.end());
        return head;
    };
    impl_->toAces = processor(in);
    impl_->fromAces = processor(withOutput({}, xyzToLinearRec709()));
    impl_->linear = processor(withOutput(in, xyzToLinearRec709()));
    impl_->srgb = processor(withOutput(in, {builtin("DISPLAY - CIE-XYZ-D65_to_sRGB")}));
    impl_->bt1886 = processor(withOutput(in, {builtin("DISPLAY - CIE-XYZ-D65_to_REC.1886-REC.709")}));
}

Reference::~Reference() = default;

Rgb Reference::toAces(const Rgb& rec709) const { return process(impl_->toAces, rec709); }
Rgb Reference::displayLinearFromAces(const Rgb& aces) const { return process(impl_->fromAces, aces); }
Rgb Reference::displayLinear(const Rgb& rec709) const { return process(impl_->linear, rec709); }
Rgb Reference::encoded(const Rgb& rec709, Encoding e) const {
    return process(e == Encoding::Srgb ? impl_->srgb : impl_->bt1886, rec709);
}

double encode(double linear, Encoding e) {
    linear = std::clamp(linear, 0.0, 1.0);
    return e == Encoding::Srgb ? math::srgbEncode(linear) : std::pow(linear, 1.0 / 2.4);
}

std::vector<Swatch> swatches() {
    auto checker = [](int r, int g, int b) {
        return Rgb(math::srgbDecode(r / 255.0), math::srgbDecode(g / 255.0), math::srgbDecode(b / 255.0));
    };
    return {{"grey", "grey", Rgb(1.0)},
            {"red", "red", Rgb(1, 0, 0)},
            {"green", "green", Rgb(0, 1, 0)},
            {"blue", "blue", Rgb(0, 0, 1)},
            {"dark skin", "skin", checker(115, 82, 68)},
            {"light skin", "skin", checker(194, 150, 130)},
            {"blue sky", "sky/foliage", checker(98, 122, 157)},
            {"foliage", "sky/foliage", checker(87, 108, 67)}};
}

std::vector<double> exposureRamp(int perStop) {
    std::vector<double> ramp;
    for (int i = -8 * perStop; i <= 8 * perStop; ++i) ramp.push_back(std::exp2(double(i) / perStop));
    return ramp;
}

FitError compare(const Reference& ref, const Fit& fit, const std::vector<Swatch>& all, const std::string& group,
                 const std::vector<double>& ramp, Encoding e) {
    static const bench::DeltaE2000 deltaE;
    FitError r;
    double sumCodes = 0, sumDe = 0;
    size_t n = 0;
    for (const Swatch& s : all) {
        if (!group.empty() && s.group != group) continue;
        for (double m : ramp) {
            const Rgb scene = s.rgb * m;
            const Rgb mine = fit(scene), theirs = ref.encoded(scene, e);
            int a[3], b[3], sa[3], sb[3];
            const Rgb refSrgb = e == Encoding::Srgb ? theirs : ref.encoded(scene, Encoding::Srgb);
            for (int k = 0; k < 3; ++k) {
                a[k] = code(encode(mine[k], e));
                b[k] = code(theirs[k]);
                sa[k] = code(encode(mine[k], Encoding::Srgb));
                sb[k] = code(refSrgb[k]);
                const int d = std::abs(a[k] - b[k]);
                sumCodes += d;
                if (d > r.maxCodes) r.maxCodes = d, r.worstCodesAt = at(s, m);
            }
            const double da[3] = {sa[0] / 255.0, sa[1] / 255.0, sa[2] / 255.0};
            const double db[3] = {sb[0] / 255.0, sb[1] / 255.0, sb[2] / 255.0};
            const double de = deltaE(da, db);
            sumDe += de;
            if (de > r.maxDe) r.maxDe = de, r.worstDeAt = at(s, m);
            ++n;
        }
    }
    if (n == 0) throw std::invalid_argument("no swatch in group '" + group + "'");
    r.meanCodes = sumCodes / double(3 * n);
    r.meanDe = sumDe / double(n);
    return r;
}

std::vector<NamedFit> fits() {
    using math::ToneOperator;
    return {{"Narkowicz", [](const Rgb& c) { return math::tonemap(c, 0.0, ToneOperator::AcesNarkowicz); }},
            {"Hill", [](const Rgb& c) { return math::tonemap(c, 0.0, ToneOperator::AcesHill); }},
            {"Narkowicz x0.6", [](const Rgb& c) { return math::tonemap(c * 0.6, 0.0, ToneOperator::AcesNarkowicz); }}};
}

void printFitTable(const Reference& ref, int perStop) {
    const auto all = swatches();
    const auto ramp = exposureRamp(perStop);
    std::printf("ACES fits vs the reference RRT + ODT (OpenColorIO %s, %s), scene x 2^-8..2^8, %d steps per stop;\n"
                "  codes = |fit - reference| in 8-bit codes, both sides sRGB- or BT.1886-encoded; dE00 on the sRGB codes\n",
                OCIO::GetVersion(), kOutput, perStop);
    std::printf("  %-15s %-12s %9s %9s %9s %9s %7s %7s  %-24s %s\n", "fit", "swatches", "srgb_max", "srgb_mean", "1886_max",
                "1886_mean", "dE_mean", "dE_max", "worst codes (sRGB) at", "worst dE at");
    for (const auto& f : fits())
        for (const std::string group : {"", "grey", "red", "green", "blue", "skin", "sky/foliage"}) {
            const FitError s = compare(ref, f.fit, all, group, ramp, Encoding::Srgb);
            const FitError b = compare(ref, f.fit, all, group, ramp, Encoding::Bt1886);
            std::printf("  %-15s %-12s %9.0f %9.2f %9.0f %9.2f %7.2f %7.2f  %-24s %s\n", f.name.c_str(),
                        group.empty() ? "all" : group.c_str(), s.maxCodes, s.meanCodes, b.maxCodes, b.meanCodes, s.meanDe,
                        s.maxDe, s.worstCodesAt.c_str(), s.worstDeAt.c_str());
        }
}

}  // namespace skygraph::aces
