// The plan's transient memory as a picture (planMemoryToSvg), drawn the way the memory views of
// AMD's Render Pipeline Shaders and Frostbite's frame graph draw it: plan steps across, byte
// offsets down, heaps stacked, one rectangle per placed resource over its lifetime. Resources
// that share memory sit in the same rows at different times.
#include <skygraph/plan_format.hpp>

#include "byte_text.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {
namespace {

// Layout, in SVG user units (pixels).
constexpr double kColumn = 28;          // one plan step
constexpr double kLeft = 100;           // offset ticks
constexpr double kRight = 130;          // the peak line's label
constexpr double kTop = 70;             // title and legend
constexpr double kHeapGap = 24;         // each heap's label, above it
constexpr double kPlotHeight = 480;     // every heap at one scale...
constexpr double kMinHeapHeight = 40;   // ...except that a small heap stays readable
constexpr double kMinWidth = 720;       // room for the title when there are few passes
constexpr double kMinTick = 36;         // offset ticks at least this far apart
constexpr double kCharWidth = 5.9;      // Helvetica at 11 px on average: whether a label fits
constexpr double kLineHeight = 13;
constexpr size_t kMaxPassLabel = 28;    // longer pass names are cut, the whole name in a tooltip

/// Locale-independent, so the same plan draws the same bytes everywhere.
std::string fixed(double v, int decimals) {
    std::array<char, 64> text{};
    const auto [end, ec] = std::to_chars(text.data(), text.data() + text.size(), v, std::chars_format::fixed, decimals);
    return ec == std::errc() ? std::string(text.data(), end) : "0";
}

/// Coordinates: one decimal, without a trailing ".0".
std::string num(double v) {
    std::string s = fixed(v, 1);
    if (s.ends_with(".0")) s.resize(s.size() - 2);
    return s == "-0" ? "0" : s;
}

/// Offset ticks are powers of two: "4 MiB", "512 KiB".
std::string tickText(uint64_t bytes) {
    if (bytes == 0) return "0";
    if (bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
    if (bytes % 1024 == 0) return std::to_string(bytes >> 10) + " KiB";
    return std::to_string(bytes) + " B";
}

/// Text and attribute values. Control characters, which XML 1.0 cannot hold, become '?'.
std::string xml(std::string_view s) {
    std::string out;
    for (const char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default:
                out += static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' ? '?' : c;
        }
    }
    return out;
}

/// Cuts `s` to `max` characters (a UTF-8 sequence counts as one), the last an ellipsis.
std::string shortened(std::string_view s, size_t max) {
    std::vector<size_t> starts;  // where each character begins
    for (size_t i = 0; i < s.size(); ++i)
        if ((static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) starts.push_back(i);
    if (starts.size() <= max || max == 0) return std::string(s);
    return std::string(s.substr(0, starts[max - 1])) + "\xE2\x80\xA6";
}

/// What the rectangles' colours tell apart, read from how the plan uses each resource.
enum class Kind : uint8_t { DepthImage, ColorImage, ShaderImage, Buffer };
struct KindStyle {
    const char* name;
    const char* fill;
    const char* stroke;
};
constexpr std::array<KindStyle, 4> kKinds{{
    {"depth/stencil attachment", "#9dc3e6", "#2f5f8f"},
    {"color attachment", "#f4b183", "#a0522d"},
    {"image (shaders, transfers)", "#b5d99c", "#4d7a2f"},
    {"buffer", "#cdb4e0", "#6a4a8a"},
}};

std::vector<Kind> resourceKinds(const Plan& plan) {
    std::vector<bool> image(plan.resources().size()), depth(image), color(image);
    for (const PlannedPass& p : plan.passes())
        for (const PlannedUsage& u : p.usages) {
            image[u.resource] = image[u.resource] || u.layout != VK_IMAGE_LAYOUT_UNDEFINED;  // buffers have none
            depth[u.resource] = depth[u.resource] || u.usage.stage == Stage::DepthAttachment;
            color[u.resource] = color[u.resource] || u.usage.stage == Stage::ColorAttachment;
        }
    std::vector<Kind> kinds(image.size());
    for (size_t r = 0; r < kinds.size(); ++r)
        kinds[r] = !image[r] ? Kind::Buffer : depth[r] ? Kind::DepthImage : color[r] ? Kind::ColorImage : Kind::ShaderImage;
    return kinds;
}

/// Where each heap is drawn: one scale for all, so sizes compare across heaps, except that a
/// heap too small to see gets kMinHeapHeight.
struct HeapBand {
    double top = 0, height = 0, pixelsPerByte = 0;
};

std::vector<HeapBand> heapBands(const MemoryLayout& m) {
    const double total = static_cast<double>(std::max<uint64_t>(m.heapBytes(), 1));
    std::vector<HeapBand> bands;
    double y = kTop;
    for (const MemoryHeap& h : m.heaps) {
        HeapBand b;
        b.top = y + kHeapGap;
        b.height = std::max(kMinHeapHeight, kPlotHeight * static_cast<double>(h.bytes) / total);
        b.pixelsPerByte = h.bytes ? b.height / static_cast<double>(h.bytes) : 0;
        bands.push_back(b);
        y = b.top + b.height;
    }
    return bands;
}

/// The y of a byte count taken through the heaps one after another: where the peak line goes.
double stackedY(const MemoryLayout& m, const std::vector<HeapBand>& bands, uint64_t bytes) {
    for (size_t h = 0; h < bands.size(); ++h) {
        if (bytes <= m.heaps[h].bytes || h + 1 == bands.size())
            return bands[h].top + std::min(bands[h].height, static_cast<double>(bytes) * bands[h].pixelsPerByte);
        bytes -= m.heaps[h].bytes;
    }
    return kTop + kHeapGap;
}

class SvgWriter {
public:
    explicit SvgWriter(const Plan& plan)
        : plan_(plan), m_(plan.memory()), bands_(heapBands(m_)), kinds_(resourceKinds(plan)) {
        columns_ = std::max<size_t>(plan.passes().size(), 1);
        width_ = std::max(kMinWidth, kLeft + static_cast<double>(columns_) * kColumn + kRight);
        plotBottom_ = bands_.empty() ? kTop + kHeapGap + kMinHeapHeight : bands_.back().top + bands_.back().height;
        size_t longest = 0;
        for (const PlannedPass& p : plan.passes()) longest = std::max(longest, std::min(p.name.size(), kMaxPassLabel));
        height_ = plotBottom_ + 16 + static_cast<double>(longest) * kCharWidth + 12;
    }

    std::string draw() {
        o_ << R"(<?xml version="1.0" encoding="UTF-8"?>)" << "\n"
           << R"(<svg xmlns="http://www.w3.org/2000/svg" width=")" << num(width_) << R"(" height=")" << num(height_)
           << R"(" viewBox="0 0 )" << num(width_) << " " << num(height_)
           << R"(" font-family="Helvetica, Arial, sans-serif" font-size="11">)" << "\n"
           << R"(<rect class="background" x="0" y="0" width=")" << num(width_) << R"(" height=")" << num(height_)
           << R"(" fill="#ffffff"/>)" << "\n";
        title();
        legend();
        for (size_t h = 0; h < bands_.size(); ++h) heap(h);
        if (bands_.empty())
            o_ << R"(<text x=")" << num(kLeft) << R"(" y=")" << num(kTop + kHeapGap + kMinHeapHeight / 2)
               << R"(" fill="#666666">no transient resources: nothing to place</text>)" << "\n";
        for (const MemoryPlacement& p : m_.placements) placement(p);
        peakLine();
        passLabels();
        o_ << "</svg>\n";
        return o_.str();
    }

