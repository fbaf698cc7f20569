// planSetup and planImageRead: short plans around a frame's, built step by step with the
// synchronizer's own per-subresource rules (barrier_rules.hpp). Each resource's steps touch
// only that resource, so one state per resource is enough: every step covers the whole
// resource or a part of it that the previous step wrote as a whole.
#include "format_table.hpp"
#include "barrier_rules.hpp"
#include "graph_file.hpp"
#include "plan_builder.hpp"
#include "vulkan_state.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/transfer_plans.hpp>

#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {
namespace {

using namespace sync;

constexpr Usage kTransferWrite{Access::Write, Stage::Transfer, BindAs::Default, std::nullopt};
constexpr Usage kTransferRead{Access::Read, Stage::Transfer, BindAs::Default, std::nullopt};

/// Collects steps, then lays them out in a Plan's storage in one go (its spans view arrays
/// that must not move once set).
class StepListBuilder {
public:
    explicit StepListBuilder(const Plan& frame) {
        detail::PlanBuilder::graph(plan_) = frame.graph();
        detail::PlanBuilder::features(plan_) = frame.features();
        detail::PlanBuilder::setOutputExtent(plan_, frame.outputWidth(), frame.outputHeight());
        detail::PlanBuilder::shareNames(plan_, frame);
    }

    /// Adds `frameResource` of `frame` to the plan, starting in `initialLayout`; returns its
    /// index here.
    uint32_t addResource(const PlannedResource& frameResource, VkImageLayout initialLayout) {
        PlannedResource r = frameResource;
        r.firstPass = static_cast<uint32_t>(steps_.size());
        r.initialLayout = initialLayout;
        resources().push_back(r);
        return static_cast<uint32_t>(resources().size() - 1);
    }

    /// What a step does to one part of a resource, and that part's state, which it advances.
    struct StepAccess {
        const Usage& usage;
        SubresourceRange range;
        SubresourceState& state;
    };

    /// Adds a step of `type` named "<verb><resource name><suffix>" that performs `accesses` on
    /// resource `r` (the first is what the step writes, for the executor), with the barrier
    /// each needs.
    void addStep(std::string_view verb, std::string_view type, uint32_t r, const ResourceDesc& desc,
                 std::initializer_list<StepAccess> accesses, std::string_view suffix = {}) {
        Step step;
        step.nameOffset = text_.size();
        text_ += verb;
        text_ += resources()[r].name;
        text_ += suffix;
        step.nameLength = text_.size() - step.nameOffset;
        step.type = type;
        for (const StepAccess& a : accesses) {
            const VulkanScope need = vulkanScope(desc, a.usage);
            const bool write = writesContents(a.usage.access);
            PlannedUsage& u = step.usages.emplace_back();
            u.stages = need.stages;
            u.access = need.access;
            u.range = a.range;
            u.resource = r;
            u.layout = need.layout;
            u.usage = a.usage.mode();
            Barrier b;
            if (barrierInto(b, a.state, need, need.layout, write, a.usage.access == Access::Write,
                            [&] { return StageAccess{need.stages, need.access}; })) {
                b.resource = r;
                b.kind = desc.isImage() ? BarrierKind::Image : BarrierKind::Buffer;
                b.range = a.range;
                step.barriers.push_back(b);
            }
            recordAccess(a.state, write, need.layout, need);
        }
        resources()[r].lastPass = static_cast<uint32_t>(steps_.size());
        steps_.push_back(std::move(step));
    }

    /// The barrier that hands resource `r` from `state` to what comes after the plan: `target`
    /// layout, visible to `scope`.
    void addFinal(uint32_t r, const ResourceDesc& desc, SubresourceState& state, const VulkanScope& scope,
                  VkImageLayout target, const SubresourceRange& whole) {
        const bool nextUseWrites = writeBits(scope.access) != 0;
        if (auto b = barrierFor(state, scope, target, nextUseWrites, false,
                                [&] { return StageAccess{scope.stages, scope.access}; })) {
            b->resource = r;
            b->kind = desc.isImage() ? BarrierKind::Image : BarrierKind::Buffer;
            b->range = whole;
            detail::PlanBuilder::finalBarriers(plan_).push_back(*b);
        }
        resources()[r].finalLayout = desc.isImage() ? target : VK_IMAGE_LAYOUT_UNDEFINED;
    }

    /// The host reads what the steps copied out once the plan's fence has signalled.
    void addHostRead(uint32_t r) { detail::PlanBuilder::finalBarriers(plan_).push_back(hostReadAfterCopy(r)); }

