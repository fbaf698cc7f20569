#include <skygraph/compiled_graph.hpp>

namespace skygraph {

CompiledGraph::CompiledGraph(GraphDesc graph, CompileOptions options)
    : graph_(std::move(graph)), options_(std::move(options)), plan_(compile(graph_, options_)) {}

CompiledGraph CompiledGraph::resized(uint32_t width, uint32_t height) const {
    CompileOptions o = options_;
    o.outputWidth = width;
    o.outputHeight = height;
    return CompiledGraph(graph_, std::move(o));
}

CompiledGraph CompiledGraph::withGraph(GraphDesc graph) const { return CompiledGraph(std::move(graph), options_); }

}  // namespace skygraph
