// Shared by the glTF tests: where Debian's assimp-testmodels are, diagnostics as text, and the
// check that a file is refused with a message naming where.
#pragma once

#include <skygraph/diagnostics.hpp>
#include <skygraph/triangle_mesh.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace skygraph::gltf_test {

inline const std::filesystem::path kModels = "/usr/share/assimp/models/glTF2";

inline std::string messages(const Diagnostics& d) {
    std::string s;
    for (const Diagnostic& x : d.items()) s += x.format() + "\n";
    return s;
}

/// loadGltf(file) draws nothing, and its first diagnostic is at `jsonPath` with `message` in
/// its text.
inline void expectRefusedAt(const std::filesystem::path& file, const std::string& jsonPath,
                            const std::string& message, const GltfLimits& limits = {}) {
    Diagnostics d;
    EXPECT_FALSE(loadGltf(file, {}, d, limits));
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.items()[0].jsonPath, jsonPath) << messages(d);
    EXPECT_NE(d.items()[0].message.find(message), std::string::npos) << messages(d);
}

}  // namespace skygraph::gltf_test
