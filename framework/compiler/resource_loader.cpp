#include "resource_loader.hpp"

#include "graph_limits.hpp"
#include "json_path.hpp"
#include "printable_name.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <string>

namespace skygraph {
namespace {

constexpr Keys<13> kResourceKeys{"type",     "format",   "extent",  "mips",        "layers", "size",   "clear",
                                 "external", "initial", "final",   "description", "alias",  "sharing"};
constexpr Keys<3> kClearKeys{"color", "depth", "stencil"};
using ResourceFields = JsonFields<kResourceKeys.size()>;

namespace key {
constexpr size_t type = keyIndex(kResourceKeys, "type"), format = keyIndex(kResourceKeys, "format"),
                 extent = keyIndex(kResourceKeys, "extent"), mips = keyIndex(kResourceKeys, "mips"),
                 layers = keyIndex(kResourceKeys, "layers"), size = keyIndex(kResourceKeys, "size"),
                 clear = keyIndex(kResourceKeys, "clear"), external = keyIndex(kResourceKeys, "external"),
                 initial = keyIndex(kResourceKeys, "initial"), final = keyIndex(kResourceKeys, "final"),
                 alias = keyIndex(kResourceKeys, "alias"), sharing = keyIndex(kResourceKeys, "sharing"),
                 description = keyIndex(kResourceKeys, "description"),
                 color = keyIndex(kClearKeys, "color"), depth = keyIndex(kClearKeys, "depth"),
                 stencil = keyIndex(kClearKeys, "stencil");
}  // namespace key

template <typename T, size_t N>
const T* lookup(const std::array<std::pair<std::string_view, T>, N>& table, std::string_view name) {
    for (const auto& [n, value] : table)
        if (n == name) return &value;
    return nullptr;
}

constexpr std::array<std::pair<std::string_view, ResourceType>, 4> kResourceTypes{{
    {"buffer", ResourceType::Buffer}, {"cube", ResourceType::Cube}, {"image2d", ResourceType::Image2D},
    {"image2d_array", ResourceType::Image2DArray}}};
constexpr std::array<std::pair<std::string_view, ExternalState>, 4> kExternalStates{{
    {"General", ExternalState::General}, {"Present", ExternalState::Present},
    {"ShaderRead", ExternalState::ShaderRead}, {"TransferSrc", ExternalState::TransferSrc}}};

/// Reports a problem of resource `name` at `sub` (a key path under the resource; empty: the
/// resource itself).
class ResourceProblems {
public:
    ResourceProblems(std::string_view name, FileProblems& report) : name_(name), report_(report) {}
    [[nodiscard]] std::string path() const { return jsonPathMember("resources", name_); }
    void operator()(std::string_view sub, const std::string& message) const {
        report_(sub.empty() ? path() : path() + "." + std::string(sub), "", name_, message);
    }
    [[nodiscard]] FileProblems& file() const { return report_; }

private:
    std::string_view name_;
    FileProblems& report_;
};

void loadImageShape(ResourceDesc& r, const ResourceFields& f, const ResourceProblems& fail) {
    if (f[key::size]) fail("size", "images have an extent, not a size");
    const JsonValue format = f[key::format];
    if (!format || !format.isString()) {
        fail("format", "missing; a VkFormat name without VK_FORMAT_, e.g. R16G16B16A16_SFLOAT");
    } else if (auto found = findFormat(format.string())) {
        r.format = *found;
    } else {
        std::string known;
        for (const auto& k : knownFormats()) known += (known.empty() ? "" : ", ") + std::string(k.name);
        fail("format", "unknown format '" + std::string(format.string()) + "'; known: " + known);
    }
    const JsonValue extent = f[key::extent];
    if (!extent) {
        fail("extent", "missing; \"output\", \"output/N\" or [width, height]");
    } else if (extent.isString()) {
        const std::string_view s = extent.string();
        if (s == "output") {
            r.extent.divisor = 1;
        } else if (s.starts_with("output/") && s.size() > 7 &&
                   s.find_first_not_of("0123456789", 7) == std::string::npos && s.size() < 13) {
            r.extent.divisor = static_cast<uint32_t>(std::stoul(std::string(s.substr(7))));
            if (r.extent.divisor == 0 || r.extent.divisor > kMaxDivisor)
                fail("extent", "divisor must be between 1 and " + std::to_string(kMaxDivisor));
        } else {
            fail("extent", "expected \"output\", \"output/N\" or [width, height], got \"" + std::string(s) + "\"");
        }
        if (r.type == ResourceType::Cube)
            fail("extent", "cube faces must be square, which an output-relative extent is not "
                           "in general; give a fixed [n, n]");
    } else if (extent.isArray() && extent.size() == 2 && extent[0].isInteger() && extent[1].isInteger()) {
        const auto w = extent[0].number<int64_t>(), h = extent[1].number<int64_t>();
        if (w < 1 || h < 1 || w > kMaxImageExtent || h > kMaxImageExtent)
            // As written: a number past int64_t (18446744073709551615) would print as -1.
            fail("extent", "[" + extent[0].dump() + ", " + extent[1].dump() + "] is outside 1.." +
                               std::to_string(kMaxImageExtent));
        r.extent.relativeToOutput = false;
        r.extent.width = static_cast<uint32_t>(std::clamp<int64_t>(w, 1, kMaxImageExtent));
        r.extent.height = static_cast<uint32_t>(std::clamp<int64_t>(h, 1, kMaxImageExtent));
        if (r.type == ResourceType::Cube && w != h) fail("extent", "cube faces must be square");
    } else {
        fail("extent", "expected \"output\", \"output/N\" or [width, height], got " + extent.dump() +
                           extent.integersHint(1, kMaxImageExtent));
    }
    if (const JsonValue mips = f[key::mips]) {
        const auto maxMips = static_cast<uint32_t>(std::bit_width(kMaxImageExtent));
        if (mips.isString() && mips.string() == "full") {
            r.mips = 0;
        } else if (!mips.isInteger() || mips.number<int64_t>() < 1 || mips.number<int64_t>() > maxMips) {
            fail("mips", "expected \"full\" or a count between 1 and " + std::to_string(maxMips) + ", got " +
                             mips.dump() + mips.integerHint(1, maxMips));
        } else {
            r.mips = mips.number<uint32_t>();
            if (!r.extent.relativeToOutput &&
                r.mips > static_cast<uint32_t>(std::bit_width(std::max(r.extent.width, r.extent.height))))
                fail("mips", std::to_string(r.mips) + " levels is more than a " + std::to_string(r.extent.width) +
                                 "x" + std::to_string(r.extent.height) + " image has");
        }
    }
    r.layers = r.type == ResourceType::Cube ? 6 : 1;
    if (const JsonValue layers = f[key::layers]) {
        if (!layers.isInteger() || layers.number<int64_t>() < 1 || layers.number<int64_t>() > kMaxLayers) {
            fail("layers", "expected a count between 1 and " + std::to_string(kMaxLayers) + ", got " + layers.dump() +
                               layers.integerHint(1, kMaxLayers));
        } else {
            r.layers = layers.number<uint32_t>();
            if (r.type == ResourceType::Cube && r.layers != 6) fail("layers", "a cube has 6 layers");
            if (r.type == ResourceType::Image2D && r.layers != 1)
                fail("layers", "an image2d has 1 layer; use image2d_array");
        }
    }
}

/// What a depth/stencil format's clear holds, for advice: its aspects' keys.
std::string depthStencilClear(const FormatInfo& f) {
    if (f.hasDepth && f.hasStencil) return "{\"depth\": d, \"stencil\": s}";
    return f.hasStencil ? "{\"stencil\": s}" : "{\"depth\": d}";
}

void loadClear(ResourceDesc& r, JsonValue clear, const ResourceProblems& fail) {
    if (!clear) return;
    ClearValue c;
    // The advice fits the format where it is known.
    const std::string expected = !r.format.isDepthStencil() ? "expected {\"color\": [r, g, b, a]}"
                                 : r.format.hasDepth         ? "expected " + depthStencilClear(r.format)
                                                             : "expected {\"stencil\": s}";
    const std::string either = r.format.format == VK_FORMAT_UNDEFINED
                                   ? "expected {\"color\": [r, g, b, a]} or {\"depth\": d}"
                                   : expected + " for the format " + std::string(r.format.name);
    if (!clear.isObject()) {
        fail("clear", either);
        return;
    }
    const auto f = fieldsOf(clear, kClearKeys);
    fail.file().unknownKeys(clear, f, [&] { return r.jsonPath() + ".clear"; }, kClearKeys, "", r.name);
    if (!r.isImage()) fail("clear", "buffers cannot be cleared by the graph");
    if (f[key::color] && (f[key::depth] || f[key::stencil]))
        fail("clear", "expected {\"color\": [r, g, b, a]} or {\"depth\": d, \"stencil\": s}, not both");
    if (const JsonValue color = f[key::color]) {
        bool numbers = color.isArray() && color.size() == 4;
        for (size_t i = 0; numbers && i < 4; ++i) numbers = color[i].isNumber();
        // Empty while the format is unknown or a depth format's, which are named on their own.
        const format_table::ClearColorRange range = format_table::clearColorRange(r.format.format);
        bool fits = numbers;
        for (size_t i = 0; fits && i < 4; ++i) {
            const double v = color[i].number<double>();
            fits = range.holds(v, color[i].isInteger());
        }
        if (range.integers && !fits)
            fail("clear.color", "expected four integers in " + clearRangeText(range) + " for the integer format " +
                                    std::string(r.format.name) + ", got " + color.dump() +
                                    color.integersHint(range.lowest, range.highest));
        else if (!numbers)
            fail("clear.color", "expected four numbers");
        else if (!range.empty() && !fits)
            fail("clear.color", "expected four numbers in " + clearRangeText(range) + ", the range of the format " +
                                    std::string(r.format.name) + " (" + std::string(kClearOutsideRange) + "), got " +
                                    color.dump());
        else
            for (size_t i = 0; i < 4; ++i) c.color[i] = color[i].number<float>();
        if (r.format.isDepthStencil())
            fail("clear.color", "the depth/stencil format " + std::string(r.format.name) + " needs " +
                                    depthStencilClear(r.format));
    } else if (f[key::depth] || f[key::stencil]) {
        c.isDepth = true;
        if (const JsonValue depth = f[key::depth]) {
            if (r.format.isDepthStencil() && !r.format.hasDepth)
                fail("clear.depth", "format " + std::string(r.format.name) + " has no depth aspect");
            else if (!depth.isNumber() || depth.number<double>() < 0.0 || depth.number<double>() > 1.0)
                fail("clear.depth", "expected a number in [0, 1], got " + depth.dump());
            else
                c.depth = depth.number<float>();
        }
        if (const JsonValue st = f[key::stencil]) {
            if (r.format.isDepthStencil() && !r.format.hasStencil)
                fail("clear.stencil", "format " + std::string(r.format.name) + " has no stencil aspect");
            else if (!st.isUnsigned() || st.number<uint64_t>() > 255)
                fail("clear.stencil", "expected an integer in [0, 255], got " + st.dump() + st.integerHint(0, 255));
            else
                c.stencil = st.number<uint32_t>();
        }
        if (r.isImage() && r.format.format != VK_FORMAT_UNDEFINED && !r.format.isDepthStencil())
            fail("clear", "a color format needs {\"color\": [r, g, b, a]}");
    } else {
        fail("clear", either);
    }
    r.clear = c;
}

void loadExternal(ResourceDesc& r, const ResourceFields& f, const ResourceProblems& fail) {
    auto state = [&](size_t k) {
        const std::string_view name = kResourceKeys[k];
        const JsonValue value = f[k];
        if (!value) return ExternalState::None;
        const ExternalState* s = value.isString() ? lookup(kExternalStates, value.string()) : nullptr;
        if (!s) {
            fail(name, "expected one of Present, TransferSrc, ShaderRead, General");
            return ExternalState::None;
        }
        if (!r.isImage() && (*s == ExternalState::Present || *s == ExternalState::TransferSrc))
            fail(name, "a buffer cannot be in state " + std::string(value.string()));
        return *s;
    };
    if (const JsonValue ext = f[key::external]) {
        if (!ext.isBoolean()) fail("external", "expected true or false");
        else r.external = ext.boolean();
    }
    r.final = state(key::final);
    r.initial = state(key::initial);
    if (r.initial != ExternalState::None && !r.external) fail("initial", "only external resources arrive in a state");
    // Only the embedder can hand an image to the presentation engine: the graph's own have no swapchain.
    if (r.final == ExternalState::Present && !r.external)
        fail("final", "only an external image (the swapchain's) can be presented; add \"external\": true");
    else if (r.final == ExternalState::Present && r.isImage() && r.format.format != VK_FORMAT_UNDEFINED && !presentable(r))
        fail("final", unpresentableShape(r));
    // An external resource that persists comes back in the state it was left in.
    if (r.external && r.initial == ExternalState::None)
        r.initial = r.final != ExternalState::None ? r.final : ExternalState::ShaderRead;
    else if (handedBackChanged(r, ExternalState::Present))  // a file is as written
        fail("initial", handedBackProblem(r));
    if (r.external && r.clear) fail("clear", "an external resource arrives with contents; it is not cleared");
    if (const JsonValue alias = f[key::alias]) {
        if (!alias.isBoolean()) fail("alias", "expected true or false");
        else r.alias = alias.boolean();
        if (r.external)
            fail("alias", "an external resource has memory of its own; only transient resources share memory");
    }
    if (const JsonValue text = f[key::description]; text && !text.isString())
        fail("description", "expected a string, got " + text.dump());
    if (const JsonValue sharing = f[key::sharing]) {
        const auto mode = sharing.isString() ? parseSharing(sharing.string()) : std::nullopt;
        if (mode) r.sharing = *mode;
        else fail("sharing", "expected \"auto\", \"exclusive\" or \"concurrent\", got " + sharing.dump());
    }
}

}  // namespace

void loadResource(std::string_view name, JsonValue v, FileProblems& report, ResourceDesc& r) {
    r.name = name;
    const ResourceProblems fail(name, report);
    if (name.empty()) fail("", "a resource needs a name: plans and passes refer to it by its key");
    if (const std::string why = unprintableNameProblem(name); !why.empty()) fail("", "its name " + why);
    if (!v.isObject()) {
        fail("", "must be an object");
        return;
    }
    const auto f = fieldsOf(v, kResourceKeys);
    report.unknownKeys(v, f, [&] { return fail.path(); }, kResourceKeys, "", name);
    const JsonValue type = f[key::type];
    const ResourceType* known = type && type.isString() ? lookup(kResourceTypes, type.string()) : nullptr;
    if (!known) {
        fail("type", "expected one of image2d, cube, image2d_array, buffer" +
                         (!type ? std::string(" (missing)") : ", got " + type.dump()));
        return;
    }
    r.type = *known;
    if (r.isImage()) {
        loadImageShape(r, f, fail);
    } else {
        for (const size_t k : {key::format, key::extent, key::mips, key::layers})
            if (f[k]) fail(kResourceKeys[k], "buffers have no " + std::string(kResourceKeys[k]));
        const JsonValue size = f[key::size];
        if (!size)
            fail("size", "missing; buffers need a size in bytes between 1 and 2 GiB");
        else if (!size.isUnsigned() || size.number<uint64_t>() == 0 || size.number<uint64_t>() > kMaxBufferBytes)
            fail("size", "buffers need a size in bytes between 1 and 2 GiB, got " + size.dump() +
                               size.integerHint(1, double(kMaxBufferBytes)));
        else
            r.sizeBytes = size.number<uint64_t>();
    }
    loadClear(r, f[key::clear], fail);
    loadExternal(r, f, fail);
}

}  // namespace skygraph
