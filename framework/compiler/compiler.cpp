#include "plan_builder.hpp"
#include "scheduler.hpp"
#include "synchronizer.hpp"

#include <skygraph/compiler.hpp>

#include <algorithm>
#include <bit>

namespace skygraph {

namespace {

/// A copy of `graph` with `outputs` and `exports` applied, or a diagnostic per unknown name.
GraphDesc withExports(const GraphDesc& graph, const CompileOptions& options) {
    GraphDesc copy = graph;
    Diagnostics diags;
    if (options.outputs) {
        for (const std::string& name : *options.outputs)
            if (!graph.findResource(name))
                diags.add({graph.file, "resources", "", name, "cannot keep '" + name + "' as an output: no such resource"});
        for (ResourceDesc& r : copy.resources)
            if (!options.outputs->count(r.name)) r.final = ExternalState::None;
    }
    for (const auto& [name, state] : options.exports) {
        // A plain reference: clang 14 (the fuzz build) cannot capture structured bindings.
        const std::string& wanted = name;
        auto it = std::find_if(copy.resources.begin(), copy.resources.end(),
                               [&](const ResourceDesc& r) { return r.name == wanted; });
        if (it == copy.resources.end()) {
            diags.add({graph.file, "resources", "", name, "cannot export '" + name + "': no such resource"});
        } else if (!it->isExported()) {
            it->final = state;
        }
    }
    for (const std::string& name : options.readbacks) {
        auto it = std::find_if(copy.resources.begin(), copy.resources.end(),
                               [&](const ResourceDesc& r) { return r.name == name; });
        if (it == copy.resources.end())
            diags.add({graph.file, "resources", "", name, "cannot read back '" + name + "': no such resource"});
        else if (!it->isImage())
            diags.add({graph.file, it->jsonPath(), "", name,
                       "cannot read back '" + name + "': it is a buffer; read-backs copy images"});
        else if (!it->isExported())
            it->final = ExternalState::TransferSrc;
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    return copy;
}

/// A read-back of an image that no scheduled pass writes, that is neither external nor
/// `clear`, would copy undefined contents.
void checkReadbacksHaveSources(const GraphIndex& index, const Schedule& schedule, const CompileOptions& options,
                               Diagnostics& diags) {
    const GraphDesc& graph = index.graph();
    for (const std::string& name : options.readbacks) {
        const ResourceDesc* r = graph.findResource(name);
        const auto d = static_cast<uint32_t>(r - graph.resources.data());
        bool source = r->external || r->clear.has_value();
        for (size_t s = 0; s < schedule.passes.size() && !source; ++s)
            for (const IndexedUsage& u : index.usesOf(schedule.passes[s]))
                source = source || (u.resource == d && writesContents(u.usage.access));
        if (!source)
            diags.add({graph.file, r->jsonPath(), "", name,
                       "cannot read back '" + name + "': no pass that runs writes it, and it is neither external nor `clear`"});
    }
}

}  // namespace

namespace {
/// compile() once the options' exports, outputs and read-backs are in the graph.
Plan compileExported(const GraphDesc& graph, const CompileOptions& options);
}  // namespace

Plan compile(const GraphDesc& graph, const CompileOptions& options) {
    if (!options.exports.empty() || options.outputs || !options.readbacks.empty()) {
        CompileOptions rest = options;
        rest.exports.clear();
        rest.outputs.reset();
        rest.readbacks.clear();
        const GraphDesc exported = withExports(graph, options);
        rest.readbacks = options.readbacks;  // exported now: compile() takes them as they are
        return compileExported(exported, rest);
    }
    return compileExported(graph, options);
}

namespace {
Plan compileExported(const GraphDesc& graph, const CompileOptions& options) {
    Diagnostics diags;
    FeatureValues features = graph.defaultFeatures();
    for (const auto& [name, value] : options.features) {
        if (!features.count(name)) {
            std::string known;
            for (const auto& f : graph.features) known += (known.empty() ? "" : ", ") + f.name;
            diags.add({graph.file, "features", "", "",
                       "unknown feature '" + name + "'; the graph declares: " +
                           (known.empty() ? "none" : known)});
            continue;
        }
        features[name] = value;
    }
    if (options.outputWidth == 0 || options.outputHeight == 0)
        diags.add({graph.file, "", "", "", "the output extent must not be zero"});
    // Mip counts of output-relative images can only be checked against a real output size.
    // The index finds them (and the ranged usages below) in the walks it makes anyway.
    const GraphIndex index(graph, features, options.outputWidth, options.outputHeight);
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
    for (const uint32_t i : index.tooManyMips()) {
        const ResourceDesc& r = graph.resources[i];
        const auto [w, h] = r.extent.resolve(options.outputWidth, options.outputHeight);
        const auto most = static_cast<uint32_t>(std::bit_width(std::max(w, h)));
        diags.add({graph.file, r.jsonPath() + ".mips", "", r.name,
                   std::to_string(r.mips) + " levels is more than a " + std::to_string(w) + "x" +
                       std::to_string(h) + " image has (" + std::to_string(most) + ") at output " +
                       std::to_string(options.outputWidth) + "x" + std::to_string(options.outputHeight)});
    }
    // Ranges are checked against the chain the output size resolves (and against extents an
    // embedder may have changed after loading): a range that starts past the last level, or
    // names layers the image lacks, is an error here, not a plan that fails at run time. One
    // that runs past the end of a chain is clipped to it: the loader gives a `layers`-only
    // usage of a full output-sized chain every level the largest image could have.
    // Images are checked against the index's grids; the graph's own (cold) records are read
    // for buffers and to word a diagnostic.
    for (const auto& [pass, k] : index.rangedUses()) {
        const IndexedUsage& iu = index.use(k);
        const bool image = index.aspects(iu.resource).image;
        const SubresourceGrid& grid = index.grid(iu.resource);
        const ResourceDesc* r = image ? nullptr : &graph.resources[iu.resource];
        const uint32_t levels = std::max(1u, r ? r->mipCount(options.outputWidth, options.outputHeight) : grid.mips);
        const uint32_t layers = std::max(1u, r ? r->layers : grid.layers);
        const SubresourceRange& range = *index.writtenRange(iu);
        // The loader never writes an empty range; a GraphDesc built in code can, and every
        // sweep assumes a usage touches at least one subresource.
        const bool empty = range.mipCount == 0 || range.layerCount == 0;
        const bool mipsFit = range.baseMip < levels;
        const bool layersFit = uint64_t(range.baseLayer) + range.layerCount <= layers;
        if (!empty && mipsFit && layersFit) continue;
        const ResourceDesc& res = graph.resources[iu.resource];
        const PassDesc& p = graph.passes[pass];
        const auto [w, h] = res.extent.resolve(options.outputWidth, options.outputHeight);
        diags.add({graph.file, index.jsonPathOf(pass, iu), p.name, res.name,
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

    checkReadsHaveSources(index, features, diags);
    if (!diags.empty()) throw GraphError(std::move(diags));

    Schedule schedule = schedulePasses(index, features, options.cull);
    checkReadbacksHaveSources(index, schedule, options, diags);
    if (!diags.empty()) throw GraphError(std::move(diags));
    Plan plan = synchronize(index, schedule, options);
    detail::PlanBuilder::features(plan) = std::move(features);
    detail::PlanBuilder::setOutputExtent(plan, options.outputWidth, options.outputHeight);
    detail::PlanBuilder::culled(plan) = std::move(schedule.culled);
    return plan;
}

}  // namespace

}  // namespace skygraph