    Plan finish() && {
        auto& usages = detail::PlanBuilder::usages(plan_);
        auto& barriers = detail::PlanBuilder::barriers(plan_);
        auto& passes = detail::PlanBuilder::passes(plan_);
        size_t usageCount = 0, barrierCount = 0;
        for (const Step& step : steps_) {
            usageCount += step.usages.size();
            barrierCount += step.barriers.size();
        }
        usages.reserve(usageCount);  // the spans below must not move
        barriers.reserve(barrierCount);
        passes.reserve(steps_.size());
        auto names = std::make_shared<const std::string>(std::move(text_));
        for (const Step& step : steps_) {
            PlannedPass& p = passes.emplace_back();
            p.name = std::string_view(*names).substr(step.nameOffset, step.nameLength);
            p.type = step.type;
            const size_t firstUsage = usages.size(), firstBarrier = barriers.size();
            usages.insert(usages.end(), step.usages.begin(), step.usages.end());
            p.usages = {usages.data() + firstUsage, step.usages.size()};
            if (!step.barriers.empty()) {
                barriers.insert(barriers.end(), step.barriers.begin(), step.barriers.end());
                p.barriers = {barriers.data() + firstBarrier, step.barriers.size()};
            }
        }
        detail::PlanBuilder::keepNames(plan_, std::move(names));
        detail::PlanBuilder::singleSubmit(plan_);
        return std::move(plan_);
    }

private:
    std::vector<PlannedResource>& resources() noexcept { return detail::PlanBuilder::resources(plan_); }

