// What SkyboxPass can fade between and what its `sampling` param may say, checked when a graph
// loads (skybox_type.cpp); the fade again when its pipeline is made (skybox_pass.cpp).
#pragma once

#include <skygraph/graph.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace skygraph::passes {

/// Why SkyboxPass cannot fade from `previous` to `environment` (null where the slot is not
/// bound), or nothing: the fade blends two cubemaps.
[[nodiscard]] inline std::optional<std::string> skyboxFadeProblem(const ResourceDesc* environment,
                                                                  const ResourceDesc* previous) {
    if (!previous || (environment && environment->type == ResourceType::Cube && previous->type == ResourceType::Cube))
        return std::nullopt;
    return "SkyboxPass fades between cubemaps: 'environment' and 'previous' must both be cubes";
}

/// Why `sampling` (the pass's "sampling" param) contradicts how SkyboxPass samples
/// `environment`, or nothing. The resource's type picks the shader (skybox_pass.cpp): a cube is
/// sampled as a cubemap, an image2d as an equirect map; the param only states which.
[[nodiscard]] inline std::optional<std::string> skyboxSamplingProblem(const ResourceDesc& environment,
                                                                      std::string_view sampling) {
    const bool cube = environment.type == ResourceType::Cube;
    const std::string_view sampled = cube ? "cubemap" : "equirect";
    // Another value is the params' error (skybox_type.cpp's rules), said there.
    if (sampling == sampled || (sampling != "cubemap" && sampling != "equirect")) return std::nullopt;
    return "SkyboxPass samples the " + std::string(toString(environment.type)) + " '" + environment.name + "' as " +
           (cube ? "a cubemap" : "an equirect map") + ", which its type decides, but \"sampling\" says \"" +
           std::string(sampling) + "\": say \"" + std::string(sampled) + "\" or bind " +
           (cube ? "an image2d" : "a cube");
}

}  // namespace skygraph::passes
