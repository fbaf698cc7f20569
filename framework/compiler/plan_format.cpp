#include <skygraph/plan_format.hpp>

#include "byte_text.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

namespace skygraph {
namespace {

using json = nlohmann::ordered_json;

#define SG_BIT(prefix, name) std::pair<uint64_t, const char*>{prefix##name, #prefix #name}

constexpr std::array kStageBits{
    SG_BIT(VK_PIPELINE_STAGE_2_, TOP_OF_PIPE_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, DRAW_INDIRECT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, VERTEX_INPUT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, VERTEX_SHADER_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, FRAGMENT_SHADER_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, EARLY_FRAGMENT_TESTS_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, LATE_FRAGMENT_TESTS_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, COLOR_ATTACHMENT_OUTPUT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, COMPUTE_SHADER_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, TRANSFER_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, BOTTOM_OF_PIPE_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, HOST_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, ALL_GRAPHICS_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, ALL_COMMANDS_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, COPY_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, RESOLVE_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, BLIT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, CLEAR_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, INDEX_INPUT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, VERTEX_ATTRIBUTE_INPUT_BIT),
    SG_BIT(VK_PIPELINE_STAGE_2_, PRE_RASTERIZATION_SHADERS_BIT),
};

constexpr std::array kAccessBits{
    SG_BIT(VK_ACCESS_2_, INDIRECT_COMMAND_READ_BIT),
    SG_BIT(VK_ACCESS_2_, INDEX_READ_BIT),
    SG_BIT(VK_ACCESS_2_, VERTEX_ATTRIBUTE_READ_BIT),
    SG_BIT(VK_ACCESS_2_, UNIFORM_READ_BIT),
    SG_BIT(VK_ACCESS_2_, INPUT_ATTACHMENT_READ_BIT),
    SG_BIT(VK_ACCESS_2_, SHADER_READ_BIT),
    SG_BIT(VK_ACCESS_2_, SHADER_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, COLOR_ATTACHMENT_READ_BIT),
    SG_BIT(VK_ACCESS_2_, COLOR_ATTACHMENT_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, DEPTH_STENCIL_ATTACHMENT_READ_BIT),
    SG_BIT(VK_ACCESS_2_, DEPTH_STENCIL_ATTACHMENT_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, TRANSFER_READ_BIT),
    SG_BIT(VK_ACCESS_2_, TRANSFER_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, HOST_READ_BIT),
    SG_BIT(VK_ACCESS_2_, HOST_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, MEMORY_READ_BIT),
    SG_BIT(VK_ACCESS_2_, MEMORY_WRITE_BIT),
    SG_BIT(VK_ACCESS_2_, SHADER_SAMPLED_READ_BIT),
    SG_BIT(VK_ACCESS_2_, SHADER_STORAGE_READ_BIT),
    SG_BIT(VK_ACCESS_2_, SHADER_STORAGE_WRITE_BIT),
};
#undef SG_BIT

template <size_t N>
std::vector<std::string> bitNames(uint64_t mask, const std::array<std::pair<uint64_t, const char*>, N>& table) {
    std::vector<std::string> out;
    for (const auto& [bit, name] : table)
        if (mask & bit) {
            out.emplace_back(name);
            mask &= ~bit;
        }
    for (int b = 0; b < 64; ++b)  // bits this table does not know still show up, in hex
        if (mask & (1ull << b)) {
            char hex[24];
            std::snprintf(hex, sizeof hex, "0x%llx", static_cast<unsigned long long>(1ull << b));
            out.emplace_back(hex);
        }
    return out;
}

std::string joined(const std::vector<std::string>& names, const char* prefix) {
    if (names.empty()) return "NONE";
    std::string out;
    for (const auto& n : names) {
        std::string shortName = n.starts_with(prefix) ? n.substr(std::string_view(prefix).size()) : n;
        if (shortName.ends_with("_BIT")) shortName.resize(shortName.size() - 4);
        out += (out.empty() ? "" : "|") + shortName;
    }
    return out;
}

std::string shortLayout(VkImageLayout l) {
    std::string n = layoutName(l);
    return n.starts_with("VK_IMAGE_LAYOUT_") ? n.substr(16) : n;
}

const char* kindName(BarrierKind k) {
    switch (k) {
        case BarrierKind::Image: return "image";
        case BarrierKind::Buffer: return "buffer";
        case BarrierKind::Memory: return "memory";
    }
    return "?";
}

const char* loadName(LoadOp op) {
    switch (op) {
        case LoadOp::Load: return "LOAD";
        case LoadOp::Clear: return "CLEAR";
        case LoadOp::DontCare: return "DONT_CARE";
    }
    return "?";
}

const char* storeName(StoreOp op) {
    switch (op) {
        case StoreOp::Store: return "STORE";
        case StoreOp::DontCare: return "DONT_CARE";
        case StoreOp::None: return "NONE";
    }
    return "?";
}

/// Why the executor keeps the copies it does of a resource, in the plan's words.
const char* copiesReason(ResourceCopies c) {
    switch (c) {
        case ResourceCopies::PerFrameTransient: return "transient";
        case ResourceCopies::SharedTransient: return "sharedTransient";
        case ResourceCopies::PerFramePresented: return "presented";
        case ResourceCopies::PerFrameWrittenNotExported: return "writtenNotExported";
        case ResourceCopies::SharedExported: return "exported";
        case ResourceCopies::SharedReadOnly: return "readOnly";
    }
    return "?";
}

/// The resources whose memory an aliasing barrier's resource takes over, earlier in the frame
/// or (`previousFrame`) in the frame before.
std::vector<std::string_view> aliasNames(const Plan& plan, uint32_t resource, bool previousFrame = false) {
    std::vector<std::string_view> names;
    const uint32_t p = plan.resources()[resource].placement;
    if (p == PlannedResource::kNoPlacement) return names;
    const MemoryPlacement& placement = plan.memory().placements[p];
    for (const uint32_t a : previousFrame ? placement.previousFrameAliases : placement.aliases)
        names.push_back(plan.resources()[a].name);
    return names;
}

/// " after a b", " after a; the previous frame's c" or "", for text plans.
std::string aliasText(const Plan& plan, uint32_t resource) {
    std::string text;
    for (const std::string_view n : aliasNames(plan, resource)) text += (text.empty() ? " after " : " ") + std::string(n);
    const auto previous = aliasNames(plan, resource, true);
    for (size_t i = 0; i < previous.size(); ++i)
        text += (i ? " " : text.empty() ? " after the previous frame's " : "; the previous frame's ") + std::string(previous[i]);
    return text;
}

json barrierJson(const Plan& plan, const Barrier& b) {
    json j = {{"resource", plan.resources()[b.resource].name},
              {"kind", kindName(b.kind)},
              {"srcStageMask", stageMaskNames(b.srcStages)},
              {"srcAccessMask", accessMaskNames(b.srcAccess)},
              {"dstStageMask", stageMaskNames(b.dstStages)},
              {"dstAccessMask", accessMaskNames(b.dstAccess)}};
    if (b.kind == BarrierKind::Image) {
        j["oldLayout"] = layoutName(b.oldLayout);
        j["newLayout"] = layoutName(b.newLayout);
        j["baseMipLevel"] = b.range.baseMip;
        j["levelCount"] = b.range.mipCount;
        j["baseArrayLayer"] = b.range.baseLayer;
        j["layerCount"] = b.range.layerCount;
    }
    if (b.aliasing) {
        j["aliases"] = aliasNames(plan, b.resource);
        if (plan.memory().sharedAcrossFrames) j["previousFrameAliases"] = aliasNames(plan, b.resource, true);
    }
    if (b.transfersOwnership()) {
        j["srcQueue"] = toString(b.srcQueue);
        j["dstQueue"] = toString(b.dstQueue);
    }
    return j;
}

bool onSeveralQueues(const Plan& plan) { return plan.submits().size() > 1; }

std::string semaphoreText(const SemaphoreOp& op) {
    return std::string(toString(op.semaphore)) + "=" + std::to_string(op.value) + " at " +
           joined(stageMaskNames(op.stages), "VK_PIPELINE_STAGE_2_");
}

json semaphoresJson(std::span<const SemaphoreOp> ops) {
    json j = json::array();
    for (const SemaphoreOp& op : ops)
        j.push_back({{"semaphore", toString(op.semaphore)}, {"value", op.value}, {"stage", stageMaskNames(op.stages)}});
    return j;
}

json submitsJson(const Plan& plan) {
    json j = json::array();
    for (const Submit& s : plan.submits()) {
        json js = {{"queue", toString(s.queue)}, {"passes", json::array()}};
        for (uint32_t p : s.passes) js["passes"].push_back(plan.passes()[p].name);
        js["waits"] = semaphoresJson(s.waits);
        js["signals"] = semaphoresJson(s.signals);
        js["releases"] = json::array();
        for (const Barrier& b : s.releases) js["releases"].push_back(barrierJson(plan, b));
        if (s.waitsForAcquire) js["waitsForAcquire"] = true;
        j.push_back(std::move(js));
    }
    return j;
}

json memoryJson(const Plan& plan) {
    const MemoryLayout& m = plan.memory();
    json j = {{"model", m.model}, {"strategy", toString(m.strategy)}, {"granularity", m.granularity}};
    j["heaps"] = json::array();
    for (const MemoryHeap& h : m.heaps)
        j["heaps"].push_back({{"bytes", h.bytes}, {"memoryTypeBits", h.memoryTypeBits}, {"granular", h.granular}});
    j["placements"] = json::array();
    for (const MemoryPlacement& p : m.placements) {
        json jp = {{"resource", plan.resources()[p.resource].name},
                   {"heap", p.heap},
                   {"offset", p.offset},
                   {"bytes", p.bytes},
                   {"alignment", p.requirements.alignment},
                   {"aliasable", p.aliasable},
                   {"aliases", json::array()}};
        for (const uint32_t a : p.aliases) jp["aliases"].push_back(plan.resources()[a].name);
        if (m.sharedAcrossFrames) {
            jp["previousFrameAliases"] = json::array();
            for (const uint32_t a : p.previousFrameAliases) jp["previousFrameAliases"].push_back(plan.resources()[a].name);
        }
        j["placements"].push_back(std::move(jp));
    }
    j["sharedAcrossFrames"] = m.sharedAcrossFrames;
    j["heapBytes"] = m.heapBytes();
    j["unaliasedBytes"] = m.unaliasedBytes;
    j["peakLiveBytes"] = m.peakLiveBytes;
    return j;
}

std::string memoryText(const Plan& plan) {
    const MemoryLayout& m = plan.memory();
    std::ostringstream o;
    o << "memory: " << m.placements.size() << " transient(s) in " << m.heaps.size() << " heap(s) of "
      << byteText(m.heapBytes()) << (m.sharedAcrossFrames ? " shared by the frames in flight (" : " per frame in flight (")
      << toString(m.strategy) << ", requirements: " << m.model
      << "); unaliased " << byteText(m.unaliasedBytes) << ", peak live " << byteText(m.peakLiveBytes) << "\n";
    for (size_t h = 0; h < m.heaps.size(); ++h) {
        o << "    heap " << h << ": " << byteText(m.heaps[h].bytes) << ", memory types 0x" << std::hex
          << m.heaps[h].memoryTypeBits << std::dec;
        if (m.heaps[h].granular) o << ", placed on the buffer-image granularity (" << m.granularity << " bytes)";
        o << "\n";
        for (const MemoryPlacement& p : m.placements) {
            if (p.heap != h) continue;
            o << "      [" << p.offset << ", " << p.offset + p.bytes << ") " << plan.resources()[p.resource].name << " ("
              << byteText(p.bytes) << ")";
            if (!p.aliasable) o << " not shared";
            o << aliasText(plan, p.resource) << "\n";
        }
    }
    return o.str();
}

std::string barrierText(const Plan& plan, const Barrier& b) {
    std::ostringstream o;
    o << "    " << kindName(b.kind) << " " << plan.resources()[b.resource].name;
    if (b.kind == BarrierKind::Image)
        o << " mips[" << b.range.baseMip << "+" << b.range.mipCount << "] layers["
          << b.range.baseLayer << "+" << b.range.layerCount << "]";
    if (b.aliasing) o << " aliasing," << aliasText(plan, b.resource);
    if (b.transfersOwnership()) o << " ownership " << toString(b.srcQueue) << " -> " << toString(b.dstQueue);
    o << "\n      " << joined(stageMaskNames(b.srcStages), "VK_PIPELINE_STAGE_2_") << " / "
      << joined(accessMaskNames(b.srcAccess), "VK_ACCESS_2_") << "  ->  "
      << joined(stageMaskNames(b.dstStages), "VK_PIPELINE_STAGE_2_") << " / "
      << joined(accessMaskNames(b.dstAccess), "VK_ACCESS_2_");
    if (b.kind == BarrierKind::Image) {
        if (b.oldLayout != b.newLayout)
            o << "\n      " << shortLayout(b.oldLayout) << " -> " << shortLayout(b.newLayout);
        else
            o << "\n      stays " << shortLayout(b.newLayout);
    }
    o << "\n";
    return o.str();
}

std::string dotEscape(std::string_view s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out;
}


/// The memory layout for graphviz: a box per heap listing its placements in offset order,
/// and a dashed edge from each resource to the one that takes over its memory. Edges do not
/// constrain the ranks, so the passes and resources keep the places they have without them.
std::string memoryDot(const Plan& plan) {
    const MemoryLayout& m = plan.memory();
    std::ostringstream o;
    for (size_t h = 0; h < m.heaps.size(); ++h) {
        std::vector<const MemoryPlacement*> inHeap;
        for (const MemoryPlacement& p : m.placements)
            if (p.heap == h) inHeap.push_back(&p);
        std::stable_sort(inHeap.begin(), inHeap.end(),
                         [](const MemoryPlacement* a, const MemoryPlacement* b) { return a->offset < b->offset; });
        o << "  subgraph \"cluster_heap" << h << "\" {\n    label=\"heap " << h << ": " << byteText(m.heaps[h].bytes)
          << (m.sharedAcrossFrames ? " shared by the frames in flight (" : " per frame in flight (")
          << toString(m.strategy) << ")\";\n    style=rounded;\n    color=\"#7a5cc6\";\n"
          << "    \"heap:" << h << "\" [shape=box, style=filled, fillcolor=\"#f1ecfa\", fontname=\"Courier\", label=\"";
        for (const MemoryPlacement* p : inHeap) {
            o << "[" << byteText(p->offset) << ", " << byteText(p->offset + p->bytes) << ") "
              << dotEscape(plan.resources()[p->resource].name);
            if (!p->aliasable) o << " (not shared)";
            o << "\\l";
        }
        if (inHeap.empty()) o << "(empty)\\l";
        o << "\"];\n  }\n";
    }
    for (const MemoryPlacement& p : m.placements)
        for (const uint32_t a : p.aliases)
            o << "  \"res:" << dotEscape(plan.resources()[a].name) << "\" -> \"res:"
              << dotEscape(plan.resources()[p.resource].name)
              << "\" [style=dashed, color=\"#7a5cc6\", fontcolor=\"#7a5cc6\", label=\"memory\", constraint=false];\n";
    return o.str();
}

}  // namespace

std::vector<std::string> stageMaskNames(VkPipelineStageFlags2 mask) { return bitNames(mask, kStageBits); }
std::vector<std::string> accessMaskNames(VkAccessFlags2 mask) { return bitNames(mask, kAccessBits); }

std::string layoutName(VkImageLayout layout) {
    switch (layout) {
#define SG_LAYOUT(n) \
    case VK_IMAGE_LAYOUT_##n: return "VK_IMAGE_LAYOUT_" #n;
        SG_LAYOUT(UNDEFINED)
        SG_LAYOUT(GENERAL)
        SG_LAYOUT(COLOR_ATTACHMENT_OPTIMAL)
        SG_LAYOUT(DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
        SG_LAYOUT(DEPTH_STENCIL_READ_ONLY_OPTIMAL)
        SG_LAYOUT(SHADER_READ_ONLY_OPTIMAL)
        SG_LAYOUT(TRANSFER_SRC_OPTIMAL)
        SG_LAYOUT(TRANSFER_DST_OPTIMAL)
        SG_LAYOUT(PREINITIALIZED)
        SG_LAYOUT(DEPTH_ATTACHMENT_OPTIMAL)
        SG_LAYOUT(DEPTH_READ_ONLY_OPTIMAL)
        SG_LAYOUT(STENCIL_ATTACHMENT_OPTIMAL)
        SG_LAYOUT(STENCIL_READ_ONLY_OPTIMAL)
        SG_LAYOUT(READ_ONLY_OPTIMAL)
        SG_LAYOUT(ATTACHMENT_OPTIMAL)
        SG_LAYOUT(PRESENT_SRC_KHR)
#undef SG_LAYOUT
        default: return "VK_IMAGE_LAYOUT_" + std::to_string(static_cast<int>(layout));
    }
}

json planToJson(const Plan& plan) {
    json j;
    j["graph"] = plan.graph();
    j["features"] = json::object();
    for (const auto& [name, on] : plan.features()) j["features"][name] = on;
    j["output"] = {plan.outputWidth(), plan.outputHeight()};
    // Only when not the default, so that the default's plans read as they always have.
    if (plan.layouts() != LayoutPolicy::FewestBarriers) j["layouts"] = toString(plan.layouts());
    j["passes"] = json::array();
    for (const auto& p : plan.passes()) {
        json pass = {{"name", p.name}, {"type", p.type}, {"barriers", json::array()}};
        if (onSeveralQueues(plan)) pass["queue"] = toString(plan.queueOf(static_cast<uint32_t>(&p - plan.passes().data())));
        for (const auto& b : p.barriers) pass["barriers"].push_back(barrierJson(plan, b));
        // Extension: how the pass uses each resource once barriers have run.
        pass["usages"] = json::array();
        for (const auto& u : p.usages) {
            json ju = {{"resource", plan.resources()[u.resource].name},
                       {"usage", toString(u.usage)},
                       {"stageMask", stageMaskNames(u.stages)},
                       {"accessMask", accessMaskNames(u.access)}};
            if (!u.slot.empty()) ju["slot"] = u.slot;
            if (u.layout != VK_IMAGE_LAYOUT_UNDEFINED) {
                ju["layout"] = layoutName(u.layout);
                ju["mips"] = {u.range.baseMip, u.range.mipCount};
                ju["layers"] = {u.range.baseLayer, u.range.layerCount};
            }
            if (isAttachmentStage(u.usage.stage)) {
                ju["loadOp"] = loadName(u.load);
                ju["storeOp"] = storeName(u.store);
            }
            pass["usages"].push_back(std::move(ju));
        }
        for (const InPassBarrier& ib : plan.inPassBarriers()) {
            if (&plan.passes()[ib.pass] != &p) continue;
            pass["inPassBarriers"].push_back({{"beforeWriteOfUsage", ib.usage}, {"barrier", barrierJson(plan, ib.barrier)}});
        }
        j["passes"].push_back(std::move(pass));
    }
    j["final"] = json::array();
    for (const auto& b : plan.finalBarriers()) j["final"].push_back(barrierJson(plan, b));
    // Only for plans on several queues: one submit holding every pass goes without saying.
    if (onSeveralQueues(plan)) j["submits"] = submitsJson(plan);
    j["culled"] = json::array();
    for (const auto& c : plan.culled()) j["culled"].push_back({{"pass", c.name}, {"reason", c.reason}});
    // Extension: the semaphore stages of a presented frame.
    if (!plan.presentations().empty()) {
        j["present"] = json::array();
        for (const Presentation& pr : plan.presentations())
            j["present"].push_back({{"resource", plan.resources()[pr.resource].name},
                                    {"acquireWaitStageMask", stageMaskNames(pr.acquireWaitStages)},
                                    {"renderCompleteStageMask", stageMaskNames(pr.renderCompleteStages)}});
    }
    // Extension: resource lifetimes as indices into "passes".
    j["resources"] = json::array();
    for (const auto& r : plan.resources())
        j["resources"].push_back({{"name", r.name},
                                  {"firstPass", r.firstPass},
                                  {"lastPass", r.lastPass},
                                  {"initialLayout", layoutName(r.initialLayout)},
                                  {"finalLayout", layoutName(r.finalLayout)},
                                  {"copies", perFrameInFlight(r.copies) ? "perFrameInFlight" : "one"},
                                  {"copiesWhy", copiesReason(r.copies)}});
    for (size_t r = 0; r < plan.resources().size(); ++r)
        if (plan.concurrent(static_cast<uint32_t>(r))) j["resources"][r]["sharing"] = "concurrent";
    // Extension: where the transient resources live (plans of compile() only).
    if (!plan.memory().model.empty()) j["memory"] = memoryJson(plan);
    return j;
}

std::string planToText(const Plan& plan) {
    std::ostringstream o;
    o << "graph " << plan.graph() << "\nfeatures:";
    for (const auto& [name, on] : plan.features()) o << " " << name << "=" << (on ? "on" : "off");
    o << "\noutput: " << plan.outputWidth() << "x" << plan.outputHeight() << "\n";
    if (plan.layouts() != LayoutPolicy::FewestBarriers) o << "layouts: " << toString(plan.layouts()) << "\n";
    o << "\n";
    for (size_t i = 0; i < plan.passes().size(); ++i) {
        const auto& p = plan.passes()[i];
        o << "[" << i << "] " << p.name << " (" << p.type << ")";
        if (onSeveralQueues(plan)) o << " on " << toString(plan.queueOf(static_cast<uint32_t>(i)));
        o << "\n";
        for (const auto& b : p.barriers) o << barrierText(plan, b);
        for (const auto& u : p.usages) {
            o << "    uses " << plan.resources()[u.resource].name << " " << toString(u.usage);
            if (u.layout != VK_IMAGE_LAYOUT_UNDEFINED) o << " in " << shortLayout(u.layout);
            if (isAttachmentStage(u.usage.stage))
                o << " load=" << loadName(u.load) << " store=" << storeName(u.store);
            o << "\n";
        }
        for (const InPassBarrier& ib : plan.inPassBarriers())
            if (ib.pass == i) o << "  between the copy out and the copy in of usage " << ib.usage << ":\n"
                                << barrierText(plan, ib.barrier);
    }
    o << "final:\n";
    for (const auto& b : plan.finalBarriers()) o << barrierText(plan, b);
    if (onSeveralQueues(plan)) {
        o << "submits:\n";
        for (size_t k = 0; k < plan.submits().size(); ++k) {
            const Submit& sub = plan.submits()[k];
            o << "    " << k << ": " << toString(sub.queue) << " [";
            for (size_t n = 0; n < sub.passes.size(); ++n) o << (n ? " " : "") << sub.passes[n];
            o << "]";
            if (sub.waitsForAcquire) o << " waits for the swapchain acquire";
            o << "\n";
            for (const SemaphoreOp& w : sub.waits) o << "      wait " << semaphoreText(w) << "\n";
            for (const Barrier& b : sub.releases) o << "      release" << barrierText(plan, b).substr(3);
            for (const SemaphoreOp& sg : sub.signals) o << "      signal " << semaphoreText(sg) << "\n";
        }
        o << "sharing:";
        bool any = false;
        for (size_t r = 0; r < plan.resources().size(); ++r)
            if (plan.concurrent(static_cast<uint32_t>(r))) {
                o << " " << plan.resources()[r].name;
                any = true;
            }
        o << (any ? " concurrent; the rest exclusive\n" : " every resource exclusive\n");
    }
    o << "culled:\n";
    for (const auto& c : plan.culled()) o << "    " << c.name << ": " << c.reason << "\n";
    for (const Presentation& pr : plan.presentations())
        o << "present " << plan.resources()[pr.resource].name << ": the submit waits on its acquire at "
          << joined(stageMaskNames(pr.acquireWaitStages), "VK_PIPELINE_STAGE_2_") << " and signals render-complete at "
          << joined(stageMaskNames(pr.renderCompleteStages), "VK_PIPELINE_STAGE_2_") << "\n";
    o << "lifetimes:\n";
    for (const auto& r : plan.resources())
        o << "    " << r.name << ": passes " << r.firstPass << ".." << r.lastPass << ", "
          << (perFrameInFlight(r.copies) ? "a copy per frame in flight" : "one copy") << " ("
          << copiesReason(r.copies) << ")\n";
    if (!plan.memory().model.empty()) o << memoryText(plan);
    return o.str();
}

/// One lane per queue holding its passes, and an edge per semaphore wait from the last pass
/// of the submit it waits for (the frame's start, when that submit has no passes).
std::string queueLanesDot(const Plan& plan) {
    std::ostringstream o;
    for (size_t q = 0; q < kQueueKinds; ++q) {
        const auto kind = static_cast<QueueKind>(q);
        o << "  subgraph \"cluster_queue_" << toString(kind) << "\" {\n    label=\"" << toString(kind)
          << " queue\";\n    style=dashed;\n";
        for (size_t i = 0; i < plan.passes().size(); ++i)
            if (plan.queueOf(static_cast<uint32_t>(i)) == kind) o << "    \"pass:" << dotEscape(plan.passes()[i].name) << "\";\n";
        if (kind == QueueKind::Graphics) o << "    \"frame start\" [shape=point];\n    \"frame end\" [shape=point];\n";
        o << "  }\n";
    }
    auto endOf = [&](const Submit& s, bool signalling) {
        if (s.passes.empty()) return std::string(signalling ? "\"frame start\"" : "\"frame end\"");
        return "\"pass:" + dotEscape(plan.passes()[signalling ? s.passes.back() : s.passes.front()].name) + "\"";
    };
    for (const Submit& waiter : plan.submits())
        for (const SemaphoreOp& w : waiter.waits)
            for (const Submit& signaller : plan.submits())
                for (const SemaphoreOp& sg : signaller.signals)
                    if (sg.semaphore == w.semaphore && sg.value == w.value)
                        o << "  " << endOf(signaller, true) << " -> " << endOf(waiter, false)
                          << " [style=bold, color=\"#c03030\", label=\"" << dotEscape(semaphoreText(w)) << "\"];\n";
    return o.str();
}

std::string planToDot(const Plan& plan, const GraphDesc& graph, const Plan* setup) {
    std::ostringstream o;
    o << "digraph \"" << dotEscape(plan.graph()) << "\" {\n  rankdir=LR;\n"
      << "  node [fontname=\"Helvetica\", fontsize=10];\n  edge [fontname=\"Helvetica\", fontsize=8];\n";
    if (setup && !setup->passes().empty()) {
        // What runs once before the first frame, in a box of its own beside the frame.
        o << "  subgraph \"cluster_setup\" {\n    label=\"setup, once before the first frame\";\n"
          << "    style=dashed;\n    color=\"#888888\";\n";
        for (size_t i = 0; i < setup->passes().size(); ++i) {
            const auto& p = setup->passes()[i];
            o << "    \"setup:" << dotEscape(p.name) << "\" [shape=box, style=\"rounded,filled\", "
              << "fillcolor=\"#e4f2dc\", label=\"" << dotEscape(p.name) << "\\n(" << dotEscape(p.type) << ")\\n"
              << p.barriers.size() << " barrier(s)\"];\n";
        }
        o << "  }\n";
        for (const auto& p : setup->passes())
            for (const auto& u : p.usages)
                o << "  \"setup:" << dotEscape(p.name) << "\" -> \"res:" << dotEscape(setup->resources()[u.resource].name)
                  << "\" [style=dashed, color=\"#5a9a3a\", label=\"" << toString(u.usage.stage) << "\"];\n";
    }
    for (size_t i = 0; i < plan.passes().size(); ++i) {
        const auto& p = plan.passes()[i];
        o << "  \"pass:" << dotEscape(p.name) << "\" [shape=box, style=\"rounded,filled\", "
          << "fillcolor=\"#cfe3ff\", label=\"" << i << ": " << dotEscape(p.name) << "\\n("
          << dotEscape(p.type) << ")\\n" << p.barriers.size() << " barrier(s)\"];\n";
    }
    if (onSeveralQueues(plan)) o << queueLanesDot(plan);
    for (size_t i = 0; i < plan.resources().size(); ++i) {
        const PlannedResource& r = plan.resources()[i];
        o << "  \"res:" << dotEscape(r.name) << "\" [shape=ellipse, label=\"" << dotEscape(r.name);
        for (const Presentation& pr : plan.presentations())
            if (pr.resource == i)
                o << "\\npresented: acquire waited at "
                  << joined(stageMaskNames(pr.acquireWaitStages), "VK_PIPELINE_STAGE_2_");
        o << "\"];\n";
    }
    for (const auto& p : plan.passes())
        for (const auto& u : p.usages) {
            const std::string res = "\"res:" + dotEscape(plan.resources()[u.resource].name) + "\"";
            const std::string pass = "\"pass:" + dotEscape(p.name) + "\"";
            const std::string label = " [label=\"" + std::string(toString(u.usage.stage)) + "\"]";
            if (readsContents(u.usage.access)) o << "  " << res << " -> " << pass << label << ";\n";
            if (writesContents(u.usage.access)) o << "  " << pass << " -> " << res << label << ";\n";
        }
    std::set<std::string> onlyCulledUse;  // resources no pass of the plan uses, declared once
    for (const auto& c : plan.culled()) {
        o << "  \"pass:" << dotEscape(c.name) << "\" [shape=box, style=\"rounded,dashed,filled\", "
          << "fillcolor=\"#eeeeee\", fontcolor=\"#888888\", color=\"#aaaaaa\", label=\""
          << dotEscape(c.name) << "\\nculled: " << dotEscape(c.reason) << "\"];\n";
        for (const auto& pass : graph.passes) {
            if (pass.name != c.name) continue;
            for (const auto& u : pass.uses) {
                const std::string& name = graph.resources[u.resource].name;
                const std::string res = "\"res:" + dotEscape(name) + "\"";
                // Labelled as the plan's resources are: Graphviz labels a node without one by
                // its id, "res:lonely".
                if (plan.resourceIndex(name) < 0 && onlyCulledUse.insert(name).second)
                    o << "  " << res << " [shape=ellipse, style=dashed, fontcolor=\"#888888\", label=\""
                      << dotEscape(name) << "\"];\n";
                o << "  \"pass:" << dotEscape(c.name) << "\" -> " << res
                  << " [style=dashed, color=\"#aaaaaa\", arrowhead=none];\n";
            }
        }
    }
    if (!plan.memory().model.empty()) o << memoryDot(plan);
    o << "}\n";
    return o.str();
}

}  // namespace skygraph