    struct Step {
        size_t nameOffset = 0, nameLength = 0;
        std::string_view type;  // a literal
        std::vector<PlannedUsage> usages;
        std::vector<Barrier> barriers;
    };
    Plan plan_;
    std::string text_;
    std::vector<Step> steps_;
};

SubresourceRange wholeOf(const ResourceDesc& d, const Plan& frame) {
    if (!d.isImage()) return {};
    return {0, std::max(1u, d.mipCount(frame.outputWidth(), frame.outputHeight())), 0, std::max(1u, d.layers)};
}

/// Where the frame first uses each subresource of resource `r` (declared as `d`): the scopes of
/// those uses together, which is where the frame expects a General resource's contents to be
/// visible when it starts (the synchronizer's boundary scope). A later pass's first use of
/// another mip or layer counts as much as the first pass's.
VulkanScope firstUsesScope(const Plan& frame, uint32_t r, const ResourceDesc& d) {
    VulkanScope scope;
    const std::span<const PlannedPass> passes = frame.passes();
    const PlannedResource& res = frame.resources()[r];
    if (res.firstPass >= passes.size() || res.lastPass >= passes.size() || res.firstPass > res.lastPass)
        throw std::out_of_range("a plan resource's lifetime is not in the plan");
    const SubresourceRange whole = wholeOf(d, frame);
    const size_t layers = whole.layerCount;
    std::vector<bool> seen(d.isImage() ? size_t(whole.mipCount) * layers : 1, false);
    size_t unseen = seen.size();
    for (uint32_t p = res.firstPass; p <= res.lastPass && unseen > 0; ++p)
        for (const PlannedUsage& u : passes[p].usages) {
            if (u.resource != r) continue;
            bool first = false;
            const auto mark = [&](size_t cell) {
                if (cell >= seen.size() || seen[cell]) return;
                seen[cell] = true;
                first = true;
                --unseen;
            };
            if (!d.isImage()) mark(0);
            for (uint32_t m = u.range.baseMip; d.isImage() && m < u.range.baseMip + u.range.mipCount; ++m)
                for (uint32_t l = u.range.baseLayer; l < u.range.baseLayer + u.range.layerCount; ++l)
                    mark(size_t(m) * layers + l);
            if (!first) continue;
            scope.stages |= u.stages;
            scope.access |= u.access;
        }
    return scope;
}

/// The state the frame takes `d` to arrive in: its `initial`, unless that is Present and the
/// plan was compiled to replace Present (CompileOptions::presentReplacement), as its layout says.
ExternalState arrivesIn(const PlannedResource& res, const ResourceDesc& d) {
    if (d.initial != ExternalState::Present || res.initialLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR) return d.initial;
    switch (res.initialLayout) {
        case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return ExternalState::TransferSrc;
        case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return ExternalState::ShaderRead;
        case VK_IMAGE_LAYOUT_GENERAL: return ExternalState::General;
        default: return ExternalState::None;
    }
}

/// What the frame expects of an external resource when it starts: the documented scope of its
/// `initial` state, or, where that names no stages (a buffer that arrives in no particular
/// state, or General, the graph's own state), its first use.
VulkanScope frameStartScope(const Plan& frame, uint32_t r, const ResourceDesc& d) {
    VulkanScope scope = externalScope(d, arrivesIn(frame.resources()[r], d));
    if (scope.stages == 0 || d.initial == ExternalState::General) {
        const VulkanScope first = firstUsesScope(frame, r, d);
        scope.stages = first.stages;
        scope.access = first.access;
    }
    scope.layout = frame.resources()[r].initialLayout;
    return scope;
}

void checkUploads(const GraphDesc& graph, const SetupOptions& options) {
    Diagnostics diags;
    for (const std::string& name : options.uploads) {
        const ResourceDesc* d = graph.findResource(name);
        std::string problem;
        if (!d) problem = "no such resource";
        else if (!d->external) problem = "it is not external: the graph itself writes it";
        else if (!d->isImage()) problem = "it is a buffer; uploads fill images";
        else if (d->initial == ExternalState::None)
            problem = "its `initial` state is None, so every frame discards its contents";
        else if (options.imports.count(name)) problem = "it is imported from another renderer";
        if (!problem.empty())
            diags.add({graph.file, d ? d->jsonPath() : "resources", "", name, "cannot upload '" + name + "': " + problem});
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
}

/// Throws unless each of `frame`'s resources names a resource of `graph` by its decl: the
/// graph it was compiled from, which the plan's records index.
void checkCompiledFrom(const GraphDesc& graph, const Plan& frame) {
    for (const PlannedResource& res : frame.resources())
        if (res.decl >= graph.resources.size() || graph.resources[res.decl].name != res.name) {
            Diagnostics diags;
            diags.add({graph.file, "resources", "", std::string(res.name),
                       "the plan of graph '" + frame.graph() + "' was not compiled from this graph ('" + graph.name +
                           "'): its resource '" + std::string(res.name) + "' is not resource " +
                           std::to_string(res.decl) + " here"});
            throw GraphError(std::move(diags));
        }
}

}  // namespace

Plan planSetup(const GraphDesc& graph, const Plan& frame, const SetupOptions& options) {
    checkCompiledFrom(graph, frame);
    checkUploads(graph, options);
    StepListBuilder steps(frame);
    for (uint32_t fr = 0; fr < frame.resources().size(); ++fr) {
        const PlannedResource& res = frame.resources()[fr];
        const ResourceDesc& d = graph.resources.at(res.decl);
        if (!d.external || options.imports.count(d.name)) continue;
        // The frame discards such an image's contents; and a swapchain image comes from the
        // presentation engine.
        if (d.isImage() && (res.initialLayout == VK_IMAGE_LAYOUT_UNDEFINED ||
                            res.initialLayout == VK_IMAGE_LAYOUT_PRESENT_SRC_KHR))
            continue;
        const uint32_t r = steps.addResource(res, VK_IMAGE_LAYOUT_UNDEFINED);
        const SubresourceRange whole = wholeOf(d, frame);
        const VulkanScope start = frameStartScope(frame, fr, d);
        SubresourceState state{};
        if (!d.isImage()) {
            steps.addStep("initialize ", "Upload", r, d, {{kTransferWrite, whole, state}});
        } else if (options.uploads.count(d.name) == 0) {
            steps.addStep("initialize ", "Clear", r, d, {{kTransferWrite, whole, state}});
        } else {
            // The upload fills mip 0; each further level is the level above, downsampled by a
            // linear blit (a 2x2 box), so an uploaded image always has its whole mip chain.
            std::vector<SubresourceState> levels(whole.mipCount, SubresourceState{});
            const auto level = [&](uint32_t m) { return SubresourceRange{m, 1, 0, whole.layerCount}; };
            steps.addStep("upload ", "Upload", r, d, {{kTransferWrite, level(0), levels[0]}});
            for (uint32_t m = 1; m < whole.mipCount; ++m)
                steps.addStep("downsample ", "Downsample", r, d,
                              {{kTransferWrite, level(m), levels[m]}, {kTransferRead, level(m - 1), levels[m - 1]}},
                              " to mip " + std::to_string(m));
            for (uint32_t m = 0; m < whole.mipCount; ++m) steps.addFinal(r, d, levels[m], start, start.layout, level(m));
            continue;
        }
        steps.addFinal(r, d, state, start, start.layout, whole);
    }
    return std::move(steps).finish();
}

Plan planImageRead(const GraphDesc& graph, const Plan& frame, std::string_view resource) {
    checkCompiledFrom(graph, frame);
    const int32_t fr = frame.resourceIndex(resource);
    const ResourceDesc* d = graph.findResource(resource);
    std::string problem;
    if (!d) problem = "no such resource";
    else if (!d->isImage()) problem = "it is a buffer";
    else if (fr < 0 || frame.resources()[size_t(fr)].finalLayout == VK_IMAGE_LAYOUT_UNDEFINED)
        problem = "no pass of the plan leaves it written";
    if (!problem.empty()) {
        Diagnostics diags;
        diags.add({graph.file, d ? d->jsonPath() : "resources", "", std::string(resource),
                   "cannot read '" + std::string(resource) + "': " + problem});
        throw GraphError(std::move(diags));
    }
    const PlannedResource& res = frame.resources()[size_t(fr)];
    StepListBuilder steps(frame);
    const uint32_t r = steps.addResource(res, res.finalLayout);
    const SubresourceRange whole = wholeOf(*d, frame);
    // The frames have finished (a fence): their writes are available, and the barrier before
    // the copy makes them visible to it, as for contents that arrive from outside a frame.
    SubresourceState state{};
    state.layout = res.finalLayout;
    state.fromOutside = true;
    steps.addStep("read back ", "Readback", r, *d, {{kTransferRead, whole, state}});
    // Back to the layout the frame left it in, which is what the executor and the next frame
    // take it to be in. An external image that the next frame finds as it was left must be
    // visible where the frame expects its `initial` contents.
    VulkanScope next{0, 0, res.finalLayout};
    if (d->external && res.initialLayout == res.finalLayout) {
        next = externalScope(*d, arrivesIn(res, *d));
        next.layout = res.finalLayout;
    }
    steps.addFinal(r, *d, state, next, next.layout, whole);
    steps.addHostRead(r);
    return std::move(steps).finish();
}

namespace {

/// The graph that sampled image uploads are the setup of: the images, external and arriving
/// ready to sample, and one pass that samples them all (so none is culled).
GraphDesc sampledImagesGraph(std::span<const SampledImageShape> images) {
    GraphDesc g;
    g.file = "<sampled images>";
    g.name = "sampled images";
    Diagnostics diags;
    const auto refuse = [&](const SampledImageShape& image, const std::string& problem) {
        diags.add({g.file, "images." + image.name, "", image.name, "cannot upload '" + image.name + "': " + problem});
    };
    if (images.empty()) diags.add({g.file, "images", "", "", "no images to upload"});
    PassDesc& sample = g.passes.emplace_back();
    sample.name = "sample";
    sample.type = "Generic";
    sample.neverCull = true;
    for (const SampledImageShape& image : images) {
        if (image.name.empty()) refuse(image, "an image needs a name");
        else if (g.findResource(image.name)) refuse(image, "another image has that name");
        else if (image.format.format == VK_FORMAT_UNDEFINED || image.format.isDepthStencil())
            refuse(image, "its format is not a colour format");
        else if (!formatInfoMatches(image.format))
            refuse(image, "its FormatInfo is not the one findFormat() gives for its format");
        else if (image.width < 1 || image.height < 1 || image.width > kMaxImageExtent || image.height > kMaxImageExtent)
            refuse(image, std::to_string(image.width) + "x" + std::to_string(image.height) + " is outside 1.." +
                              std::to_string(kMaxImageExtent) + " a side");
        if (diags.size() > 0) continue;
        ResourceDesc& r = g.resources.emplace_back();
        r.name = image.name;
        r.format = image.format;
        r.extent.relativeToOutput = false;
        r.extent.width = image.width;
        r.extent.height = image.height;
        r.mips = 0;  // full
        r.external = true;
        r.initial = ExternalState::ShaderRead;
        r.final = ExternalState::ShaderRead;
        UsageDecl& use = sample.uses.emplace_back();
        use.resource = static_cast<uint32_t>(g.resources.size() - 1);
        use.usage = Usage{Access::Read, Stage::Fragment, BindAs::Sampled, std::nullopt};
    }
    if (!diags.empty()) throw GraphError(std::move(diags));
    return g;
}

}  // namespace

Plan planSampledImageUploads(std::span<const SampledImageShape> images) {
    const GraphDesc graph = sampledImagesGraph(images);
    const Plan frame = compile(graph);
    SetupOptions options;
    for (const ResourceDesc& r : graph.resources) options.uploads.insert(r.name);
    return planSetup(graph, frame, options);
}

}  // namespace skygraph
