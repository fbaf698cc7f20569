// A graph together with the options it is compiled with and the plan they give: what a
// Renderer runs. One value, so that what runs can be compiled again the same way, at another
// output size or from an edited file, and never drifts from the plan it was given.
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/plan.hpp>

#include <cstdint>

namespace skygraph {

namespace detail {
struct CompiledGraphAccess;  // the implementation's own access; not part of the API
}

/// Owns its graph, options and plan; copies are independent. The references the accessors
/// return are valid while this CompiledGraph lives and is not assigned to; the names a plan
/// views stay valid while any copy of that plan lives (plan.hpp).
class CompiledGraph {
public:
    /// Takes `graph` and `options` and compiles them; the options' output size is the one the
    /// plan is valid for. Throws GraphError as compile() does, and passes on what
    /// `options.memory` throws: with a device's model (Device::memoryModel()),
    /// DeviceCapacityError for a resource past the device's limits and ExecutorError for one
    /// it cannot create, or once the device is destroyed.
    CompiledGraph(GraphDesc graph, CompileOptions options);

    [[nodiscard]] const GraphDesc& graph() const noexcept { return graph_; }
    [[nodiscard]] const CompileOptions& options() const noexcept { return options_; }
    [[nodiscard]] const Plan& plan() const noexcept { return plan_; }
    [[nodiscard]] uint32_t outputWidth() const noexcept { return options_.outputWidth; }
    [[nodiscard]] uint32_t outputHeight() const noexcept { return options_.outputHeight; }

    /// The same graph and options (copied) compiled for another output size. Throws GraphError
    /// (e.g. a zero size, or a mip range that the new size's chain does not have), and what
    /// the options' memory model throws, as the constructor does; this one is unchanged then.
    [[nodiscard]] CompiledGraph resized(uint32_t width, uint32_t height) const;
    /// Another graph (an edited file) compiled with the same options. Throws as the
    /// constructor does.
    [[nodiscard]] CompiledGraph withGraph(GraphDesc graph) const;

private:
    friend struct detail::CompiledGraphAccess;
    GraphDesc graph_;
    CompileOptions options_;
    Plan plan_;
};

}  // namespace skygraph
