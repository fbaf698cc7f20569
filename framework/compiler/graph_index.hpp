// The graph as the compiler's sweeps read it: flat arrays, built in one pass over GraphDesc.
// GraphDesc is pointer-rich (each pass keeps its usages, and its condition, in allocations of
// their own), so a sweep over it misses the cache at every pass; compile() sweeps the graph
// twice more (culling, plan building). The walk that builds the index also finds reads with
// no source. Shared by validation.cpp, scheduler.cpp and the synchronizer.
#pragma once

#include "graph_limits.hpp"
#include "subresources.hpp"
#include "usage_fit.hpp"
#include "vulkan_state.hpp"

#include <skygraph/condition.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skygraph {

/// One entry of a pass's `uses`, with what the sweeps read of it. 12 bytes: three sweeps
/// stream every one, so the few written ranges live in a table of their own.
struct IndexedUsage {
    static constexpr uint32_t kWhole = ~0u;
    UsageMode usage;           ///< As written.
    bool fillsSlot = false;    ///< Whether UsageDecl::slot is non-empty (never for Generic).
    uint32_t resource = 0;     ///< Index into GraphDesc::resources.
    uint32_t rangeIndex = kWhole;  ///< Its written range's place in the index's table, or none.
};
static_assert(sizeof(IndexedUsage) == 12);

/// A graph may have this many subresources, together. The sweeps keep tables of tens of bytes
/// per subresource, and an index is built before the first of them is refused: a bound far
/// past any frame (a 4K frame has thousands) keeps a graph built in code from costing
/// gigabytes before its error.
inline constexpr size_t kMaxSubresources = size_t(1) << 24;

/// The error for a graph whose resources, up to and including `r`, have more.
inline Diagnostics tooManySubresources(const GraphDesc& graph, const ResourceDesc& r) {
    Diagnostics d;
    d.add({graph.file, r.jsonPath(), "", r.name,
           "the graph's resources have more than " + std::to_string(kMaxSubresources) +
               " subresources (mip levels x layers) together"});
    return d;
}

class GraphIndex {
public:
    /// A pass is active when its `if` holds under `features`. Grids are resolved at the given
    /// output size. Resources' states are checked with Present replaced by `presentReplacement`
    /// (CompileOptions::presentReplacement).
    GraphIndex(const GraphDesc& graph, const FeatureValues& features, uint32_t outputWidth, uint32_t outputHeight,
               ExternalState presentReplacement)
        : graph_(graph) {
        reserveForPasses();
        indexPasses(features, indexResources(outputWidth, outputHeight, presentReplacement));
        names_.finish();
    }

    /// Not copyable: plans view its name text, which a copy would share and could grow.
    GraphIndex(const GraphIndex&) = delete;
    GraphIndex& operator=(const GraphIndex&) = delete;

    [[nodiscard]] const GraphDesc& graph() const noexcept { return graph_; }
    [[nodiscard]] size_t passes() const noexcept { return passFlags_.size(); }
    [[nodiscard]] bool active(size_t pass) const noexcept { return (passFlags_[pass] & kActive) != 0; }
    /// PassDesc::neverCull, kept here so that culling's backward sweep need not read the
    /// (large, cold) PassDesc of every pass.
    [[nodiscard]] bool neverCull(size_t pass) const noexcept { return (passFlags_[pass] & kNeverCull) != 0; }
    [[nodiscard]] std::span<const IndexedUsage> usesOf(size_t pass) const noexcept {
        return {uses_.data() + firstUse_[pass], uses_.data() + firstUse_[pass + 1]};
    }
    /// A usage by its position among all the graph's usages, pass after pass, and back.
    [[nodiscard]] uint32_t indexOf(const IndexedUsage& u) const noexcept {
        return static_cast<uint32_t>(&u - uses_.data());
    }
    [[nodiscard]] const IndexedUsage& use(uint32_t i) const noexcept { return uses_[i]; }
    /// Names, copied out of the graph in the index's walk: the plan views them (in the text
    /// that names() shares), and reading them from the large, long-evicted
    /// PassDesc/ResourceDesc would miss the cache. Valid while the index or that text lives.
    [[nodiscard]] std::string_view passName(size_t pass) const noexcept { return names_[passNames_[pass].name]; }
    [[nodiscard]] std::string_view passType(size_t pass) const noexcept { return names_[passNames_[pass].type]; }
    [[nodiscard]] std::string_view resourceName(size_t r) const noexcept { return names_[resources_[r].name]; }
    /// The text every name above views, complete once the index is built.
    [[nodiscard]] std::shared_ptr<const std::string> names() const noexcept { return names_.text(); }
    /// The pass's usage as declared (its slot): `u` must come from usesOf(pass).
    [[nodiscard]] const UsageDecl& declOf(size_t pass, const IndexedUsage& u) const noexcept {
        return graph_.passes[pass].uses[static_cast<size_t>(&u - usesOf(pass).data())];
    }
    /// Its JSON path, for messages (derived: see GraphDesc::usageJsonPath).
    [[nodiscard]] std::string jsonPathOf(size_t pass, const IndexedUsage& u) const {
        return graph_.usageJsonPath(pass, static_cast<size_t>(&u - usesOf(pass).data()));
    }

