// SpirvDiskCache: see spirv_cache.hpp. Entry layout (native endianness, the cache is local):
//   "skygraph-spirv-1\n", u64 key size, key, u32 include count,
//   per include: u64 path size, path, u64 content hash; then u64 word count, SPIR-V words.
#include "spirv_cache.hpp"

#include "read_file.hpp"
#include "replace_file.hpp"

#include <cstdlib>
#include <cstring>

namespace skygraph {
namespace {

constexpr std::string_view kMagic = "skygraph-spirv-1\n";
constexpr uint32_t kSpirvMagic = 0x07230203;

/// Reads a whole entry and walks it with bounds checks: a truncated or foreign file misses.
class Reader {
public:
    explicit Reader(std::string bytes) : bytes_(std::move(bytes)) {}
    bool bytes(size_t n, std::string_view& out) {
        if (n > bytes_.size() - at_) return false;
        out = std::string_view(bytes_).substr(at_, n);
        at_ += n;
        return true;
    }
    template <class T>
    bool value(T& out) {
        std::string_view raw;
        if (!bytes(sizeof(T), raw)) return false;
        std::memcpy(&out, raw.data(), sizeof(T));
        return true;
    }
    bool text(std::string_view& out) {
        uint64_t n = 0;
        return value(n) && bytes(size_t(n), out);
    }
    [[nodiscard]] bool atEnd() const { return at_ == bytes_.size(); }

private:
    std::string bytes_;
    size_t at_ = 0;
};

template <class T>
void put(std::string& out, const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void putText(std::string& out, std::string_view s) {
    put(out, uint64_t(s.size()));
    out.append(s);
}

std::filesystem::path entryPath(const std::filesystem::path& dir, const std::string& key) {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.spv", static_cast<unsigned long long>(SpirvDiskCache::hash(key)));
    return dir / name;
}

}  // namespace

uint64_t SpirvDiskCache::hash(std::string_view bytes) noexcept {
    uint64_t h = 0xcbf29ce484222325ull;
    for (const unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

std::optional<std::vector<uint32_t>> SpirvDiskCache::find(const std::string& key, const IncludeReader& read) const {
    if (dir_.empty()) return std::nullopt;
    auto file = files::readFile(entryPath(dir_, key));
    if (!file) return std::nullopt;
    Reader in(std::move(*file));
    std::string_view magic, storedKey;
    uint32_t includes = 0;
    if (!in.bytes(kMagic.size(), magic) || magic != kMagic || !in.text(storedKey) || storedKey != key ||
        !in.value(includes))
        return std::nullopt;
    for (uint32_t i = 0; i < includes; ++i) {
        std::string_view path;
        uint64_t storedHash = 0;
        if (!in.text(path) || !in.value(storedHash)) return std::nullopt;
        const std::string* now = read(std::filesystem::path(path));
        if (!now || hash(*now) != storedHash) return std::nullopt;
    }
    uint64_t words = 0;
    std::string_view raw;
    if (!in.value(words) || words == 0 || words > (1u << 26) || !in.bytes(size_t(words) * 4, raw) || !in.atEnd())
        return std::nullopt;
    std::vector<uint32_t> spirv(static_cast<size_t>(words));
    std::memcpy(spirv.data(), raw.data(), raw.size());
    if (spirv[0] != kSpirvMagic) return std::nullopt;
    return spirv;
}

void SpirvDiskCache::store(const std::string& key, const std::vector<IncludedFile>& includes,
                           const std::vector<uint32_t>& spirv) const noexcept {
    if (dir_.empty() || spirv.empty()) return;
    try {
        std::string out(kMagic);
        putText(out, key);
        put(out, uint32_t(includes.size()));
        for (const IncludedFile& f : includes) {
            putText(out, f.path.string());
            put(out, f.contentHash);
        }
        put(out, uint64_t(spirv.size()));
        out.append(reinterpret_cast<const char*>(spirv.data()), spirv.size() * 4);

        std::error_code ec;
        std::filesystem::create_directories(dir_, ec);
        // Whole or not at all: another process may read the entry at any moment.
        files::replaceFileContents(entryPath(dir_, key), out);
    } catch (...) {
        // Out of memory or a filesystem error: the next run compiles again.
    }
}

}  // namespace skygraph
