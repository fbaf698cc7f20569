#include "generic_program.hpp"

#include "pass_error.hpp"
#include "texel_encoding.hpp"

#include <skygraph/device.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace skygraph::passes {

using detail::passError;
using detail::scalarPrefix;

namespace {

std::string glslStorageFormat(VkFormat f) {
    switch (f) {
        case VK_FORMAT_R8G8B8A8_UNORM: return "rgba8";
        case VK_FORMAT_R8G8B8A8_SNORM: return "rgba8_snorm";
        case VK_FORMAT_R8G8B8A8_UINT: return "rgba8ui";
        case VK_FORMAT_R8G8B8A8_SINT: return "rgba8i";
        case VK_FORMAT_R16G16B16A16_SFLOAT: return "rgba16f";
        case VK_FORMAT_R16G16B16A16_UNORM: return "rgba16";
        case VK_FORMAT_R16G16B16A16_UINT: return "rgba16ui";
        case VK_FORMAT_R32G32B32A32_SFLOAT: return "rgba32f";
        case VK_FORMAT_R32G32B32A32_UINT: return "rgba32ui";
        case VK_FORMAT_R32G32B32A32_SINT: return "rgba32i";
        case VK_FORMAT_R16G16_SFLOAT: return "rg16f";
        case VK_FORMAT_R32G32_SFLOAT: return "rg32f";
        case VK_FORMAT_R16_SFLOAT: return "r16f";
        case VK_FORMAT_R32_SFLOAT: return "r32f";
        case VK_FORMAT_R32_UINT: return "r32ui";
        case VK_FORMAT_R32_SINT: return "r32i";
        case VK_FORMAT_R8_UNORM: return "r8";
        case VK_FORMAT_R8G8_UNORM: return "rg8";
        case VK_FORMAT_R16_UNORM: return "r16";
        case VK_FORMAT_B10G11R11_UFLOAT_PACK32: return "r11f_g11f_b10f";
        case VK_FORMAT_A2B10G10R10_UNORM_PACK32: return "rgb10_a2";
        default: return {};
    }
}

/// The GLSL name of level `level` of a storage-image binding: `iN`, or `iN[level]` for an
/// array of per-level views.
std::string storageImage(const ShaderBinding& b, uint32_t level) {
    const std::string name = "i" + std::to_string(b.binding);
    return b.levels > 1 ? name + "[" + std::to_string(level) + "]" : name;
}

/// Expression reading a binding at `xy` (ivec2) into a vec4, with `li` the linear index.
std::string readExpr(const ShaderBinding& b) {
    const std::string n = std::to_string(b.binding);
    switch (b.kind) {
        case BindKind::SampledImage:
            if (b.viewType == VK_IMAGE_VIEW_TYPE_CUBE)
                return "vec4(textureLod(t" + n + ", vec3(1.0, 0.0, 0.0), 0.0))";
            if (b.viewType == VK_IMAGE_VIEW_TYPE_2D_ARRAY)
                return "vec4(texelFetch(t" + n + ", ivec3(clamp(xy, ivec2(0), textureSize(t" + n +
                       ", 0).xy - 1), 0), 0))";
            return "vec4(texelFetch(t" + n + ", clamp(xy, ivec2(0), textureSize(t" + n +
                   ", 0) - 1), 0))";
        case BindKind::StorageImage: {
            std::string sum;
            for (uint32_t level = 0; level < b.levels; ++level) {
                const std::string image = storageImage(b, level);
                sum += (level ? " + " : "") +
                       (b.viewType == VK_IMAGE_VIEW_TYPE_2D_ARRAY
                            ? "vec4(imageLoad(" + image + ", ivec3(clamp(xy, ivec2(0), imageSize(" + image +
                                  ").xy - 1), 0)))"
                            : "vec4(imageLoad(" + image + ", clamp(xy, ivec2(0), imageSize(" + image + ") - 1)))");
            }
            return sum;
        }
        case BindKind::StorageBuffer:
            return "(b" + n + ".data.length() > kValueIndex ? vec4(uintBitsToFloat(b" + n +
                   ".data[kValueIndex])) : vec4(0.0))";
        case BindKind::UniformBuffer:
            if (b.uniformVec4s > 2) return "vec4(uintBitsToFloat(u" + n + ".data[2].x))";
            return "vec4(0.0)";
    }
    return "vec4(0.0)";
}

std::string declare(const ShaderBinding& b) {
    const std::string n = std::to_string(b.binding);
    std::ostringstream s;
    switch (b.kind) {
        case BindKind::SampledImage: {
            const char* type = b.viewType == VK_IMAGE_VIEW_TYPE_CUBE         ? "samplerCube"
                               : b.viewType == VK_IMAGE_VIEW_TYPE_2D_ARRAY ? "sampler2DArray"
                                                                           : "sampler2D";
            s << "layout(set = 0, binding = " << n << ") uniform " << b.scalarPrefix << type
              << " t" << n << ";\n";
            break;
        }
        case BindKind::StorageImage: {
            const char* type = b.viewType == VK_IMAGE_VIEW_TYPE_2D_ARRAY ? "image2DArray" : "image2D";
            s << "layout(set = 0, binding = " << n;
            if (!b.glslFormat.empty()) s << ", " << b.glslFormat;
            s << ") uniform " << (b.write && !b.read ? "writeonly " : b.read && !b.write ? "readonly " : "")
              << b.scalarPrefix << type << " i" << n;
            if (b.levels > 1) s << "[" << b.levels << "]";
            s << ";\n";
            break;
        }
        case BindKind::StorageBuffer:
            s << "layout(std430, set = 0, binding = " << n << ") "
              << (b.write && !b.read ? "writeonly " : b.read && !b.write ? "readonly " : "")
              << "buffer B" << n << " { uint data[]; } b" << n << ";\n";
            break;
        case BindKind::UniformBuffer:
            s << "layout(std140, set = 0, binding = " << n << ") uniform U" << n
              << " { uvec4 data[" << b.uniformVec4s << "]; } u" << n << ";\n";
            break;
    }
    return s.str();
}

/// Statements performing every read (into `acc`) and then every write of `bindings` for
/// one shader stage. `vertexStage` writes with vertex-invocation coordinates.
std::string body(const std::vector<ShaderBinding>& bindings, VkShaderStageFlagBits stage) {
    std::ostringstream s;
    for (const auto& b : bindings) {
        if (b.stage != stage || !b.read) continue;
        if (b.kind == BindKind::StorageBuffer && b.write) {
            // Read-modify-write buffers read their own element; it does not feed `acc` so that
            // the result does not depend on invocation order.
            const std::string n = std::to_string(b.binding);
            s << "    if (b" << n << ".data.length() > 0 && b" << n << ".data[min(li, uint(b" << n
              << ".data.length()) - 1u)] == 0xfeedfaceu) acc.w += 1.0;\n";
            continue;
        }
        s << "    acc += " << readExpr(b) << ";\n";
    }
    for (const auto& b : bindings) {
        if (b.stage != stage || !b.write) continue;
        const std::string n = std::to_string(b.binding);
        if (b.kind == BindKind::StorageImage) {
            const std::string value = b.scalarPrefix + "vec4(acc)";
            for (uint32_t level = 0; level < b.levels; ++level) {
                const std::string image = storageImage(b, level);
                if (b.viewType == VK_IMAGE_VIEW_TYPE_2D_ARRAY) {
                    s << "    if (all(lessThan(xy, imageSize(" << image << ").xy)))\n"
                      << "        for (int l = 0; l < imageSize(" << image << ").z; ++l) imageStore(" << image
                      << ", ivec3(xy, l), " << value << ");\n";
                } else {
                    s << "    if (all(lessThan(xy, imageSize(" << image << ")))) imageStore(" << image << ", xy, "
                      << value << ");\n";
                }
            }
        } else if (b.kind == BindKind::StorageBuffer) {
            if (stage == VK_SHADER_STAGE_VERTEX_BIT) {
                s << "    if (gl_VertexIndex == 0 && gl_InstanceIndex == 0)\n"
                  << "        for (uint i = 0u; i < uint(b" << n << ".data.length()); ++i) b" << n
                  << ".data[i] = genericBufferWord(i, acc);\n";
            } else {
                s << "    if (li < uint(b" << n << ".data.length())) b" << n
                  << ".data[li] = genericBufferWord(li, acc);\n";
            }
        }
    }
    return s.str();
}

std::string vec4Literal(const std::array<float, 4>& c) {
    std::ostringstream s;
    s.precision(9);
    s << "vec4(" << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3] << ")";
    return s.str();
}

}  // namespace