    /// Per resource (index into GraphDesc::resources).
    [[nodiscard]] const SubresourceGrid& grid(size_t r) const noexcept { return resources_[r].grid; }
    /// Subresources of all resources together: the size of a flat per-subresource array,
    /// which holds each resource's end to end, in file order.
    [[nodiscard]] size_t cells() const noexcept { return cells_; }
    /// The range the usage's file entry names; null when it names none (the whole resource).
    [[nodiscard]] const SubresourceRange* writtenRange(const IndexedUsage& u) const noexcept {
        return u.rangeIndex == IndexedUsage::kWhole ? nullptr : &ranges_[u.rangeIndex];
    }
    [[nodiscard]] SubresourceRange range(const IndexedUsage& u) const noexcept {
        return resources_[u.resource].grid.resolve(writtenRange(u));
    }
    /// Calls f(flat index) for every subresource the usage touches; a resource of one
    /// subresource (most of them) skips resolving the range.
    template <typename F>
    void forEachCell(const IndexedUsage& u, F&& f) const {
        if (const uint32_t cell = onlyCell_[u.resource]; cell != kSeveralCells) return f(size_t(cell));
        const IndexedResource& res = resources_[u.resource];
        res.grid.forEach(range(u), [&](size_t sub) { f(res.firstCell + sub); });
    }
    /// Per subresource of every resource (flat, numbered as forEachCell numbers them):
    /// whether its contents are wanted when the frame ends (exported). What culling starts
    /// from.
    [[nodiscard]] const std::vector<uint8_t>& liveAtEnd() const noexcept { return liveAtEnd_; }
    [[nodiscard]] const ResourceAspects& aspects(size_t r) const noexcept { return resources_[r].aspects; }
    [[nodiscard]] bool clear(size_t r) const noexcept { return resources_[r].clear; }
    /// How many resources are `clear`.
    [[nodiscard]] size_t clearResources() const noexcept { return clearResources_; }
    [[nodiscard]] bool external(size_t r) const noexcept { return resources_[r].external; }
    [[nodiscard]] bool exported(size_t r) const noexcept { return resources_[r].exported; }
    /// Images whose `mips` exceed what their extent (at the output size) gives them, in file
    /// order: compile() reports them (the loader checks a file's fixed extents itself).
    [[nodiscard]] std::span<const uint32_t> tooManyMips() const noexcept { return tooManyMips_; }
    /// Passes on a queue other than graphics, or with a condition, in file order: compile()
    /// checks their queues and the features their conditions name (the loader checks a file's).
    [[nodiscard]] std::span<const uint32_t> offGraphicsOrConditional() const noexcept { return offGraphicsOrConditional_; }
    /// The active passes' usages that name a range, as (pass, usage index for use()), in
    /// file order: what compile() checks against the resolved mip chains.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> rangedUses() const noexcept { return ranged_; }
    /// Usages, of any pass, whose resource index is past the graph's resources or whose slot
    /// id is past its slot names, as (pass, usage index for use()), in file order. Only a
    /// GraphDesc built in code has them (the loader writes none); compile() reports them, and
    /// no sweep may run on such an index.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> invalidUses() const noexcept { return invalid_; }
    /// Usages, of any pass, that do not fit their resource (usage_fit.hpp: a buffer as an
    /// attachment, a sampled image written), as (pass, usage index for use()), in file order.
    /// Only a GraphDesc built in code has them; compile() reports them before any sweep.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> misfitUses() const noexcept { return misfits_; }
    /// Reads, by active passes, of a subresource that no earlier active pass wrote and whose
    /// resource is neither `clear` nor `external`, as (pass, usage index for use()), in file
    /// order. Found in the index's own walk (a sweep of their own cost as much again as
    /// finding them there); validate() words them.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> unsourcedReads() const noexcept { return unsourced_; }
    /// Outputs (exported, neither external nor `clear`) with a subresource that no active pass
    /// writes: the frame would hand it on undefined. Resource indices, in order.
    [[nodiscard]] std::span<const uint32_t> unwrittenOutputs() const noexcept { return unwrittenOutputs_; }
    /// Outputs that are `clear` and not external: a plan holds each, cleared where no pass
    /// that runs uses it. Resource indices, in order.
    [[nodiscard]] std::span<const uint32_t> clearOutputs() const noexcept { return clearOutputs_; }
    /// Per active pass whose attachments differ in size (of the mip each renders to) or layer
    /// count at the output size: its first attachment usage that differs from its first
    /// attachment, as (pass, usage index for use()). Found in the index's walk; validate() words them.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> misshapenAttachments() const noexcept {
        return misshapen_;
    }
    /// Per pass (active or not), its colour attachment usage past kMaxColorAttachments and its
    /// second depth attachment usage, as (pass, usage index for use()), in file order. Only a
    /// GraphDesc built in code has them (the loader refuses them); validate() words them.
    [[nodiscard]] std::span<const std::pair<uint32_t, uint32_t>> overfullAttachments() const noexcept {
        return overfull_;
    }
    /// What one framebuffer asks its attachments to share: the size of the mip each renders to
    /// and the layer count.
    struct AttachmentShape {
        uint32_t width, height, layers;
        bool operator==(const AttachmentShape&) const = default;
    };
    [[nodiscard]] AttachmentShape attachmentShape(const IndexedUsage& u) const noexcept {
        const IndexedResource& res = resources_[u.resource];
        const SubresourceRange* written = u.rangeIndex == IndexedUsage::kWhole ? nullptr : &ranges_[u.rangeIndex];
        const uint32_t mip = written ? std::min(written->baseMip, res.grid.mips - 1) : 0;
        return {std::max(1u, res.width >> mip), std::max(1u, res.height >> mip),
                written ? written->layerCount : res.grid.layers};
    }


