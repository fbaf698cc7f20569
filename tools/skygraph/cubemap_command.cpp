#include "cubemap_command.hpp"

#include "builtin_ibl_graph.hpp"
#include "progress_bar.hpp"
#include "replace_file.hpp"

#include "app/environment_bake.hpp"
#include "app/output_file_name.hpp"
#include "file_extension.hpp"
#include "printable_name.hpp"
#include "shipped_names.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/ktx2.hpp>
#include <skygraph/shading_math.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string_view>
#include <system_error>

namespace skygraph::cli {
namespace {

using app::BakeOptions;
using app::BakeResult;
using namespace shipped;

struct CubemapArgs {
    std::string input, output, cross, format = "rgba16f", device;
    std::vector<std::string> products{"irradiance", "prefiltered", "brdf"};
    BakeOptions bake;
};

/// OUT.ktx2 -> OUT.<product>.ktx2
std::filesystem::path productPath(const std::filesystem::path& output, const std::string& product) {
    std::filesystem::path p = output;
    return p.replace_extension().string() + "." + product + ".ktx2";
}

/// levels[mip * faces + face] -> a KTX2 texture.
Ktx2Texture toKtx2(const std::vector<ImageData>& levels, size_t faces, Ktx2Format format) {
    Ktx2Texture t;
    t.format = format;
    for (size_t i = 0; i < levels.size(); i += faces) {
        t.levels.emplace_back();
        for (size_t f = 0; f < faces; ++f) t.levels.back().push_back(toHdrImage(levels[i + f]));
    }
    return t;
}

/// The six mip-0 faces as a horizontal cross (+Y above, -X +Z +X -Z across, -Y below), each
/// face as stored, so neighbouring faces meet along shared edges.
HdrImage crossLayout(const std::vector<ImageData>& faces) {
    const uint32_t n = faces[0].width;
    HdrImage cross;
    cross.width = 4 * n;
    cross.height = 3 * n;
    cross.rgba.assign(size_t(cross.width) * cross.height * 4, 0.0f);
    const uint32_t cell[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};  // +X,-X,+Y,-Y,+Z,-Z
    for (int f = 0; f < 6; ++f)
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const float* src = &faces[size_t(f)].rgba[(size_t(y) * n + x) * 4];
                float* dst = &cross.rgba[((size_t(cell[f][1] * n + y)) * cross.width + cell[f][0] * n + x) * 4];
                std::copy(src, src + 4, dst);
            }
    return cross;
}

/// A failed write (from files::) as the ImageError of its output, which path1() names.
ImageError cannotWrite(const std::filesystem::filesystem_error& e) {
    return ImageError(e.path1(), "cannot write: " + files::whyNotWritten(e));
}

/// Throws ImageError naming `path` unless it can be written: files::writableOutputTarget, a
/// file in an existing folder (a link's target's) or a stream, not a folder. Checked before
/// the bake, so that a mistyped path costs no work.
void requireWritableOutput(const std::filesystem::path& path) {
    try {
        (void)files::writableOutputTarget(path);
    } catch (const std::filesystem::filesystem_error& e) {
        throw cannotWrite(e);
    }
}

int run(CubemapArgs& args) {
    const auto start = std::chrono::steady_clock::now();
    const std::filesystem::path output = args.output;
    // As `render` does with its output: any case, and a wrong one is a problem with the input.
    if (fileNameIsOnlyExtension(output, ".ktx2"))
        throw std::runtime_error(app::noStemMessage("-o", output, "sky"));
    if (lowercaseExtension(output) != ".ktx2") throw ImageError(output, "cannot write: its extension must be .ktx2");
    for (const std::string_view extension : {".hdr", ".exr"})
        if (fileNameIsOnlyExtension(args.cross, extension))
            throw std::runtime_error(app::noStemMessage("--cross", args.cross, "cross"));
    if (!args.cross.empty() && lowercaseExtension(args.cross) != ".hdr" && lowercaseExtension(args.cross) != ".exr")
        throw ImageError(args.cross, "cannot write --cross: its extension must be .hdr or .exr");
    if (args.bake.size & (args.bake.size - 1)) throw UsageError("--size must be a power of two");
    if (args.bake.prefilteredSize & (args.bake.prefilteredSize - 1))
        throw UsageError("--prefiltered-size must be a power of two");
    BakeOptions bake = args.bake;
    bake.graphText = kIblGraph;
    bake.float32 = args.format == "rgba32f";
    bake.products.clear();
    for (const auto& p : args.products) bake.products.push_back(p == "brdf" ? std::string(kBrdfLut) : p);

    // A product named twice is one output.
    for (auto it = args.products.begin(); it != args.products.end();)
        it = std::find(args.products.begin(), it, *it) != it ? args.products.erase(it) : it + 1;
    // Every output is checked before the bake and written after it, all or none.
    std::vector<std::filesystem::path> outputs{output};
    for (const auto& p : args.products) outputs.push_back(productPath(output, p));
    if (!args.cross.empty()) outputs.emplace_back(args.cross);
    for (const auto& path : outputs) {
        refuseToOverwriteInputs(path == output ? "-o" : "an output", path, {args.input});
        requireWritableOutput(path);
    }
    // Through a link or another name: the later file would replace the earlier.
    if (const auto two = files::twoNamesOfOneFile(outputs))
        throw ImageError(outputs[two->second], "cannot write: it is the same file as '" +
                                                   printableName(outputs[two->first].string()) +
                                                   "', another output of this bake");

    ProgressBar bar("cubemap", 6, "steps");
    // Half-float products would hold what a half cannot as infinity, and spread it through
    // every mip and filtered product. An .exr --cross is half floats even from an rgba32f
    // bake: the EXR writer clamps what it writes, so rgba32f keeps a float's range here.
    const HdrImage equirect = app::loadEnvironmentImage(
        args.input, bake.float32 ? std::numeric_limits<float>::max() : math::kLargestHalf);
    bar.advance();
    bake.onStep = [&](const std::string&) { bar.advance(); };
    const BakeResult result = [&] {
        try {
            return app::bakeAndReadBack(equirect, bake);
        } catch (const DeviceCapacityError& e) {  // named by what sets the resource's size
            if (e.resource() == kEquirect)
                throw ImageError(args.input, std::to_string(equirect.width) + "x" + std::to_string(equirect.height) +
                                                 " is too large for this device to bake: " + e.what());
            if (e.resource() == kEnvironment) throw UsageError("--size " + std::to_string(bake.size) + ": " + e.what());
            if (e.resource() == kPrefiltered)
                throw UsageError((bake.prefilteredSize ? "--prefiltered-size " + std::to_string(bake.prefilteredSize)
                                                       : "--size " + std::to_string(bake.size)) +
                                 ": " + e.what());
            throw;
        }
    }();
    if (args.bake.validate && result.validationMessages != 0)
        throw std::runtime_error(std::to_string(result.validationMessages) + " validation messages (see the log)");

    for (const PassTiming& t : result.passTimings) spdlog::debug("  {:<18} {:8.1f} ms", t.pass, t.milliseconds);
    const Ktx2Format colour = bake.float32 ? Ktx2Format::Rgba32Float : Ktx2Format::Rgba16Float;
    // Each output's file, encoded when it is written: one file's bytes are held at a time.
    std::vector<std::function<std::string()>> encode;  // parallel to outputs
    encode.push_back([&] { return encodeKtx2(output, toKtx2(result.products.at(std::string(kEnvironment)), 6, colour)); });
    for (size_t i = 0; i < args.products.size(); ++i)
        encode.push_back([&, i] {
            const std::string& p = args.products[i];
            const std::string resource = p == "brdf" ? std::string(kBrdfLut) : p;
            const bool table = resource == kBrdfLut;
            const Ktx2Format format = table ? (bake.float32 ? Ktx2Format::Rg32Float : Ktx2Format::Rg16Float) : colour;
            return encodeKtx2(outputs[i + 1], toKtx2(result.products.at(resource), table ? 1 : 6, format));
        });
    if (!args.cross.empty())
        encode.push_back([&] {
            const auto& env = result.products.at(std::string(kEnvironment));
            return encodeHdrImage(outputs.back(), crossLayout({env.begin(), env.begin() + 6}));
        });
    // All or none: a failure leaves every output as it was (files::replaceFilesContents).
    try {
        files::replaceFilesContents(outputs, [&](size_t i) { return encode[i](); });
    } catch (const std::filesystem::filesystem_error& e) {
        throw cannotWrite(e);
    }
    bar.advance();
    bar.finish();
    const double totalMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    spdlog::info("wrote '{}' ({}^2 cube, {} products): {:.0f} ms in all, of which setup {:.0f} ms, passes {:.0f} ms",
                 printableName(output.string()), bake.size, args.products.size(), totalMs, result.setupMs, result.gpuMs);
    return kExitOk;
}

}  // namespace

