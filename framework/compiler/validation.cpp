#include "validation.hpp"

#include "graph_file.hpp"
#include "graph_limits.hpp"
#include "scheduler.hpp"
#include "usage_fit.hpp"

#include <algorithm>
#include <bit>
#include <set>

namespace skygraph {
namespace {

/// "reads 'x' (Read@Fragment) but no earlier pass writes it, ...", for a read with no source;
/// `unwritten` names the part of the read no pass writes (e.g. "mip 1") where others are.
Diagnostic unsourcedRead(const GraphDesc& graph, size_t pass, size_t use, const std::string& why,
                         const std::string& unwritten = {}) {
    const UsageDecl& u = graph.passes[pass].uses[use];
    const ResourceDesc& res = graph.resources[u.resource];
    return {graph.file, graph.usageJsonPath(pass, use), graph.passes[pass].name, res.name,
            "reads '" + res.name + "' (" + toString(u.usage) + ") but no earlier pass writes " +
                (unwritten.empty() ? "it" : unwritten + " of it") + ", and it is neither `clear` nor `external`" + why};
}

/// "mip 1", "mips 1 and 2", "mip 0 (layers 2, 3)", "mip 0 (layers 0 to 2046)": per mip of
/// `range`, its layers for which `missing(mip, layer)` holds, all of them or those listed, a
/// run of three or more as its ends (an array of 2048 layers gives one short line).
template <typename Missing>
std::string describeUnwritten(const SubresourceRange& range, Missing&& missing) {
    std::vector<std::string> parts;
    bool wholeMipsOnly = true;
    const uint32_t endLayer = range.baseLayer + range.layerCount;
    for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m) {
        std::string layers;
        uint32_t count = 0;
        for (uint32_t l = range.baseLayer; l < endLayer; ++l) {
            if (!missing(m, l)) continue;
            uint32_t last = l;
            while (last + 1 < endLayer && missing(m, last + 1)) ++last;
            const std::string separator = count == 0 ? "" : ", ";
            if (last - l >= 2) layers += separator + std::to_string(l) + " to " + std::to_string(last);
            else layers += separator + std::to_string(l) + (last > l ? ", " + std::to_string(last) : "");
            count += last - l + 1;
            l = last;
        }
        if (count == 0) continue;
        const bool whole = count == range.layerCount;
        wholeMipsOnly &= whole;
        parts.push_back(std::to_string(m) + (whole ? "" : " (layer" + std::string(count > 1 ? "s " : " ") + layers + ")"));
    }
    std::string out;
    if (!wholeMipsOnly) {  // "mip 0 (layers 2, 3), mip 1"
        for (const std::string& part : parts) out += (out.empty() ? "mip " : ", mip ") + part;
        return out;
    }
    out = parts.size() > 1 ? "mips " : "mip ";  // "mips 1, 2 and 3"
    for (size_t i = 0; i < parts.size(); ++i) out += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
    return out;
}

/// "; its writer 'x' is off: ..." for the first earlier pass that would write `resource` but
/// is switched off by a feature: the usual cause of a read with no source.
std::string switchedOffWriter(const GraphIndex& index, const FeatureValues& features, size_t reader,
                              uint32_t resource) {
    const GraphDesc& graph = index.graph();
    for (size_t q = 0; q < reader; ++q) {
        if (index.active(q)) continue;
        for (const auto& w : graph.passes[q].uses)
            if (w.resource == resource && writesContents(w.usage.access))
                return "; its writer '" + graph.passes[q].name +
                       "' is off: " + conditionReason(graph.passes[q].condition, features);
    }
    return {};
}

/// Per subresource of `resource`, whether it holds contents before pass `reader` (it is
/// `clear` or `external`, or an earlier active pass wrote it). Only for messages: it replays
/// the earlier active passes' writes of the one resource.
std::vector<uint8_t> heldBefore(const GraphIndex& index, size_t reader, uint32_t resource) {
    const SubresourceGrid& grid = index.grid(resource);
    std::vector<uint8_t> held(grid.size(), index.clear(resource) || index.external(resource));
    for (size_t q = 0; q < reader; ++q) {
        if (!index.active(q)) continue;
        for (const IndexedUsage& w : index.usesOf(q))
            if (w.resource == resource && writesContents(w.usage.access))
                grid.forEach(index.range(w), [&](size_t cell) { held[cell] = 1; });
    }
    return held;
}

/// What read `u` of pass `reader` finds unwritten ("mips 1 and 2"), at the output size, as
/// describeUnwritten words it; empty when no part of it is written.
std::string unwrittenBefore(const GraphIndex& index, size_t reader, const IndexedUsage& u) {
    const SubresourceGrid& grid = index.grid(u.resource);
    const std::vector<uint8_t> held = heldBefore(index, reader, u.resource);
    const SubresourceRange read = index.range(u);
    size_t cells = 0, missing = 0;
    grid.forEach(read, [&](size_t cell) {
        ++cells;
        missing += held[cell] == 0;
    });
    if (missing == cells) return {};
    return describeUnwritten(read, [&](uint32_t mip, uint32_t layer) {
        return held[grid.index(mip, layer)] == 0;
    });
}

/// "'o' is an output of the graph (`final`), but no pass writes mip 1 of it, ...": `writer`
/// says which passes ("pass", "pass that runs with these features"); an empty `part` is all of it.
std::string unwrittenOutput(const std::string& name, const std::string& writer, const std::string& part) {
    return "'" + name + "' is an output of the graph (`final`), but no " + writer + " writes " +
           (part.empty() ? "it" : part + " of it") + ", and it is not `clear`: the frame would hand " +
           (part.empty() ? "it" : "that part") + " on undefined";
}

/// A resource's subresources as the load-time check sees them, with no output size. Small:
/// the check reads one per usage, in no order.
struct LoadGrid {
    uint32_t firstCell = 0;  ///< Cells number fewer than kMaxSubresources.
    uint16_t mips = 1;       ///< At most 15 (kMaxImageExtent's chain).
    uint16_t layers = 1;     ///< At most the loader's 2048.
    /// A "full" chain of an output-relative image: its length comes with the output size, so
    /// reads are checked at their first level only, and the grid has every level a file can
    /// name.
    bool chainOfOutput = false;
};

LoadGrid loadGrid(const ResourceDesc& r) {
    LoadGrid g;
    if (!r.isImage()) return g;
    g.layers = static_cast<uint16_t>(r.layers);
    g.chainOfOutput = r.mips == 0 && r.extent.relativeToOutput;
    if (g.chainOfOutput) {
        g.mips = static_cast<uint16_t>(std::bit_width(kMaxImageExtent));
    } else if (r.mips != 0) {
        g.mips = static_cast<uint16_t>(r.mips);
    } else {  // a full chain of a fixed extent
        g.mips = static_cast<uint16_t>(std::bit_width(std::max(r.extent.width, r.extent.height)));
    }
    return g;
}

}  // namespace

