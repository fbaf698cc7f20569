// What SkyboxPass can fade between, checked when a graph loads (skybox_type.cpp) and when its
// pipeline is made (skybox_pass.cpp).
#pragma once

#include <skygraph/graph.hpp>

#include <optional>
#include <string>

namespace skygraph::passes {

/// Why SkyboxPass cannot fade from `previous` to `environment` (null where the slot is not
/// bound), or nothing: the fade blends two cubemaps.
[[nodiscard]] inline std::optional<std::string> skyboxFadeProblem(const ResourceDesc* environment,
                                                                  const ResourceDesc* previous) {
    if (!previous || (environment && environment->type == ResourceType::Cube && previous->type == ResourceType::Cube))
        return std::nullopt;
    return "SkyboxPass fades between cubemaps: 'environment' and 'previous' must both be cubes";
}

}  // namespace skygraph::passes
