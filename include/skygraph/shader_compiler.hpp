// Run-time GLSL -> SPIR-V with glslang, with #include from a shader directory and a cache.
#pragma once

#include <atomic>
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

namespace skygraph {

/// Compiles GLSL at run time. Results are cached in memory by (stage, source) and, when a
/// cache directory is given, on disk as .spv files. compile(), compileFile(), source() and
/// clear() may be called from several threads at once (compilations then run one at a time).
class ShaderCompiler {
public:
    /// `includeDir` is searched for `#include "..."` (empty: defaultIncludeDir()); `cacheDir`
    /// may be empty (memory only). Disk cache failures are misses, never errors.
    explicit ShaderCompiler(std::filesystem::path includeDir, std::filesystem::path cacheDir = {});
    ~ShaderCompiler();
    ShaderCompiler(const ShaderCompiler&) = delete;
    ShaderCompiler& operator=(const ShaderCompiler&) = delete;

    /// SPIR-V for `source`, a copy the caller owns. Throws ExecutorError with glslang's log
    /// (prefixed with `name`) when the source does not compile, or for a stage other than
    /// vertex, fragment, compute or geometry.
    [[nodiscard]] std::vector<uint32_t> compile(VkShaderStageFlagBits stage,
                                                const std::string& source,
                                                const std::string& name);

    /// The text of `relativePath` under the include directory (e.g. "passes/tonemap.frag"),
    /// a copy the caller owns. Read from disk on its first call after construction or clear()
    /// and kept: later calls return the same text, so pipelines rebuilt for another reason (a
    /// resize) are built from the shaders that ran before, even while a file on disk is
    /// broken or half saved. Files a compile `#include`s are kept the same way. Throws
    /// ExecutorError when the file cannot be read.
    [[nodiscard]] std::string source(const std::filesystem::path& relativePath);

    /// Compiles source(relativePath); the stage comes from `stage`. Throws ExecutorError when
    /// the file cannot be read or does not compile.
    [[nodiscard]] std::vector<uint32_t> compileFile(VkShaderStageFlagBits stage,
                                                    const std::filesystem::path& relativePath);

    /// Forgets every cached result (memory only) and every kept source and included file, so
    /// that the next compiles read the shader directory again, e.g. after an edit.
    void clear();

    /// Whether a kept file, source or include, now reads differently on disk: whether an edit
    /// in the shader directory concerns what this compiler built. A file missing or empty is
    /// taken to be mid-save (renamed away or truncated by an editor), not changed. Reads only
    /// the kept files.
    [[nodiscard]] bool keptFilesChanged();

    /// Fixed at construction; the reference is valid while this compiler lives.
    [[nodiscard]] const std::filesystem::path& includeDir() const noexcept { return includeDir_; }
    /// Fixed at construction (empty: memory only); the reference is valid while this compiler lives.
    [[nodiscard]] const std::filesystem::path& cacheDir() const noexcept { return cacheDir_; }

    /// Number of compilations that actually ran glslang (cache misses) so far.
    [[nodiscard]] uint32_t compilations() const noexcept { return compilations_.load(std::memory_order_relaxed); }

    /// The shaders/ directory of the built-in passes, used when no include directory is given:
    /// $SKYGRAPH_SHADER_DIR if set; else share/skygraph/shaders beside the running executable's
    /// bin/ (an installed, possibly relocated prefix); else the source tree's shaders/ if it
    /// exists; else the install prefix configured at build time. Programs built against an
    /// installed package should pass SKYGRAPH_PACKAGE_SHADER_DIR instead (docs/embedding.md).
    [[nodiscard]] static std::filesystem::path defaultIncludeDir();

    /// Where compiled SPIR-V is kept between runs when no cache directory is given:
    /// $SKYGRAPH_SHADER_CACHE if set (empty: none); else $XDG_CACHE_HOME/skygraph/spirv; else
    /// ~/.cache/skygraph/spirv; else none (empty).
    [[nodiscard]] static std::filesystem::path defaultCacheDir();

private:
    std::filesystem::path includeDir_;
    std::filesystem::path cacheDir_;
    std::mutex mutex_;
    std::unordered_map<std::string, std::vector<uint32_t>> cache_;
    /// Shader and included files as first read, by absolute normal path; keptFile() reads them.
    std::unordered_map<std::string, std::string> sources_;
    std::atomic<uint32_t> compilations_{0};

    /// The kept text of the file at `path`, read on first use; null when it cannot be read.
    /// The caller holds mutex_.
    const std::string* keptFile(const std::filesystem::path& path);
};

}  // namespace skygraph
