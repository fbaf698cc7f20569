// Queue kinds' stages and accesses, from the Vulkan 1.3 tables "Supported pipeline stage
// flags" and "Supported access types".
#include "queue_scopes.hpp"

namespace skygraph {

VkPipelineStageFlags2 queueStages(QueueKind q) {
    constexpr VkPipelineStageFlags2 common = VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT |
                                             VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT | VK_PIPELINE_STAGE_2_HOST_BIT |
                                             VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT |
                                             VK_PIPELINE_STAGE_2_COPY_BIT;
    switch (q) {
        case QueueKind::Graphics: return ~VkPipelineStageFlags2(0);
        case QueueKind::Compute:
            return common | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT |
                   VK_PIPELINE_STAGE_2_CLEAR_BIT;
        case QueueKind::Transfer: return common;
    }
    return common;
}

VkPipelineStageFlags2 simplified(VkPipelineStageFlags2 stages) {
    return (stages & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT) ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT : stages;
}

VkAccessFlags2 accessesOf(VkPipelineStageFlags2 stages) {
    if (stages & VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT) return ~VkAccessFlags2(0);
    VkAccessFlags2 a = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT;
    if (stages & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT)
        a |= VK_ACCESS_2_UNIFORM_READ_BIT | VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT |
             VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
             VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    if (stages & VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT) a |= VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT;
    if (stages & (VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_CLEAR_BIT))
        a |= VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT;
    if (stages & VK_PIPELINE_STAGE_2_HOST_BIT) a |= VK_ACCESS_2_HOST_READ_BIT | VK_ACCESS_2_HOST_WRITE_BIT;
    constexpr VkPipelineStageFlags2 shaders = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT |
                                              VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                                              VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT;
    if (stages & shaders)
        a |= VK_ACCESS_2_UNIFORM_READ_BIT | VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT |
             VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
             VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
    if (stages & VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT) a |= VK_ACCESS_2_INPUT_ATTACHMENT_READ_BIT;
    if (stages & VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT)
        a |= VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    if (stages & (VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT))
        a |= VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    if (stages & (VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT |
                  VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT))
        a |= VK_ACCESS_2_INDEX_READ_BIT | VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT;
    if (stages & VK_PIPELINE_STAGE_2_ALL_GRAPHICS_BIT) return ~VkAccessFlags2(0);
    return a;
}

void keepToQueue(Barrier& b, QueueKind q) {
    if (q == QueueKind::Graphics) return;
    // Sources at stages this queue lacks ran elsewhere (another queue, or before the frame):
    // the queue's waits order them, and the barrier continues those waits.
    const bool elsewhere = (b.srcStages & ~queueStages(q)) != 0;
    b.srcStages &= queueStages(q);
    b.srcAccess &= accessesOf(b.srcStages);
    b.dstStages &= queueStages(q);
    b.dstAccess &= accessesOf(b.dstStages);
    if (elsewhere && b.kind != BarrierKind::Memory) {
        b.srcStages |= b.dstStages;
        b.srcAccess |= VK_ACCESS_2_MEMORY_READ_BIT;
    }
}

/// On several queues, every layout transition's source access scope holds MEMORY_READ: nothing
/// for Vulkan (reads need no availability), while validation layer 1.3.239, which merges the
/// submits' histories at each semaphore wait, otherwise loses the execution chain that orders
/// the transition after earlier writes (docs/queues.md).
void readsIntoTransition(Barrier& b) {
    if (b.kind == BarrierKind::Image && b.oldLayout != b.newLayout && b.srcStages != 0)
        b.srcAccess |= VK_ACCESS_2_MEMORY_READ_BIT;
}

}  // namespace skygraph