GenericParams parseGenericParams(const PassDesc& desc, bool strict) {
    GenericParams out;
    const nlohmann::json& params = desc.params;
    // params: { "color": [r, g, b, a], "depth": d }
    if (params.is_object()) {
        if (auto it = params.find("color"); it != params.end()) {
            const bool ok = it->is_array() && it->size() == 4 &&
                            std::all_of(it->begin(), it->end(),
                                        [](const nlohmann::json& v) { return v.is_number(); });
            if (ok) {
                for (size_t i = 0; i < 4; ++i) out.color[i] = (*it)[i].get<float>();
            } else if (strict) {
                throw ExecutorError(passError(desc.name, "", "params.color must be an array of 4 numbers"));
            }
        }
        if (auto it = params.find("depth"); it != params.end()) {
            if (it->is_number() && it->get<double>() >= 0.0 && it->get<double>() <= 1.0) {
                out.depth = it->get<float>();
            } else if (strict) {
                throw ExecutorError(passError(desc.name, "", "params.depth must be a number in [0, 1]"));
            }
        }
    }
    return out;
}

GenericProgram buildGenericProgram(const PlannedPass& pass, std::span<const BoundResource> resources,
                                   const GenericParams& params, bool layeredRendering) {
    GenericProgram p;
    p.color = params.color;
    p.depthValue = params.depth;
    if (resources.size() != pass.usages.size())
        throw ExecutorError(passError(pass, "", "the bound resources are not parallel to the usages"));

    uint32_t nextBinding = 0;
    for (uint32_t i = 0; i < pass.usages.size(); ++i) {
        const PlannedUsage& u = pass.usages[i];
        const ResourceDesc& r = *resources[i].desc;
        switch (u.usage.stage) {
            case Stage::ColorAttachment:
                if (!r.isImage() || r.format.isDepthStencil())
                    throw ExecutorError(passError(pass, r.name, "is not a color image"));
                p.colors.push_back(i);
                p.graphics = true;
                break;
            case Stage::DepthAttachment:
                if (!r.isImage() || !r.format.isDepthStencil())
                    throw ExecutorError(passError(pass, r.name, "is not a depth/stencil image"));
                if (p.depth >= 0)
                    throw ExecutorError(passError(pass, r.name, "a pass can have one depth attachment"));
                p.depth = static_cast<int32_t>(i);
                p.graphics = true;
                break;
            case Stage::Transfer:
                p.transfers.push_back(i);
                break;
            case Stage::VertexInput:
                if (r.isImage()) throw ExecutorError(passError(pass, r.name, "VertexInput needs a buffer"));
                if (u.usage.as == BindAs::Index) {
                    if (p.indexBuffer >= 0)
                        throw ExecutorError(passError(pass, r.name, "a pass can have one index buffer"));
                    p.indexBuffer = static_cast<int32_t>(i);
                } else {
                    p.vertexBuffers.push_back(i);
                }
                p.graphics = true;
                break;
            case Stage::Indirect:
                if (r.isImage()) throw ExecutorError(passError(pass, r.name, "Indirect needs a buffer"));
                if (p.indirectBuffer >= 0)
                    throw ExecutorError(passError(pass, r.name, "a pass can have one indirect buffer"));
                p.indirectBuffer = static_cast<int32_t>(i);
                p.graphics = true;
                break;
            case Stage::Vertex:
            case Stage::Fragment:
            case Stage::Compute: {
                ShaderBinding b;
                b.usage = i;
                b.binding = nextBinding++;
                b.stage = u.usage.stage == Stage::Vertex     ? VK_SHADER_STAGE_VERTEX_BIT
                          : u.usage.stage == Stage::Fragment ? VK_SHADER_STAGE_FRAGMENT_BIT
                                                             : VK_SHADER_STAGE_COMPUTE_BIT;
                b.read = readsContents(u.usage.access);
                b.write = writesContents(u.usage.access);
                const BindAs as = resolvedBinding(u.usage, r.isImage());
                if (r.isImage()) {
                    b.scalarPrefix = scalarPrefix(r.format.format);
                    const bool wholeCube = r.type == ResourceType::Cube && u.range.layerCount == 6;
                    if (as == BindAs::Sampled) {
                        b.kind = BindKind::SampledImage;
                        b.viewType = wholeCube ? VK_IMAGE_VIEW_TYPE_CUBE
                                     : (u.range.layerCount > 1 || r.type != ResourceType::Image2D)
                                         ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                                         : VK_IMAGE_VIEW_TYPE_2D;
                    } else if (as == BindAs::Storage) {
                        b.kind = BindKind::StorageImage;
                        b.levels = std::max(u.range.mipCount, 1u);
                        b.viewType = (u.range.layerCount > 1 || r.type != ResourceType::Image2D)
                                         ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                                         : VK_IMAGE_VIEW_TYPE_2D;
                        b.glslFormat = glslStorageFormat(r.format.format);
                        if (b.read && b.glslFormat.empty()) {
                            throw ExecutorError(passError(pass, r.name,
                                                    "format " + std::string(r.format.name) +
                                                        " cannot be read as a storage image"));
                        }
                        if (!b.read) b.glslFormat.clear();  // write-only: no qualifier needed
                    } else {
                        throw ExecutorError(passError(pass, r.name, "an image cannot be a uniform buffer"));
                    }
                } else {
                    if (as == BindAs::Uniform) {
                        b.kind = BindKind::UniformBuffer;
                        b.uniformVec4s = static_cast<uint32_t>(
                            std::clamp<uint64_t>(r.sizeBytes / 16, 1, 1024));
                    } else {
                        b.kind = BindKind::StorageBuffer;
                    }
                    if (r.sizeBytes < 4)
                        throw ExecutorError(passError(pass, r.name, "buffer is smaller than 4 bytes"));
                }
                if (b.stage == VK_SHADER_STAGE_COMPUTE_BIT) {
                    p.computeBindings.push_back(b);
                    p.compute = true;
                } else {
                    p.graphicsBindings.push_back(b);
                    p.graphics = true;
                }
                break;
            }
        }
    }
    for (uint32_t c : p.colors) p.attachmentLayers = std::max(p.attachmentLayers, pass.usages[c].range.layerCount);
    if (p.depth >= 0)
        p.attachmentLayers = std::max(p.attachmentLayers, pass.usages[size_t(p.depth)].range.layerCount);
    if (p.attachmentLayers > 1 && !layeredRendering) {
        throw ExecutorError(passError(pass, "", "rendering to several layers needs shaderOutputLayer"));
    }

    const std::string header =
        "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
        "#include \"generic_common.glsl\"\n"
        "layout(push_constant) uniform PC { uvec4 extent; } pc;\n";

    if (p.graphics) {
        std::ostringstream vs;
        vs << header;
        if (p.attachmentLayers > 1) {
            vs << "#extension GL_ARB_shader_viewport_layer_array : require\n";
        }
        for (const auto& b : p.graphicsBindings)
            if (b.stage == VK_SHADER_STAGE_VERTEX_BIT) vs << declare(b);
        for (size_t v = 0; v < p.vertexBuffers.size(); ++v)
            vs << "layout(location = " << v << ") in float attr" << v << ";\n";
        vs << "layout(location = 0) flat out vec4 vAcc;\n"
           << "void main() {\n"
           << "    vec4 acc = " << vec4Literal(p.color) << ";\n"
           << "    ivec2 xy = ivec2(gl_VertexIndex, 0);\n"
           << "    uint li = uint(gl_VertexIndex);\n";
        for (size_t v = 0; v < p.vertexBuffers.size(); ++v)
            vs << "    if (isnan(attr" << v << ")) acc.w += 0.0;\n";
        vs << body(p.graphicsBindings, VK_SHADER_STAGE_VERTEX_BIT)
           << "    vAcc = acc;\n"
           << "    gl_Position = vec4(kFullscreen[gl_VertexIndex & 3], " << p.depthValue << ", 1.0);\n";
        if (p.attachmentLayers > 1) vs << "    gl_Layer = gl_InstanceIndex;\n";
        vs << "}\n";
        p.vertexSource = vs.str();

        std::ostringstream fs;
        fs << header;
        for (const auto& b : p.graphicsBindings)
            if (b.stage == VK_SHADER_STAGE_FRAGMENT_BIT) fs << declare(b);
        // A Read attachment gets no output: the load op reads it, and a draw into it would be a
        // write the plan never ordered (blending writes even with every channel masked).
        const auto drawnInto = [&](size_t c) { return resources[p.colors[c]].usage->usage.access != Access::Read; };
        for (size_t c = 0; c < p.colors.size(); ++c) {
            if (!drawnInto(c)) continue;
            const ResourceDesc& r = *resources[p.colors[c]].desc;
            fs << "layout(location = " << c << ") out " << scalarPrefix(r.format.format)
               << "vec4 o" << c << ";\n";
        }
        fs << "layout(location = 0) flat in vec4 vAcc;\n"
           << "void main() {\n"
           << "    vec4 acc = vAcc;\n"
           << "    ivec2 xy = ivec2(gl_FragCoord.xy);\n"
           << "    uint li = uint(xy.y) * pc.extent.x + uint(xy.x);\n"
           << body(p.graphicsBindings, VK_SHADER_STAGE_FRAGMENT_BIT);
        for (size_t c = 0; c < p.colors.size(); ++c) {
            if (!drawnInto(c)) continue;
            const ResourceDesc& r = *resources[p.colors[c]].desc;
            fs << "    o" << c << " = " << scalarPrefix(r.format.format) << "vec4(genericOutput(acc));\n";
        }
        fs << "}\n";
        p.fragmentSource = fs.str();
    }
    if (p.compute) {
        std::ostringstream cs;
        cs << header << "layout(local_size_x = 8, local_size_y = 8) in;\n";
        for (const auto& b : p.computeBindings) cs << declare(b);
        cs << "void main() {\n"
           << "    vec4 acc = " << vec4Literal(p.color) << ";\n"
           << "    ivec2 xy = ivec2(gl_GlobalInvocationID.xy);\n"
           << "    if (any(greaterThanEqual(uvec2(xy), pc.extent.xy))) return;\n"
           << "    uint li = uint(xy.y) * pc.extent.x + uint(xy.x);\n"
           << body(p.computeBindings, VK_SHADER_STAGE_COMPUTE_BIT) << "}\n";
        p.computeSource = cs.str();
    }
    return p;
}

}  // namespace skygraph::passes
