// What makes a graph unusable as a whole, apart from how its file is written: the checks the
// loader makes once a file is read, and those compile() makes against its options and output
// size. (The loader's own checks are of the file: keys, types and values of each entry.)
// Every problem is a Diagnostic naming the file, the JSON path, the pass and the resource.
#pragma once

#include "graph_index.hpp"
#include "scheduler.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>
#include <skygraph/graph.hpp>

namespace skygraph {

// ---- at load time: no output size, every pass active ------------------------------------

/// Reads that no earlier pass writes, in any feature combination and at any output size:
/// every pass counts as a writer, and a read of a "full" chain of an output-relative image
/// (whose length only the output size gives) is checked at its first level, which every
/// output size has. Neither `clear` nor `external`. For a loaded graph only (every usage
/// names one of its resources and a range within it). An output (`final`, not external) is
/// read whole as the frame ends: a part of it that no pass writes is an error too.
void checkReadsHaveSourcesAtLoad(const GraphDesc& graph, Diagnostics& out);

// ---- compile(): in the order it calls them -----------------------------------------------

/// CompileOptions::outputs, ::exports and ::readbacks name resources of `graph` (images, for
/// read-backs; exported ones, for outputs), and ::presentReplacement is a state an image can
/// be left in; throws GraphError if not.
void checkOutputNames(const GraphDesc& graph, const CompileOptions& options);

/// The file's feature defaults with the options' overrides, adding a diagnostic for each
/// override the graph does not declare, and for a zero output extent.
[[nodiscard]] FeatureValues checkedFeatures(const GraphDesc& graph, const CompileOptions& options,
                                            Diagnostics& out);

/// Everything compile() refuses about the indexed graph at the options' output size: usages
/// naming a resource or slot the graph lacks (only a GraphDesc built in code has them), mip
/// counts and ranges that the resolved chains cannot hold, and reads of active passes with no
/// source. Throws GraphError with `found` (the earlier checks' diagnostics) and its own, if any.
void validate(const GraphIndex& index, const FeatureValues& features, const CompileOptions& options,
              Diagnostics found);

/// A read-back of an image that no scheduled pass writes, and that is neither external nor
/// `clear`, would copy undefined contents: throws GraphError naming each.
void checkReadbacksHaveSources(const GraphIndex& index, const Schedule& schedule, const CompileOptions& options);

}  // namespace skygraph