private:
    /// Appends `count` subresources' `value`; one (most resources) without insert's overhead.
    template <typename T>
    static void appendCells(std::vector<T>& cells, size_t count, T value) {
        if (count == 1) cells.push_back(value);
        else cells.insert(cells.end(), count, value);
    }

    /// Reserves the per-pass and per-usage arrays and the name table's room. Sized from a
    /// sample of passes spread over the graph, not by counting: a counting walk reads every
    /// (cold) PassDesc once more, which costs more than the one further doubling a low guess
    /// costs. Resource names are guessed at 8 bytes.
    void reserveForPasses() {
        const size_t passes = graph_.passes.size();
        passFlags_.reserve(passes);
        passNames_.reserve(passes);
        firstUse_.reserve(passes + 1);
        const size_t stride = std::max<size_t>(1, passes / kSampledPasses);
        size_t sampled = 0, sampledUses = 0, sampledRanges = 0, sampledNameBytes = 0;
        for (size_t p = 0; p < passes; p += stride, ++sampled) {
            const PassDesc& pass = graph_.passes[p];
            sampledUses += pass.uses.size();
            for (const auto& u : pass.uses) sampledRanges += u.usage.range.has_value();
            sampledNameBytes += pass.name.size() + pass.type.size();
        }
        const auto estimate = [&](size_t total) { return sampled ? total * passes / sampled * 9 / 8 : 0; };
        uses_.reserve(estimate(sampledUses));
        ranges_.reserve(estimate(sampledRanges));
        names_.makeRoom(estimate(sampledNameBytes) + 8 * graph_.resources.size());
    }

    /// Returns, per subresource, 1 where it holds contents when the frame starts (its resource
    /// is `clear` or `external`), else 0: where indexPasses' read check starts.
    std::vector<uint32_t> indexResources(uint32_t outputWidth, uint32_t outputHeight, ExternalState presentReplacement) {
        std::vector<uint32_t> heldAtStart;
        resources_.reserve(graph_.resources.size());
        onlyCell_.reserve(graph_.resources.size());
        fitRows_.resize(graph_.resources.size());
        heldAtStart.reserve(graph_.resources.size() * 9 / 8);  // most resources have one subresource
        liveAtEnd_.reserve(graph_.resources.size() * 9 / 8);
        for (const auto& r : graph_.resources) {
            // The loader keeps these; a GraphDesc built in code may not (a divisor of 0 would
            // divide by zero resolving the extent).
            if (!withinLimits(r, presentReplacement)) throw GraphError(limitProblems(graph_, presentReplacement));
            const SubresourceGrid grid(r, outputWidth, outputHeight);
            const size_t cells = grid.size();
            // The sweeps number subresources with 32 bits. Only a GraphDesc built in code can
            // come near (the loader bounds mips and layers).
            if (cells > kMaxCells - cells_) throw GraphError(tooManySubresources(graph_, r));
            // A buffer's extent is not checked (nor used): it may divide by zero.
            const auto [width, height] =
                r.isImage() ? r.extent.resolve(outputWidth, outputHeight) : std::array<uint32_t, 2>{1, 1};
            const IndexedResource& res = resources_.emplace_back(
                IndexedResource{grid, static_cast<uint32_t>(cells_), names_.add(r.name), aspectsOf(r),
                                r.clear.has_value(), r.external, r.isExported(), width, height});
            onlyCell_.push_back(cells == 1 ? static_cast<uint32_t>(cells_) : kSeveralCells);
            fitRows_[resources_.size() - 1] = fitRow(usageSubject(r, std::nullopt));
            cells_ += cells;
            clearResources_ += res.clear;
            appendCells(heldAtStart, cells, uint32_t{res.clear || res.external});
            appendCells(liveAtEnd_, cells, uint8_t{res.exported});
            // One level always fits (most images): the extent is resolved only for more.
            if (r.isImage() && r.mips > 1) {
                if (r.mips > static_cast<uint32_t>(std::bit_width(std::max(width, height))))
                    tooManyMips_.push_back(static_cast<uint32_t>(&r - graph_.resources.data()));
            }
        }
        return heldAtStart;
    }

    /// The passes' usages, and (for active passes, in the same walk) the reads of contents
    /// that no earlier active pass wrote: validate() words them.
    void indexPasses(const FeatureValues& features, std::vector<uint32_t> heldFrom) {
        const size_t passes = graph_.passes.size();
        firstUse_.push_back(0);
        const size_t resources = graph_.resources.size(), slots = graph_.slotNames.size();
        // Per subresource, from when its contents are held: 0 never yet, 1 from the frame's
        // start (indexResources), p + 2 from pass p's write on. A read in pass p is sourced by
        // what holds before p + 2: a pass's reads see what earlier passes wrote, not its own
        // writes, whichever order its usages come in (stamps spare a second loop over them).
        for (size_t p = 0; p < passes; ++p) {
            if (p + kPrefetchAhead < passes) prefetchUses(graph_.passes[p + kPrefetchAhead]);
            const PassDesc& pass = graph_.passes[p];
            passNames_.push_back({names_.add(pass.name), names_.add(pass.type)});
            const bool active = pass.condition.evaluate(features);
            // evaluate() has read the condition's text: what validate() checks costs no more lines.
            if (pass.queue != QueueKind::Graphics || !pass.condition.text().empty()) [[unlikely]]
                offGraphicsOrConditional_.push_back(static_cast<uint32_t>(p));
            passFlags_.push_back(static_cast<uint8_t>((active ? kActive : 0) | (pass.neverCull ? kNeverCull : 0)));
            const auto stamp = static_cast<uint32_t>(p + 2);
            uint32_t next = firstUse_.back();  // the usage's index for use() (size() would divide by 12)
            AttachmentShape attachments{};  // the first attachment's, when width != 0
            bool misshapen = false;
            uint32_t colors = 0, depths = 0;
            for (const auto& u : pass.uses) {
                IndexedUsage& iu = uses_.emplace_back();  // field by field: see vulkanScope
                iu.usage = u.usage.mode();
                iu.resource = u.resource;
                iu.fillsSlot = u.slot != 0;
                const uint32_t at = next++;
                if (u.usage.range) {
                    iu.rangeIndex = static_cast<uint32_t>(ranges_.size());
                    ranges_.push_back(*u.usage.range);
                    if (active) ranged_.emplace_back(static_cast<uint32_t>(p), at);
                }
                if (u.resource >= resources || u.slot > slots) {
                    invalid_.emplace_back(static_cast<uint32_t>(p), at);
                    continue;
                }
                const FitRow row = fitRows_[u.resource];
                if (!usageFits(u.usage.range ? withLevels(row, u.usage.range->mipCount) : row, iu.usage)) [[unlikely]]
                    misfits_.emplace_back(static_cast<uint32_t>(p), at);
                if (isAttachmentStage(iu.usage.stage)) {
                    // Counted in every pass, as the loader counts them; shapes in those that run.
                    const bool depth = iu.usage.stage == Stage::DepthAttachment;
                    if (depth ? ++depths == 2 : ++colors == kMaxColorAttachments + 1) [[unlikely]]
                        overfull_.emplace_back(static_cast<uint32_t>(p), at);
                    if (active && !misshapen) {
                        const AttachmentShape shape = attachmentShape(iu);
                        if (attachments.width == 0) attachments = shape;
                        else if (!(shape == attachments)) {
                            misshapen = true;
                            misshapen_.emplace_back(static_cast<uint32_t>(p), at);
                        }
                    }
                }
                if (!active) continue;
                if (readsContents(iu.usage.access)) {
                    bool missing = false;
                    forEachCell(iu, [&](size_t i) { missing |= heldFrom[i] - 1 >= stamp - 1; });  // 0 wraps
                    if (missing) unsourced_.emplace_back(static_cast<uint32_t>(p), at);
                }
                if (writesContents(iu.usage.access))
                    forEachCell(iu, [&](size_t i) { if (heldFrom[i] == 0) heldFrom[i] = stamp; });
            }
            firstUse_.push_back(next);
        }
        for (uint32_t r = 0; r < resources_.size(); ++r) {
            const IndexedResource& res = resources_[r];
            if (!res.exported || res.external) continue;
            if (res.clear) {
                clearOutputs_.push_back(r);
                continue;
            }
            const auto cell = heldFrom.begin() + res.firstCell;
            if (std::find(cell, cell + static_cast<std::ptrdiff_t>(res.grid.size()), 0u) != cell + res.grid.size())
                unwrittenOutputs_.push_back(r);
        }
    }

    /// Each pass keeps its usages in an allocation of its own, usually on another page than
    /// the last pass's: reading them in turn waits for memory at every pass unless they are
    /// asked for a few passes ahead.
    static constexpr size_t kPrefetchAhead = 4;
    static constexpr size_t kSampledPasses = 64;
    static void prefetchUses(const PassDesc& pass) {
        const auto* begin = reinterpret_cast<const char*>(pass.uses.data());
        const auto* end = reinterpret_cast<const char*>(pass.uses.data() + pass.uses.size());
        for (const char* line = begin; line < end; line += 64) __builtin_prefetch(line);
    }

    /// Strings laid end to end; a name is its (offset, length). Shared: a plan keeps the
    /// text alive and views its names in it rather than copying them. Filled by plain copies
    /// into room made ahead (std::string's append costs twice as many instructions per
    /// name, at three names per pass), then trimmed once complete.
    class NameTable {
    public:
        struct Ref { uint32_t offset = 0, length = 0; };
        Ref add(const std::string& s) {
            const Ref ref{static_cast<uint32_t>(used_), static_cast<uint32_t>(s.size())};
            if (s.size() > text_->size() - used_) text_->resize(std::max(2 * text_->size(), used_ + s.size()));
            copyName(text_->data() + used_, s.data(), s.size());
            used_ += s.size();
            return ref;
        }
        /// Room for `bytes` more bytes of names, made now (the text is written in place);
        /// more may be added all the same.
        void makeRoom(size_t bytes) { text_->resize(used_ + bytes); }
        /// Done adding: the text is exactly the names. (Refs are 32-bit: a larger text,
        /// which only a GraphDesc built in code could have, is refused here.)
        void finish() {
            if (used_ > UINT32_MAX) throw std::length_error("graph index: more than 4 GiB of names");
            text_->resize(used_);
        }
        std::string_view operator[](Ref r) const noexcept { return {text_->data() + r.offset, r.length}; }
        [[nodiscard]] std::shared_ptr<const std::string> text() const noexcept { return text_; }
    private:
        /// memcpy, with names of 4 to 16 bytes (nearly all) copied inline as two overlapping
        /// words rather than through a call.
        static void copyName(char* to, const char* from, size_t n) noexcept {
            if (n >= 8 && n <= 16) {
                std::memcpy(to, from, 8);
                std::memcpy(to + n - 8, from + n - 8, 8);
            } else if (n >= 4 && n < 8) {
                std::memcpy(to, from, 4);
                std::memcpy(to + n - 4, from + n - 4, 4);
            } else {
                std::memcpy(to, from, n);
            }
        }
        std::shared_ptr<std::string> text_ = std::make_shared<std::string>();
        size_t used_ = 0;
    };
    struct PassNames { NameTable::Ref name, type; };

    struct IndexedResource {
        SubresourceGrid grid;    ///< At the output size.
        uint32_t firstCell;      ///< Where its subresources start in a flat per-subresource array.
        NameTable::Ref name;
        ResourceAspects aspects;
        bool clear;
        bool external;
        bool exported;
        uint32_t width, height;  ///< Mip 0's, at the output size (1x1 for a buffer).
    };

    const GraphDesc& graph_;
    static constexpr uint8_t kActive = 1, kNeverCull = 2;
    std::vector<uint8_t> passFlags_;    // per pass (bytes: a bit vector costs more to read)
    std::vector<uint32_t> firstUse_;    // per pass: its usages in uses_ (+1 at the end)
    std::vector<IndexedUsage> uses_;
    std::vector<SubresourceRange> ranges_;  // the written ranges that uses_ refer to
    std::vector<std::pair<uint32_t, uint32_t>> ranged_;
    std::vector<std::pair<uint32_t, uint32_t>> invalid_;
    std::vector<std::pair<uint32_t, uint32_t>> misfits_;
    std::vector<FitRow> fitRows_;  // per resource: usageFits' row for a usage of all of it
    std::vector<std::pair<uint32_t, uint32_t>> unsourced_;
    std::vector<uint32_t> unwrittenOutputs_;
    std::vector<uint32_t> clearOutputs_;
    std::vector<std::pair<uint32_t, uint32_t>> misshapen_;
    std::vector<std::pair<uint32_t, uint32_t>> overfull_;
    std::vector<uint32_t> tooManyMips_;
    std::vector<uint32_t> offGraphicsOrConditional_;
    // Per resource: the flat index of its one subresource, or kSeveralCells. The sweeps ask
    // it of every usage, from an array dense enough to stay in cache (the resource records
    // are 36 bytes each); otherwise it takes the record, a range and a multiplication.
    static constexpr uint32_t kSeveralCells = ~0u;
    static constexpr uint32_t kMaxCells = kMaxSubresources;
    static_assert(kMaxCells < kSeveralCells);
    std::vector<uint32_t> onlyCell_;
    std::vector<uint8_t> liveAtEnd_;  // per subresource
    NameTable names_;
    std::vector<PassNames> passNames_;               // per pass
    std::vector<IndexedResource> resources_;         // per resource
    size_t cells_ = 0;                               // subresources of all resources
    size_t clearResources_ = 0;
};

}  // namespace skygraph
