// One fuzz input through the glTF loader (gltf_fuzz_target.cpp).
#pragma once

#include <string_view>

namespace skygraph::fuzz {

/// Loads `bytes` as a .gltf or .glb file. Returns normally on a mesh, or on no mesh with at
/// least one diagnostic; aborts on anything else (an escaping exception, a mesh that breaks
/// its own invariants), so that libFuzzer and the replay test both see the failure.
void runOneGltfInput(std::string_view bytes);

}  // namespace skygraph::fuzz
