// Graph file -> plan. Pure: reads files and data, never touches a device. No state is shared
// between calls, so any thread may load and compile while no one modifies the arguments.
#pragma once

#include <skygraph/condition.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/memory.hpp>
#include <skygraph/pass_registry.hpp>
#include <skygraph/plan.hpp>

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string_view>

namespace skygraph {

/// Reads and validates a graph file against `registry`. The caller owns the result; it names
/// pass types and keeps nothing of `registry`, which is read during the call only. Throws
/// GraphError listing every problem in the file at once (or that it cannot be opened), each
/// with the file, JSON path, pass and resource. What can only be checked at an output size is
/// compile()'s.
[[nodiscard]] GraphDesc loadGraphFile(const std::filesystem::path& path,
                                      const PassRegistry& registry);

/// As loadGraphFile, for text already in memory (read during the call only); `fileName` is
/// used in messages only.
[[nodiscard]] GraphDesc parseGraph(std::string_view text, const std::string& fileName,
                                   const PassRegistry& registry);

struct CompileOptions {
    /// Overrides of the file's feature defaults. An unknown name is an error.
    FeatureValues features;
    /// When false, passes are removed only by their `if`, never for unused output.
    bool cull = true;
    /// Headless runs read the `Present` target back instead of presenting it: this replaces
    /// every exported resource's `Present` final state with another (e.g. TransferSrc); None
    /// is an error.
    ExternalState presentReplacement = ExternalState::Present;
    /// The size `"output"` extents resolve to; it matters for `"mips": "full"` only, since
    /// barriers cover whole mip chains. The executor recompiles when the output is resized.
    /// Each side from 1 to 16384, the largest extent a graph's image takes.
    uint32_t outputWidth = 1920;
    uint32_t outputHeight = 1080;
    /// Resources to export in addition to the file's own exports, with the state to leave
    /// them in: e.g. {"hdr_color", TransferSrc} to read an intermediate target back. Exporting
    /// keeps the passes that write it from being culled. An unknown name is an error, and so
    /// is None, and a state the resource cannot end in (as in a file: Present for an external
    /// image alone, Present or TransferSrc for no buffer, for an external one that arrives in a
    /// state of its own any other state: the next frame would not find it so; `readbacks`
    /// copies such an image out); a resource the file already exports keeps its own `final`.
    std::map<std::string, ExternalState, std::less<>> exports;
    /// When set, only these of the graph's exports are its outputs for this compile: the
    /// file's other exports are dropped, so passes that feed only them are culled. This is
    /// how a consumer asks for just the products it samples (e.g. graphs/ibl.json builds only
    /// the cube a skybox-only scene needs). An empty set asks for nothing, and every pass is
    /// culled. An unknown name, or one that is neither exported nor in `exports` or
    /// `readbacks`, is an error.
    std::optional<std::set<std::string, std::less<>>> outputs;
    /// Images copied to the host at the end of every frame (the first mip and layer), by
    /// steps of type Readback after the last pass; the final barriers make the copies visible
    /// to the host. Each is kept as an output, exported as TransferSrc unless the file exports
    /// it (an external image in its `initial` state, in which the next frame finds it). An
    /// unknown name, a buffer, an image that nothing writes, or one arriving as presented
    /// that is not exported (unless presentReplacement replaces Present) is an error.
    std::set<std::string, std::less<>> readbacks;
    /// Transient resources (not external, not exported) share memory where their lifetimes
    /// allow, and the plan orders each one's first use after the last uses of the memory it
    /// takes over (aliasing barriers). false: each gets a range of its own (`--no-alias`).
    bool aliasing = true;
    /// The frames in flight share the transients' memory instead of each having its own: one
    /// copy of each heap. Frames run in order on one queue, so each frame's first use of a
    /// byte waits, through the plan's aliasing barriers, for the previous frame's last use of
    /// it (docs/memory.md, "Frames in flight": it halves transient memory with two frames in
    /// flight). false: a copy per frame in flight (`--heaps-per-frame`).
    bool shareTransientsAcrossFrames = true;
    /// How they are placed when they share (docs/memory.md, "Placement").
    MemoryStrategy placement = MemoryStrategy::BestFitBySize;
    /// Where memory requirements come from: the executor passes its device's
    /// (Device::memoryModel()). Null: estimatedMemory().
    std::shared_ptr<const MemoryModel> memory;
    /// Every transient resource that is not `clear`ed is poisoned (NaN where the format can
    /// hold it) by a Clobber step inserted before its first use, and the first write of each
    /// subresource after it keeps what it does not write (no transition from UNDEFINED;
    /// attachments load). A frame that renders the same with and without this reads nothing
    /// it did not write (`--clobber-transients`).
    bool clobberTransients = false;
    /// How runs of reads of an image are laid out (docs/barriers.md, rule 4): one layout
    /// serving every reader, with the fewest barriers, or each reader's optimal layout, with a
    /// transition wherever consecutive readers want different ones. Unset: the graph file's
    /// `"layouts"` (GraphDesc::layouts), whose default is FewestBarriers.
    std::optional<LayoutPolicy> layouts;
    /// Which queue kinds (indexed by QueueKind) share a queue family: kinds with equal numbers
    /// do, and need no ownership transfers between them. The executor passes its device's
    /// (Device::queueFamilies()); the default, three families, is the general case.
    std::array<uint32_t, kQueueKinds> queueFamilies{0, 1, 2};
};

/// Schedules and synchronizes `graph`. Throws GraphError for problems that depend on the
/// feature values (a read whose only writer is switched off, an unknown feature override) or
/// on the output size (a mip range that starts past the resolved chain, where one that only
/// runs past its end is clipped to it; a read of levels of an
/// output-sized "full" chain that no pass writes), and for what only a GraphDesc
/// built in code can hold: a resource past the format's limits (an extent, layer or mip count
/// or buffer size the loader refuses) or of a shape or states it refuses (a cube of other than
/// 6 square layers, an image2d of several, an image of no format, a transient presented, a
/// buffer left for presentation or cleared, a clear value of the other kind, more mips than a
/// fixed extent has, an external resource exported in another state than it arrives in, a
/// type, state or sharing outside its enum), a pass on a queue outside QueueKind or one that
/// cannot perform its usages, a pass using one subresource twice, a condition naming an
/// undeclared feature, a usage naming a resource index past `resources`, an empty range, two
/// resources of a name the options name, or more than 2^24 subresources (mip levels x layers)
/// together; for options outside their enums; and when `options.memory` answers
/// what cannot be placed (no memory type, a zero size, an alignment or granularity that is not
/// a power of two). What the model itself throws passes through. Every error names what it can of the
/// file, JSON path, pass and resource. The plan owns copies of the names it holds (shared with
/// its own copies): it views nothing of `graph` or `options`.
[[nodiscard]] Plan compile(const GraphDesc& graph, const CompileOptions& options = {});

}  // namespace skygraph
