// Shared by the glTF tests: where Debian's assimp-testmodels are, and diagnostics as text.
#pragma once

#include <skygraph/diagnostics.hpp>

#include <filesystem>
#include <string>

namespace skygraph::gltf_test {

inline const std::filesystem::path kModels = "/usr/share/assimp/models/glTF2";

inline std::string messages(const Diagnostics& d) {
    std::string s;
    for (const Diagnostic& x : d.items()) s += x.format() + "\n";
    return s;
}

}  // namespace skygraph::gltf_test
