#include "usage_fit.hpp"

namespace skygraph {

std::string queueProblem(QueueKind queue, const ResourceDesc& r, const Usage& u) {
    const auto on = [&] { return "runs on the " + std::string(toString(queue)) + " queue"; };
    // vkCmdCopy*Image* of a depth or stencil aspect needs a queue with graphics.
    if (queue != QueueKind::Graphics && u.stage == Stage::Transfer && r.isImage() && r.format.isDepthStencil())
        return on() + ", but copies of the depth/stencil image '" + r.name + "' (" + toString(u) +
               ") need the graphics queue";
    if (queueSupports(queue, u.stage)) return {};
    const bool compute = queueSupports(QueueKind::Compute, u.stage);
    return on() + ", but its use of '" + r.name + "' (" + toString(u) + ") needs the " +
           std::string(toString(compute ? QueueKind::Compute : QueueKind::Graphics)) + " queue" +
           (compute ? " or the graphics queue" : "");
}

std::string usageProblem(const ResourceDesc& r, const Usage& u) {
    const auto stage = [&] { return std::string(toString(u.stage)); };
    const std::string format(r.format.name);
    switch (usageMisfit(usageSubject(r, u.range), u.mode())) {
        case UsageMisfit::Fits: return {};
        case UsageMisfit::UnknownValue:
            return "its access (" + std::to_string(int(u.access)) + "), stage (" + std::to_string(int(u.stage)) +
                   ") or binding (" + std::to_string(int(u.as)) + ") is not a value of its enum";
        case UsageMisfit::IndexOutsideVertexInput: return "`as: index` applies to VertexInput only";
        case UsageMisfit::AsOutsideShaders:
            return "`as` applies to shader stages (Vertex, Fragment, Compute), not " + stage();
        case UsageMisfit::BufferAttachment: return "a buffer cannot be an attachment (" + toString(u) + ")";
        case UsageMisfit::DepthFormatAsColor:
            return "format " + format +
                   " is a depth/stencil format; it cannot be a color attachment "
                   "(use Read|Write|ReadWrite@DepthAttachment)";
        case UsageMisfit::ColorFormatAsDepth:
            return "format " + format +
                   " has no depth or stencil; it cannot be a depth attachment "
                   "(use Read|Write|ReadWrite@ColorAttachment)";
        case UsageMisfit::AttachmentOfSeveralLevels:
            return "an attachment renders to one mip level; give \"mips\": [level, 1]";
        case UsageMisfit::ImageAsVertexInput: return stage() + " reads buffers, not images";
        case UsageMisfit::VertexInputWrites: return stage() + " only reads; expected Read@" + stage();
        case UsageMisfit::SampledBuffer: return "a buffer cannot be sampled; use storage or uniform";
        case UsageMisfit::SampledWrite:
            return "a sampled image is read-only; expected Read@" + stage() + " or \"as\": \"storage\"";
        case UsageMisfit::UniformImage: return "images cannot be uniform buffers; use sampled or storage";
        case UsageMisfit::UniformWrite: return "uniform buffers are read-only";
        case UsageMisfit::StorageFormat:
            return "format " + format +
                   " cannot be a storage image: it is not a storage format (no sRGB or depth format is); sample it or "
                   "pick a storage format";
    }
    return {};
}

// Every case (16 subjects x 120 usages) is worked out while skygraph is built.
constinit const std::array<uint16_t, 256> detail::kFitRows = [] {
    std::array<uint16_t, 256> t{};
    for (uint32_t stage = 0; stage < kStages; ++stage)
        for (uint32_t access = 0; access < kAccesses; ++access)
            for (uint32_t as = 0; as < kBindings; ++as)
                for (uint32_t row = 0; row < 16; ++row) {
                    const UsageSubject subject{(row & 1) != 0, (row & 2) != 0, (row & 4) != 0, (row & 8) != 0};
                    const UsageMode mode{static_cast<Access>(access), static_cast<Stage>(stage), static_cast<BindAs>(as)};
                    if (usageMisfit(subject, mode) == UsageMisfit::Fits) t[stage << 5 | access << 3 | as] |= uint16_t(1u << row);
                }
    return t;
}();

}  // namespace skygraph
