// SPIR-V kept on disk between runs, so that a run does not pay glslang for shaders that have
// not changed (about 0.1 s of CPU per run of `skygraph cubemap` on this machine).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph {

/// One file a shader #included, by content: a cached entry is only reused while every file
/// it included still hashes the same.
struct IncludedFile {
    std::filesystem::path path;
    uint64_t contentHash = 0;
};

/// Entries are files named by the hash of their key; each stores the whole key, so a hash
/// collision is a miss, never a wrong shader. Writes go to a temporary file renamed into
/// place: a reader sees a whole entry or none. Every I/O failure is a miss (find) or is
/// ignored (store): the cache can only save time.
class SpirvDiskCache {
public:
    /// `dir` empty: disabled (find() misses, store() does nothing).
    explicit SpirvDiskCache(std::filesystem::path dir) : dir_(std::move(dir)) {}

    /// The text of an included file as the compile would include it (borrowed from the
    /// compiler); null when it cannot be read.
    using IncludeReader = std::function<const std::string*(const std::filesystem::path&)>;

    /// The SPIR-V stored for `key`, if its included files, as `read` gives them, are unchanged.
    [[nodiscard]] std::optional<std::vector<uint32_t>> find(const std::string& key, const IncludeReader& read) const;

    /// Stores `spirv` for `key` with the files it included.
    void store(const std::string& key, const std::vector<IncludedFile>& includes,
               const std::vector<uint32_t>& spirv) const noexcept;

    /// 64-bit FNV-1a: stable across runs, builds and machines (std::hash is not).
    [[nodiscard]] static uint64_t hash(std::string_view bytes) noexcept;

private:
    std::filesystem::path dir_;
};

}  // namespace skygraph
