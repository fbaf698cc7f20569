// Pass types and the slots they declare. This is plain data: the compiler checks a graph
// against it without a device, and the executor later attaches recording code by type name.
#pragma once

#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/usage.hpp>

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

/// One resource role a pass type needs, e.g. TonemappingPass's "hdr" input.
struct SlotDecl {
    std::string name;
    Stage stage = Stage::Fragment;
    std::vector<Access> accesses;  ///< Allowed accesses; never empty.
    BindAs as = BindAs::Default;   ///< Required binding for shader stages; Default = any.
    bool optional = false;
    /// Whether the slot may be bound several times (e.g. one entry per mip level).
    bool repeated = false;
    std::string doc;
    /// Bound only by name (a usage's `slot`, or a resource of the slot's name), never as the
    /// one slot a usage fits: a slot added to a type this way leaves its graphs' bindings as
    /// they were.
    bool byNameOnly = false;
    /// The resource types it binds, where its recording code's views and shaders take only
    /// some (an environment cube, a 2D lookup table); empty: any. A designated initializer
    /// may leave it out.
    std::vector<ResourceType> types{};

    /// "Read@Fragment" or "Write|ReadWrite@ColorAttachment".
    [[nodiscard]] std::string describeUsage() const;
    /// Whether a usage of `usage` can fill this slot: its stage, one of its accesses, and its
    /// binding when the slot names one.
    [[nodiscard]] bool accepts(const UsageMode& usage) const noexcept;
    /// Whether a resource of type `type` can fill it (`types` empty or listing it).
    [[nodiscard]] bool takes(ResourceType type) const noexcept;
    /// Whether it can bind layers [baseLayer, baseLayer + layerCount) of `resource`: a slot of
    /// declared types binds a cube as a cube view, of every face; any other takes any layers.
    [[nodiscard]] bool takesLayers(const ResourceDesc& resource, uint32_t baseLayer, uint32_t layerCount) const noexcept;
    /// "a cube" or "an image2d or a cube": what `types` allows, for messages.
    [[nodiscard]] std::string describeTypes() const;
};

/// A problem found in a pass's `params`, relative to the params object.
struct ParamError {
    /// e.g. "operator", `tint.r`, or `["a.b"]` for a key a dot could not delimit
    /// (docs/graph-format.md, "Errors"); joined onto "passes[i].params". forKey() and
    /// memberPath() write it so for any key.
    std::string path;
    std::string message;

    /// The error about the params object's member `key`.
    [[nodiscard]] static ParamError forKey(std::string_view key, std::string message);
    /// The path of member `key` of the value at `parent` ("" for the params object itself).
    [[nodiscard]] static std::string memberPath(std::string_view parent, std::string_view key);
    /// `path` joined onto the path of the params object, e.g. "passes[2].params".
    [[nodiscard]] std::string pathUnder(std::string_view params) const;
};

using ParamValidator = std::function<std::vector<ParamError>(const nlohmann::json& params)>;

/// A problem a pass type finds in one of a pass's usages: what its slots cannot say, such as
/// the formats it can write or the range it copies.
struct UsageError {
    size_t usage = 0;  ///< Index into PassDesc::uses.
    std::string message;
};

/// Checks `pass`, whose usages are bound to this type's slots (UsageDecl::slot names the slot);
/// `graph` holds the resources they name. Reads both during the call only.
using UsageValidator = std::function<std::vector<UsageError>(const PassDesc& pass, const GraphDesc& graph)>;

class Plan;
struct PlannedPass;

/// Checks `pass`, a pass of this type as `plan` runs it: what depends on which passes run
/// before it, which the features choose (a UsageError's `usage` indexes pass.usages, which
/// are in the order the pass declares them). Reads both during the call only.
using PlannedPassValidator = std::function<std::vector<UsageError>(const PlannedPass& pass, const Plan& plan)>;

/// Everything the compiler needs to know about a pass type.
struct PassTypeInfo {
    std::string name;
    std::vector<SlotDecl> slots;
    /// The built-in Generic type: any usages, no slots (add() refuses a type with both).
    bool acceptsAnyUsage = false;
    /// Optional; when empty, any params object is accepted. An exception it throws is reported
    /// like a returned error, at the pass's `params`, naming the pass.
    ParamValidator validateParams;
    std::string doc;
    /// The queues its recording code can run on; empty: every queue whose kind supports the
    /// stages of its usages (a pass with attachments or vertex/fragment work needs graphics,
    /// compute shaders need graphics or compute, copies run anywhere). A type that records
    /// more than its usages say (a blit needs graphics) lists its queues here.
    std::vector<QueueKind> queues;
    /// Optional. parseGraph calls it for each pass of this type whose usages bound without an
    /// error, so that a pass the type cannot record is refused with the file's JSON path
    /// rather than when the graph runs. An exception it throws is reported at the pass's `uses`.
    UsageValidator validateUsages;
    /// Optional. Called for each pass of this type in a plan by plannedPassProblems() (which
    /// `skygraph compile` and `check` call) and by a renderer building the plan, so that what
    /// only the plan shows is refused before anything records. An exception it throws is
    /// reported like a returned error, at the pass. `check --jobs N` calls it from several
    /// threads at once: it must not change state that other calls read.
    PlannedPassValidator validatePlannedPass;
};

/// Pass types by name. Owns its entries; copyable because it is only data.
class PassRegistry {
public:
    /// An empty registry. Most callers want `withBuiltins()`.
    PassRegistry() = default;

    /// Generic plus every built-in pass type (docs/graph-format.md, "Built-in pass types"),
    /// in a new registry the caller owns. Defined by the pass types' library
    /// (skygraph::pass_types): link it to call this.
    [[nodiscard]] static PassRegistry withBuiltins();

    /// Registers a type (the registry keeps `info`). Throws std::invalid_argument, registering
    /// nothing, if the name is empty or taken, if it takes any usage and declares slots, or if
    /// a slot is malformed (an empty name, no accesses, duplicate names, `as` on a non-shader
    /// stage, a value outside its enum, an access that no resource of the slot's types can be
    /// used with, such as Write@VertexInput).
    void add(PassTypeInfo info);

    /// nullptr when unknown. The pointer stays valid until the registry is destroyed,
    /// assigned to, or another type is added.
    [[nodiscard]] const PassTypeInfo* find(std::string_view name) const noexcept;

    /// Registered names, sorted, for "unknown type" messages; a copy.
    [[nodiscard]] std::vector<std::string> names() const;

private:
    std::map<std::string, PassTypeInfo, std::less<>> types_;
};

/// Adds the built-in pass types; `withBuiltins()` calls it. Defined in skygraph::pass_types.
/// Throws std::invalid_argument when `registry` already has one of them; those added before
/// it stay.
void registerBuiltinPassTypes(PassRegistry& registry);

/// What the validatePlannedPass of each type in `registry` finds in the passes of `plan`,
/// compiled from `graph`: a diagnostic per problem at the usage's JSON path (the pass's for a
/// problem of no usage), naming the pass and the resource. Empty when there is none. Reads all
/// three during the call only.
[[nodiscard]] Diagnostics plannedPassProblems(const Plan& plan, const GraphDesc& graph, const PassRegistry& registry);

}  // namespace skygraph
