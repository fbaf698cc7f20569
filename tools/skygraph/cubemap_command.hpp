// `skygraph cubemap IN.(hdr|exr) -o OUT.ktx2`: an equirect HDR image to a KTX2 cube with its
// mip chain, plus the IBL products (irradiance, GGX prefiltered specular, BRDF table) each
// in a KTX2 file beside it, and optionally a cross-layout .hdr/.exr for viewing.
#pragma once

#include "cli_common.hpp"

namespace skygraph::cli {

/// Adds the `cubemap` subcommand to `parent` (which owns it).
[[nodiscard]] Command addCubemapCommand(CLI::App& parent);

}  // namespace skygraph::cli
