// The checks over a frame model: memory dependencies between every pair of conflicting
// accesses (hazards.cpp), overlapping placements in use at once (hazards.cpp), and the walk
// of layouts and contents (layouts.cpp).
#pragma once

#include "frame_model.hpp"
#include "report.hpp"

namespace skygraph::verifier {

/// Every pair of accesses to overlapping memory, one of them writing: ordered, and the write
/// available and visible. Returns the number of pairs checked.
size_t checkMemoryDependencies(const FrameModel& model, const Plan& plan, Reporter& reporter);

/// Two resources whose placements overlap may not be in use at the same time.
void checkLiveOverlaps(const FrameModel& model, Reporter& reporter);

/// Layouts through barriers and usages, the contents they keep or discard, and the aliasing
/// rule that memory taken over from another resource starts from UNDEFINED.
void checkLayoutsAndContents(const FrameModel& model, const Plan& plan, const GraphDesc& graph, Reporter& reporter);

}  // namespace skygraph::verifier