private:
    [[nodiscard]] double columnX(size_t pass) const { return kLeft + static_cast<double>(pass) * kColumn; }
    [[nodiscard]] double plotRight() const { return columnX(columns_); }

    void text(double x, double y, std::string_view s, std::string_view attributes = {}) {
        o_ << R"(<text x=")" << num(x) << R"(" y=")" << num(y) << '"';
        if (!attributes.empty()) o_ << ' ' << attributes;
        o_ << '>' << xml(s) << "</text>\n";
    }

    void title() {
        std::string line = plan_.graph() + ": transient memory, " + std::to_string(plan_.outputWidth()) + "x" +
                           std::to_string(plan_.outputHeight());
        if (!m_.model.empty()) line += std::string(" (") + toString(m_.strategy) + ", requirements: " + m_.model + ")";
        text(12, 20, line, R"(font-size="14" font-weight="bold")");
        text(12, 38,
             "heaps " + byteText(m_.heapBytes()) +
                 (m_.sharedAcrossFrames ? " shared by the frames in flight" : " per frame in flight") +
                 " vs unaliased " + byteText(m_.unaliasedBytes) +
                 " vs peak live " + byteText(m_.peakLiveBytes) + "; " + std::to_string(m_.placements.size()) +
                 " transient(s) in " + std::to_string(m_.heaps.size()) + " heap(s)",
             R"(font-size="12")");
    }

    void legend() {
        std::vector<bool> present(kKinds.size());
        for (const MemoryPlacement& p : m_.placements) present[static_cast<size_t>(kinds_[p.resource])] = true;
        double x = 12;
        const double y = 52;
        for (size_t k = 0; k < kKinds.size(); ++k) {
            if (!present[k]) continue;
            o_ << R"(<rect class="legend" x=")" << num(x) << R"(" y=")" << num(y) << R"(" width="12" height="10" fill=")"
               << kKinds[k].fill << R"(" stroke=")" << kKinds[k].stroke << R"("/>)" << "\n";
            text(x + 16, y + 9, kKinds[k].name);
            x += 16 + static_cast<double>(std::string_view(kKinds[k].name).size()) * kCharWidth + 14;
        }
        o_ << R"(<line x1=")" << num(x) << R"(" y1=")" << num(y + 5) << R"(" x2=")" << num(x + 24) << R"(" y2=")"
           << num(y + 5) << R"(" stroke="#c00000" stroke-width="1.5" stroke-dasharray="5,3"/>)" << "\n";
        text(x + 28, y + 9, "peak live bytes; a dashed outline: not shared (\"alias\": false)");
    }

    void heap(size_t h) {
        const HeapBand& b = bands_[h];
        const MemoryHeap& heap = m_.heaps[h];
        std::string label = "heap " + std::to_string(h) + ": " + byteText(heap.bytes) + ", memory types 0x";
        std::ostringstream bits;
        bits << std::hex << heap.memoryTypeBits;
        label += bits.str();
        if (heap.granular) label += ", buffers and images on the " + byteText(m_.granularity) + " granularity";
        text(kLeft, b.top - 7, label, R"(font-weight="bold")");
        o_ << R"(<rect class="heap" x=")" << num(kLeft) << R"(" y=")" << num(b.top) << R"(" width=")"
           << num(plotRight() - kLeft) << R"(" height=")" << num(b.height) << R"(" fill="#f6f6f6" stroke="#888888"/>)"
           << "\n";
        for (size_t c = 1; c < columns_; ++c)  // one column per plan step
            o_ << R"(<line x1=")" << num(columnX(c)) << R"(" y1=")" << num(b.top) << R"(" x2=")" << num(columnX(c))
               << R"(" y2=")" << num(b.top + b.height) << R"(" stroke="#e2e2e2"/>)" << "\n";
        // Offset ticks every power of two that leaves kMinTick pixels between them.
        uint64_t step = 256;
        while (b.pixelsPerByte > 0 && static_cast<double>(step) * b.pixelsPerByte < kMinTick) step *= 2;
        for (uint64_t offset = 0; offset <= heap.bytes; offset += step) {
            const double y = b.top + static_cast<double>(offset) * b.pixelsPerByte;
            o_ << R"(<line x1=")" << num(kLeft - 4) << R"(" y1=")" << num(y) << R"(" x2=")" << num(kLeft) << R"(" y2=")"
               << num(y) << R"(" stroke="#888888"/>)" << "\n";
            text(kLeft - 6, y + 4, tickText(offset), R"(text-anchor="end" fill="#555555")");
            if (heap.bytes - offset < step) break;
        }
    }

    void placement(const MemoryPlacement& p) {
        const PlannedResource& r = plan_.resources()[p.resource];
        const HeapBand& b = bands_[p.heap];
        const KindStyle& style = kKinds[static_cast<size_t>(kinds_[p.resource])];
        const double x = columnX(r.firstPass), w = static_cast<double>(r.lastPass - r.firstPass + 1) * kColumn;
        const double h = std::max(2.0, static_cast<double>(p.bytes) * b.pixelsPerByte);  // a tiny buffer stays visible
        // Made taller, one at the heap's end stays inside the heap's band.
        const double y = std::min(b.top + static_cast<double>(p.offset) * b.pixelsPerByte, b.top + b.height - h);
        // Dashed: the exceptions to sharing, which --no-alias would make of every placement.
        const bool unshared = !p.aliasable && m_.strategy != MemoryStrategy::Unaliased;

        std::string tooltip = std::string(r.name) + ": " + byteText(p.bytes) + " at offset " + std::to_string(p.offset) +
                              " of heap " + std::to_string(p.heap) + ", passes " + std::to_string(r.firstPass) + ".." +
                              std::to_string(r.lastPass) + " (" + std::string(plan_.passes()[r.firstPass].name) +
                              " .. " + std::string(plan_.passes()[r.lastPass].name) + ")";
        if (!p.aliasable) tooltip += ", not shared";
        if (!p.aliases.empty()) {
            tooltip += ", after";
            for (const uint32_t a : p.aliases) tooltip += " " + std::string(plan_.resources()[a].name);
        }
        if (!p.previousFrameAliases.empty()) {
            tooltip += "; the previous frame's";
            for (const uint32_t a : p.previousFrameAliases) tooltip += " " + std::string(plan_.resources()[a].name);
        }
        o_ << R"(<rect class="placement" x=")" << num(x) << R"(" y=")" << num(y) << R"(" width=")" << num(w)
           << R"(" height=")" << num(h) << R"(" fill=")" << style.fill << R"(" stroke=")" << style.stroke << '"'
           << (unshared ? R"( stroke-dasharray="4,2" stroke-width="1.5")" : "") << "><title>" << xml(tooltip)
           << "</title></rect>\n";

        // The name, and the size below it when there is room; nothing that would spill over.
        const std::string size = byteText(p.bytes);
        const auto fits = [&](std::string_view s) { return static_cast<double>(s.size()) * kCharWidth + 6 <= w; };
        if (h < kLineHeight || !fits(r.name)) return;
        if (h >= 2 * kLineHeight + 2 && fits(size)) {
            text(x + 3, y + 12, r.name);
            text(x + 3, y + 12 + kLineHeight, size, R"(fill="#333333")");
        } else if (const std::string both = std::string(r.name) + " " + size; fits(both)) {
            text(x + 3, y + 11, both);
        } else {
            text(x + 3, y + 11, r.name);
        }
    }

    void peakLine() {
        if (bands_.empty()) return;
        const double y = stackedY(m_, bands_, m_.peakLiveBytes);
        o_ << R"(<line class="peak" x1=")" << num(kLeft) << R"(" y1=")" << num(y) << R"(" x2=")" << num(plotRight() + 6)
           << R"(" y2=")" << num(y) << R"(" stroke="#c00000" stroke-width="1.5" stroke-dasharray="5,3"/>)" << "\n";
        text(plotRight() + 10, y + 4, "peak live " + byteText(m_.peakLiveBytes), R"(fill="#c00000")");
    }

    void passLabels() {
        const double y = plotBottom_ + 8;
        for (size_t i = 0; i < plan_.passes().size(); ++i) {
            const std::string_view name = plan_.passes()[i].name;
            const double x = columnX(i) + kColumn / 2 + 4;
            o_ << R"(<text x=")" << num(x) << R"(" y=")" << num(y) << R"(" text-anchor="end" transform="rotate(-90 )"
               << num(x) << " " << num(y) << ")\"><title>" << i << ": " << xml(name) << "</title>"
               << xml(shortened(name, kMaxPassLabel)) << "</text>\n";
        }
    }

    const Plan& plan_;
    const MemoryLayout& m_;
    std::vector<HeapBand> bands_;
    std::vector<Kind> kinds_;
    size_t columns_ = 1;
    double width_ = 0, height_ = 0, plotBottom_ = 0;
    std::ostringstream o_;
};

}  // namespace

std::string planMemoryToSvg(const Plan& plan) { return SvgWriter(plan).draw(); }

}  // namespace skygraph