// ---- at load time -------------------------------------------------------------------------

void checkReadsHaveSourcesAtLoad(const GraphDesc& graph, Diagnostics& out) {
    std::vector<LoadGrid> grids;
    grids.reserve(graph.resources.size());
    size_t cells = 0;
    for (const ResourceDesc& r : graph.resources) {
        LoadGrid& g = grids.emplace_back(loadGrid(r));
        const size_t n = size_t(g.mips) * g.layers;
        if (n > kMaxSubresources - cells) throw GraphError(tooManySubresources(graph, r));
        g.firstCell = static_cast<uint32_t>(cells);
        cells += n;
    }
    // Per subresource, from when its contents are held: 0 never yet, 1 from the frame's start,
    // p + 2 from pass p's write on. A read in pass p is sourced by what holds before p + 2 (a
    // pass's reads see earlier passes' writes, not its own), as GraphIndex checks it.
    std::vector<uint32_t> heldFrom(cells, 0);
    for (size_t i = 0; i < graph.resources.size(); ++i) {
        const ResourceDesc& r = graph.resources[i];
        if (r.clear || r.external)
            std::fill_n(heldFrom.begin() + static_cast<std::ptrdiff_t>(grids[i].firstCell),
                        size_t(grids[i].mips) * grids[i].layers, 1u);
    }
    auto forEachCell = [&](const LoadGrid& g, const SubresourceRange& range, auto&& f) {
        for (uint32_t m = range.baseMip; m < range.baseMip + range.mipCount; ++m)
            for (uint32_t l = range.baseLayer; l < range.baseLayer + range.layerCount; ++l)
                f(heldFrom[g.firstCell + size_t(m) * g.layers + l]);
    };
    for (size_t p = 0; p < graph.passes.size(); ++p) {
        const auto stamp = static_cast<uint32_t>(p + 2);
        const auto& uses = graph.passes[p].uses;
        for (size_t k = 0; k < uses.size(); ++k) {
            const UsageDecl& u = uses[k];
            const LoadGrid& g = grids[u.resource];
            SubresourceRange range = u.usage.range.value_or(SubresourceRange{0, g.mips, 0, g.layers});
            // The loader keeps a range's first level inside the grid, and clips nothing else.
            range.mipCount = std::min<uint32_t>(range.mipCount, g.mips - range.baseMip);
            if (readsContents(u.usage.access)) {
                SubresourceRange read = range;
                if (g.chainOfOutput) read.mipCount = 1;
                size_t missing = 0, cellsRead = 0;
                forEachCell(g, read, [&](uint32_t held) {
                    missing += held - 1 >= stamp - 1;  // 0 wraps
                    ++cellsRead;
                });
                const auto unheld = [&](uint32_t m, uint32_t l) {
                    return heldFrom[g.firstCell + size_t(m) * g.layers + l] - 1 >= stamp - 1;
                };
                if (missing == cellsRead)
                    out.add(unsourcedRead(graph, p, k, ""));
                else if (missing > 0)
                    out.add(unsourcedRead(graph, p, k, "", describeUnwritten(read, unheld)));
            }
            if (writesContents(u.usage.access))
                forEachCell(g, range, [&](uint32_t& held) { if (held == 0) held = stamp; });
        }
    }
    // An output hands on all of itself: a part that no pass writes would leave the frame
    // undefined. (One that no pass writes any part of is named elsewhere: unused, or read
    // unsourced. A full chain of an output-relative image is checked at its first level.)
    for (size_t i = 0; i < graph.resources.size(); ++i) {
        const ResourceDesc& r = graph.resources[i];
        if (!r.isExported() || r.external || r.clear || !r.isImage()) continue;
        const LoadGrid& g = grids[i];
        const SubresourceRange exported{0, g.chainOfOutput ? 1u : g.mips, 0, g.layers};
        const auto unwritten = [&](uint32_t m, uint32_t l) {
            return heldFrom[g.firstCell + size_t(m) * g.layers + l] == 0;
        };
        size_t missing = 0, writtenAnywhere = 0;
        for (uint32_t m = 0; m < g.mips; ++m)
            for (uint32_t l = 0; l < g.layers; ++l) {
                writtenAnywhere += !unwritten(m, l);
                missing += m < exported.mipCount && unwritten(m, l);
            }
        if (missing == 0 || writtenAnywhere == 0) continue;
        out.add({graph.file, r.jsonPath() + ".final", "", r.name,
                 unwrittenOutput(r.name, "pass", describeUnwritten(exported, unwritten))});
    }
}