Command addCubemapCommand(CLI::App& parent) {
    auto args = std::make_shared<CubemapArgs>();
    CLI::App* cmd = parent.add_subcommand(
        "cubemap", "Equirect HDR -> KTX2 cube with mips, plus IBL products (OUT.irradiance.ktx2, "
                   "OUT.prefiltered.ktx2: one GGX roughness per mip, OUT.brdf.ktx2)");
    cmd->add_option("input", args->input, "Equirectangular .hdr or .exr")->required()->check(kNotEmpty);
    cmd->add_option("-o,--output", args->output, "Output .ktx2 (the environment cube)")->required()->check(kNotEmpty);
    cmd->add_option("--size", args->bake.size, "Environment cube face size (power of two)")
        ->check(CLI::Range(32u, 4096u))->capture_default_str();
    cmd->add_option("--prefiltered-size", args->bake.prefilteredSize,
                    "Prefiltered cube face size, 6 levels of roughness 0, 0.2 .. 1 (default: max(size/2, 32))")
        ->check(CLI::Range(32u, 4096u));
    cmd->add_option("--samples", args->bake.samples, "Samples per texel for irradiance and prefilter")
        ->check(CLI::Range(1u, 1u << 16))->capture_default_str();
    cmd->add_option("--supersample", args->bake.supersample, "N: NxN equirect taps per cube texel")
        ->check(CLI::Range(1u, 16u))->capture_default_str();
    cmd->add_option("--products", args->products, "Products besides the cube: irradiance, prefiltered, brdf; "
                                                  "'none' for the cube alone")
        ->delimiter(',')->check(CLI::IsMember({"irradiance", "prefiltered", "brdf", "none"}))->capture_default_str();
    cmd->add_option("--format", args->format, "Texel format")->check(CLI::IsMember({"rgba16f", "rgba32f"}))
        ->capture_default_str();
    cmd->add_option("--cross", args->cross, "Also write mip 0 as a horizontal cross (.hdr or .exr)")->check(kNotEmpty);
    cmd->add_option("--device", args->bake.device, "Vulkan device: index or name substring")->check(kNotEmpty);
    cmd->add_flag("--validate", args->bake.validate, "Validation + synchronization validation; fail on any message");
    return {cmd, [args] {
                const bool none = std::erase(args->products, std::string("none")) > 0;
                if (none && !args->products.empty())
                    throw UsageError("--products: 'none' is the cube alone; it cannot be given with other products");
                return run(*args);
            }};
}

}  // namespace skygraph::cli