// ---- compile() ---------------------------------------------------------------------------

void checkOutputNames(const GraphDesc& graph, const CompileOptions& options) {
    Diagnostics diags;
    // The state a presented image is left in instead: None would end it in UNDEFINED.
    if (options.presentReplacement == ExternalState::None)
        diags.add({graph.file, "", "", "",
                   "CompileOptions::presentReplacement must be a state to leave the image in (Present, TransferSrc, "
                   "ShaderRead or General), not None"});
    // A code-built GraphDesc may hold two resources of one name (the loader refuses them):
    // each option naming it would pick one of them, not necessarily the same.
    std::set<std::string_view> named;
    if (options.outputs) named.insert(options.outputs->begin(), options.outputs->end());
    for (const auto& [name, state] : options.exports) named.insert(name);
    named.insert(options.readbacks.begin(), options.readbacks.end());
    for (const std::string_view name : named) {
        const auto same = std::count_if(graph.resources.begin(), graph.resources.end(),
                                        [&](const ResourceDesc& r) { return r.name == name; });
        if (same > 1)
            diags.add({graph.file, "resources", "", std::string(name),
                       std::to_string(same) + " resources are named '" + std::string(name) +
                           "': the options that name it cannot tell which"});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    if (options.outputs)
        for (const std::string& name : *options.outputs) {
            const ResourceDesc* r = graph.findResource(name);
            if (!r)
                diags.add({graph.file, "resources", "", name,
                           "cannot keep '" + name + "' as an output: no such resource"});
            // Keeping only names that are no export would cull every pass, without a word.
            else if (!r->isExported() && !options.exports.count(name) && !options.readbacks.count(name))
                diags.add({graph.file, r->jsonPath(), "", name,
                           "cannot keep '" + name + "' as an output: it is not exported (no `final`, and not in "
                           "CompileOptions::exports or readbacks)"});
        }
    for (const auto& [name, state] : options.exports)
        if (!graph.findResource(name))
            diags.add({graph.file, "resources", "", name, "cannot export '" + name + "': no such resource"});
        // None would leave it unexported, and outputs naming it would cull its writers silently.
        else if (state == ExternalState::None || state > ExternalState::General)
            diags.add({graph.file, graph.findResource(name)->jsonPath(), "", name,
                       "cannot export '" + name + "' in state " +
                           (state == ExternalState::None ? std::string("None") : std::to_string(int(state))) +
                           ": CompileOptions::exports gives the state to leave it in (Present, TransferSrc, "
                           "ShaderRead or General)"});
    for (const std::string& name : options.readbacks) {
        const ResourceDesc* r = graph.findResource(name);
        if (!r)
            diags.add({graph.file, "resources", "", name, "cannot read back '" + name + "': no such resource"});
        else if (!r->isImage())
            diags.add({graph.file, r->jsonPath(), "", name,
                       "cannot read back '" + name + "': it is a buffer; read-backs copy images"});
        // Exported Present it would be presented; left TransferSrc, the next frame would not
        // find it as presented.
        else if (r->external && r->initial == ExternalState::Present && !r->isExported() &&
                 options.presentReplacement == ExternalState::Present)
            diags.add({graph.file, r->jsonPath() + ".initial", "", name,
                       "cannot read back '" + name + "': it arrives as presented and is not exported, so the next "
                       "frame must find it in PRESENT_SRC_KHR; read it back in a plan that replaces Present "
                       "(CompileOptions::presentReplacement, as headless rendering does)"});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
}

void checkReadbacksHaveSources(const GraphIndex& index, const Schedule& schedule, const CompileOptions& options) {
    const GraphDesc& graph = index.graph();
    Diagnostics diags;
    for (const std::string& name : options.readbacks) {
        const ResourceDesc* r = graph.findResource(name);
        const auto d = static_cast<uint32_t>(r - graph.resources.data());
        // The read-back copies mip 0 of layer 0: a write of other subresources leaves it undefined.
        bool source = r->external || r->clear.has_value(), anyWrite = false;
        for (size_t s = 0; s < schedule.passes.size() && !source; ++s)
            for (const IndexedUsage& u : index.usesOf(schedule.passes[s])) {
                if (u.resource != d || !writesContents(u.usage.access)) continue;
                anyWrite = true;
                const SubresourceRange range = index.range(u);
                source = source || (range.baseMip == 0 && range.baseLayer == 0);
            }
        if (!source)
            diags.add({graph.file, r->jsonPath(), "", name,
                       "cannot read back '" + name + "': " +
                           (anyWrite ? std::string("it copies mip 0 of layer 0, which no pass that runs writes")
                                     : std::string("no pass that runs writes it")) +
                           ", and it is neither external nor `clear`"});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
}

/// A pass renders into one framebuffer, whose size and layer count its attachments share: a
/// larger attachment would be cropped, one of fewer layers is invalid Vulkan. Output-relative
/// and fixed extents, and mips, meet only at an output size, so compile() checks it, for the
/// passes that run (the index finds them in its walk).
static void checkAttachmentShapes(const GraphIndex& index, uint32_t width, uint32_t height, Diagnostics& diags) {
    const GraphDesc& graph = index.graph();
    const auto describe = [&](const IndexedUsage& u) {
        const GraphIndex::AttachmentShape s = index.attachmentShape(u);
        return "'" + graph.resources[u.resource].name + "' " + std::to_string(s.width) + "x" + std::to_string(s.height) +
               " (" + std::to_string(s.layers) + (s.layers == 1 ? " layer)" : " layers)");
    };
    for (const auto& [p, k] : index.misshapenAttachments()) {
        const IndexedUsage& u = index.use(k);
        const auto uses = index.usesOf(p);
        const IndexedUsage& first = *std::find_if(uses.begin(), uses.end(), [](const IndexedUsage& x) {
            return isAttachmentStage(x.usage.stage);
        });
        diags.add({graph.file, index.jsonPathOf(p, u), graph.passes[p].name, graph.resources[u.resource].name,
                   "its attachments differ in shape: " + describe(first) + " and " + describe(u) + " at output " +
                       std::to_string(width) + "x" + std::to_string(height) +
                       "; a pass renders into attachments of one size and layer count"});
    }
}

static std::vector<std::string> declaredFeatures(const GraphDesc& graph) {
    std::vector<std::string> names;
    for (const auto& f : graph.features) names.push_back(f.name);
    return names;
}

FeatureValues checkedFeatures(const GraphDesc& graph, const CompileOptions& options, Diagnostics& out) {
    FeatureValues features = graph.defaultFeatures();
    for (const auto& [name, value] : options.features) {
        if (!features.count(name)) {
            out.add({graph.file, "features", "", "",
                     "unknown feature '" + name + "'; the graph declares: " + joinNames(declaredFeatures(graph))});
            continue;
        }
        features[name] = value;
    }
    if (options.outputWidth == 0 || options.outputHeight == 0)
        out.add({graph.file, "", "", "", "the output extent must not be zero"});
    // Past it, output-sized images would be too (and their byte counts wrap).
    else if (options.outputWidth > kMaxImageExtent || options.outputHeight > kMaxImageExtent)
        out.add({graph.file, "", "", "",
                 "the output extent " + std::to_string(options.outputWidth) + "x" +
                     std::to_string(options.outputHeight) + " is past " + std::to_string(kMaxImageExtent) +
                     " a side, the largest extent a graph's image takes"});
    return features;
}

void validate(const GraphIndex& index, const FeatureValues& features, const CompileOptions& options,
              Diagnostics diags) {
    const GraphDesc& graph = index.graph();
    const uint32_t width = options.outputWidth, height = options.outputHeight;
    // Enums the compile reads once: a value outside them would pick no branch of its switches.
    const auto outside = [&](std::string_view what, int value) {
        diags.add({graph.file, "", "", "", std::string(what) + " (" + std::to_string(value) + ") is not a value of its enum"});
    };
    if (graph.layouts > LayoutPolicy::Optimal) outside("the graph's layouts", int(graph.layouts));
    if (options.layouts && *options.layouts > LayoutPolicy::Optimal)
        outside("CompileOptions::layouts", int(*options.layouts));
    if (options.presentReplacement > ExternalState::General)
        outside("CompileOptions::presentReplacement", int(options.presentReplacement));
    if (options.placement > MemoryStrategy::Unaliased) outside("CompileOptions::placement", int(options.placement));
    if (!diags.empty()) throw GraphError(std::move(diags));
    // A GraphDesc built in code can name a resource or a slot that is not there: every sweep
    // would index past its tables.
    for (const auto& [pass, k] : index.invalidUses()) {
        const IndexedUsage& iu = index.use(k);
        const SlotId slot = index.declOf(pass, iu).slot;
        diags.add({graph.file, index.jsonPathOf(pass, iu), graph.passes[pass].name, "",
                   iu.resource >= graph.resources.size()
                       ? "names resource index " + std::to_string(iu.resource) + ", but the graph has " +
                             std::to_string(graph.resources.size()) + " resource(s)"
                       : "names slot id " + std::to_string(slot) + ", but the graph has " +
                             std::to_string(graph.slotNames.size()) + " slot name(s)"});
    }
    if (!index.invalidUses().empty()) throw GraphError(std::move(diags));
    // What the loader refuses of a file's passes, for a GraphDesc built in code: a queue
    // outside its enum (it would index past the schedule's tables), a queue that cannot
    // perform a usage, a condition naming no declared feature (its pass would be culled
    // without a word).
    for (const uint32_t i : index.offGraphicsOrConditional()) {
        const PassDesc& p = graph.passes[i];
        const std::string path = p.jsonPath.empty() ? "passes[" + std::to_string(i) + "]" : p.jsonPath;
        for (const std::string& name : p.condition.features())
            if (!features.count(name))
                diags.add({graph.file, path + ".if", p.name, "",
                           "unknown feature '" + name + "'; the graph declares: " + joinNames(declaredFeatures(graph))});
        if (size_t(p.queue) >= kQueueKinds) {
            diags.add({graph.file, path + ".queue", p.name, "",
                       "its queue (" + std::to_string(int(p.queue)) + ") is not a value of its enum"});
            continue;
        }
        if (p.queue == QueueKind::Graphics) continue;  // it performs every usage
        for (const UsageDecl& u : p.uses)
            if (std::string problem = queueProblem(p.queue, graph.resources[u.resource], u.usage); !problem.empty())
                diags.add({graph.file, path + ".queue", p.name, graph.resources[u.resource].name, std::move(problem)});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    // The loader refuses these in a file with the same words.
    for (const auto& [pass, k] : index.misfitUses()) {
        const IndexedUsage& iu = index.use(k);
        const ResourceDesc& r = graph.resources[iu.resource];
        diags.add({graph.file, index.jsonPathOf(pass, iu), graph.passes[pass].name, r.name,
                   usageProblem(r, index.declOf(pass, iu).usage)});
    }
    if (!index.misfitUses().empty()) throw GraphError(std::move(diags));
    for (const auto& [pass, k] : index.overfullAttachments()) {
        const IndexedUsage& iu = index.use(k);
        const auto uses = index.usesOf(pass);
        std::string problem;
        if (iu.usage.stage == Stage::DepthAttachment) {
            const IndexedUsage& depth = *std::find_if(uses.begin(), uses.end(), [](const IndexedUsage& x) {
                return x.usage.stage == Stage::DepthAttachment;
            });
            problem = secondDepthAttachmentProblem(index.jsonPathOf(pass, depth));
        } else {
            problem = extraColorAttachmentProblem(kMaxColorAttachments + 1);
        }
        diags.add({graph.file, index.jsonPathOf(pass, iu), graph.passes[pass].name, graph.resources[iu.resource].name,
                   std::move(problem)});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    // Mip counts of output-relative images can only be checked against a real output size,
    // and those of a GraphDesc built in code have not been through the loader. The index
    // finds them (and the ranged usages below) in the walks it makes anyway.
    // Only those a pass that runs uses: the others are never created (a chain too long for
    // the output may belong to a feature that is off).
    std::vector<uint8_t> usedByActive;
    if (!index.tooManyMips().empty()) {
        usedByActive.resize(graph.resources.size());
        for (size_t p = 0; p < graph.passes.size(); ++p)
            if (index.active(p))
                for (const IndexedUsage& u : index.usesOf(p)) usedByActive[u.resource] = 1;
    }
    for (const uint32_t i : index.tooManyMips()) {
        if (!usedByActive[i]) continue;
        const ResourceDesc& r = graph.resources[i];
        const auto [w, h] = r.extent.resolve(width, height);
        const auto most = static_cast<uint32_t>(std::bit_width(std::max(w, h)));
        diags.add({graph.file, r.jsonPath() + ".mips", "", r.name,
                   std::to_string(r.mips) + " levels is more than a " + std::to_string(w) + "x" +
                       std::to_string(h) + " image has (" + std::to_string(most) + ")" +
                       (r.extent.relativeToOutput
                            ? " at output " + std::to_string(width) + "x" + std::to_string(height)
                            : std::string())});
    }
    // Ranges are checked against the chain the output size resolves (and against extents an
    // embedder may have changed after loading): a range that starts past the last level, or
    // names layers the image lacks, is an error here, not a plan that fails at run time. One
    // that runs past the end of a chain is clipped to it: the loader gives a `layers`-only
    // usage of a full output-sized chain every level the largest image could have.
    // Images are checked against the index's grids; the graph's own (cold) records are read
    // only to word a diagnostic.
    for (const auto& [pass, k] : index.rangedUses()) {
        const IndexedUsage& iu = index.use(k);
        // As the loader says of a file's `mips` or `layers` on a buffer.
        if (!index.aspects(iu.resource).image) {
            diags.add({graph.file, index.jsonPathOf(pass, iu), graph.passes[pass].name,
                       graph.resources[iu.resource].name, "buffers have no mips or layers: a usage takes all of one"});
            continue;
        }
        const SubresourceGrid& grid = index.grid(iu.resource);
        const uint32_t levels = grid.mips, layers = grid.layers;
        const SubresourceRange& range = *index.writtenRange(iu);
        // The loader never writes an empty range; a GraphDesc built in code can, and every
        // sweep assumes a usage touches at least one subresource.
        const bool empty = range.mipCount == 0 || range.layerCount == 0;
        const bool mipsFit = range.baseMip < levels;
        const bool layersFit = uint64_t(range.baseLayer) + range.layerCount <= layers;
        if (!empty && mipsFit && layersFit) continue;
        const ResourceDesc& res = graph.resources[iu.resource];
        const PassDesc& p = graph.passes[pass];
        const auto [w, h] = res.extent.resolve(width, height);
        // The key that holds the range, as the loader's range errors name it.
        const bool mipsAtFault = empty ? range.mipCount == 0 : !mipsFit;
        diags.add({graph.file, index.jsonPathOf(pass, iu) + (mipsAtFault ? ".mips" : ".layers"), p.name, res.name,
                   empty    ? "uses an empty range (" + std::to_string(range.mipCount) + " mip(s), " +
                                  std::to_string(range.layerCount) + " layer(s)): a usage must touch a subresource"
                   : !mipsFit ? "uses mips [" + std::to_string(range.baseMip) + ", " +
                                  std::to_string(range.mipCount) + "] but the " + std::to_string(w) + "x" +
                                  std::to_string(h) + " image has " + std::to_string(levels) + " mip level(s)"
                            : "uses layers [" + std::to_string(range.baseLayer) + ", " +
                                  std::to_string(range.layerCount) + "] but the image has " +
                                  std::to_string(res.layers) + " layer(s)"});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    checkAttachmentShapes(index, width, height, diags);
    if (!diags.empty()) throw GraphError(std::move(diags));
    // Reads with no source at this size and these features, found in the index's walk.
    for (const auto& [p, k] : index.unsourcedReads()) {
        const IndexedUsage& u = index.use(k);
        const size_t use = static_cast<size_t>(&u - index.usesOf(p).data());
        diags.add(unsourcedRead(graph, p, use, switchedOffWriter(index, features, p, u.resource),
                                unwrittenBefore(index, p, u)));
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    // Outputs with a part no active pass writes (the loader checks them with every pass on).
    // A read-back copies mip 0 of layer 0 alone, which checkReadbacksHaveSources words.
    for (const uint32_t r : index.unwrittenOutputs()) {
        const ResourceDesc& d = graph.resources[r];
        if (options.readbacks.count(d.name)) continue;
        const SubresourceGrid& grid = index.grid(r);
        const std::vector<uint8_t> held = heldBefore(index, graph.passes.size(), r);
        const bool none = std::find(held.begin(), held.end(), 1) == held.end();
        const std::string part =
            none ? "" : describeUnwritten(grid.whole(), [&](uint32_t m, uint32_t l) { return !held[grid.index(m, l)]; });
        diags.add({graph.file, d.jsonPath() + ".final", "", d.name,
                   unwrittenOutput(d.name, "pass that runs with these features", part) +
                       switchedOffWriter(index, features, graph.passes.size(), r)});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
}

}  // namespace skygraph
