#include <skygraph/shader_compiler.hpp>

#include <skygraph/device.hpp>

#include "read_file.hpp"
#include "spirv_cache.hpp"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/build_info.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace skygraph {
namespace {

/// Resolves `#include "x"` against one directory, taking each file's text from `read`; owns
/// the loaded text until released, and remembers what it loaded (by content) for the disk cache.
class DirIncluder final : public glslang::TShader::Includer {
public:
    DirIncluder(std::filesystem::path dir, SpirvDiskCache::IncludeReader read)
        : dir_(std::move(dir)), read_(std::move(read)) {}

    IncludeResult* includeLocal(const char* headerName, const char*, size_t depth) override {
        return load(headerName, depth);
    }
    IncludeResult* includeSystem(const char* headerName, const char*, size_t depth) override {
        return load(headerName, depth);
    }
    void releaseInclude(IncludeResult* result) override {
        if (result) {
            delete static_cast<std::string*>(result->userData);
            delete result;
        }
    }
    [[nodiscard]] const std::vector<IncludedFile>& loaded() const noexcept { return loaded_; }

private:
    /// Deeper than any include tree: a file that includes itself, directly or through others,
    /// without a guard would be expanded until memory runs out.
    static constexpr size_t kMostIncludeDepth = 64;

    IncludeResult* load(const char* name, size_t depth) {
        if (depth > kMostIncludeDepth) {
            // glslang's convention: no header name, and the text is the error.
            auto* error = new std::string("#include nested deeper than " + std::to_string(kMostIncludeDepth) +
                                          " levels at '" + name + "': an include cycle without an include guard?");
            return new IncludeResult("", error->data(), error->size(), error);
        }
        const auto path = std::filesystem::absolute(dir_ / name).lexically_normal();
        const std::string* kept = read_(path);
        if (!kept) return nullptr;
        auto* text = new std::string(*kept);
        loaded_.push_back({path, SpirvDiskCache::hash(*text)});
        return new IncludeResult(path.string(), text->data(), text->size(), text);
    }
    std::filesystem::path dir_;
    SpirvDiskCache::IncludeReader read_;
    std::vector<IncludedFile> loaded_;
};

EShLanguage toLanguage(VkShaderStageFlagBits stage) {
    switch (stage) {
        case VK_SHADER_STAGE_VERTEX_BIT: return EShLangVertex;
        case VK_SHADER_STAGE_FRAGMENT_BIT: return EShLangFragment;
        case VK_SHADER_STAGE_COMPUTE_BIT: return EShLangCompute;
        case VK_SHADER_STAGE_GEOMETRY_BIT: return EShLangGeometry;
        default: throw ExecutorError("unsupported shader stage");
    }
}

std::mutex& processMutex() {
    static std::mutex m;
    return m;
}
int& processRefs() {
    static int refs = 0;
    return refs;
}

}  // namespace

std::filesystem::path ShaderCompiler::defaultIncludeDir() {
    namespace fs = std::filesystem;
    std::error_code ec;
    // An explicit override first; then the copy installed beside a `skygraph` executable (a
    // relocated prefix); then the source tree, so build-tree binaries see edits; then the
    // prefix the build was configured for (cmake/install.cmake).
    if (const char* env = std::getenv("SKYGRAPH_SHADER_DIR"); env && *env) return env;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path besideExe = exe.parent_path() / SKYGRAPH_SHADER_DIR_FROM_BINDIR;
        if (fs::is_directory(besideExe / "passes", ec)) return besideExe.lexically_normal();
    }
    if (fs::is_directory(SKYGRAPH_SHADER_DIR, ec)) return SKYGRAPH_SHADER_DIR;
    return SKYGRAPH_SHADER_INSTALL_DIR;
}

std::filesystem::path ShaderCompiler::defaultCacheDir() {
    if (const char* dir = std::getenv("SKYGRAPH_SHADER_CACHE")) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return std::filesystem::path(xdg) / "skygraph" / "spirv";
    if (const char* home = std::getenv("HOME"); home && *home)
        return std::filesystem::path(home) / ".cache" / "skygraph" / "spirv";
    return {};
}

ShaderCompiler::ShaderCompiler(std::filesystem::path includeDir, std::filesystem::path cacheDir)
    : includeDir_(includeDir.empty() ? defaultIncludeDir() : std::move(includeDir)),
      cacheDir_(std::move(cacheDir)) {
    std::lock_guard lock(processMutex());
    if (processRefs()++ == 0) glslang::InitializeProcess();
}

ShaderCompiler::~ShaderCompiler() {
    std::lock_guard lock(processMutex());
    if (--processRefs() == 0) glslang::FinalizeProcess();
}

const std::string* ShaderCompiler::keptFile(const std::filesystem::path& path) {
    const std::string key = std::filesystem::absolute(path).lexically_normal().generic_string();
    if (auto it = sources_.find(key); it != sources_.end()) return &it->second;
    std::optional<std::string> text = files::readFile(path);
    return text ? &sources_.emplace(key, std::move(*text)).first->second : nullptr;
}

std::string ShaderCompiler::source(const std::filesystem::path& relativePath) {
    const auto path = includeDir_ / relativePath;
    std::lock_guard lock(mutex_);
    if (const std::string* text = keptFile(path)) return *text;
    throw ExecutorError("shader '" + path.string() + "' cannot be read");
}

std::vector<uint32_t> ShaderCompiler::compileFile(VkShaderStageFlagBits stage,
                                                  const std::filesystem::path& relativePath) {
    return compile(stage, source(relativePath), (includeDir_ / relativePath).string());
}

void ShaderCompiler::clear() {
    std::lock_guard lock(mutex_);
    cache_.clear();
    sources_.clear();
}

bool ShaderCompiler::keptFilesChanged() {
    std::lock_guard lock(mutex_);
    return std::any_of(sources_.begin(), sources_.end(), [](const auto& kept) {
        const std::optional<std::string> now = files::readFile(kept.first);
        return now && !now->empty() && *now != kept.second;  // missing or empty: mid-save
    });
}

std::vector<uint32_t> ShaderCompiler::compile(VkShaderStageFlagBits stage,
                                              const std::string& source,
                                              const std::string& name) {
    const std::string key = std::to_string(static_cast<int>(stage)) + '\n' + source;
    std::lock_guard lock(mutex_);
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;

    // The disk cache's key also names glslang and the include directory: the same text
    // compiles differently with another compiler or other includes.
    const std::string diskKey = "glslang " + std::to_string(GLSLANG_VERSION_MAJOR) + "." +
                                std::to_string(GLSLANG_VERSION_MINOR) + "." + std::to_string(GLSLANG_VERSION_PATCH) +
                                "\n" + includeDir_.string() + "\n" + key;
    // Included files as this compiler includes them: kept since their first read, like sources.
    const SpirvDiskCache::IncludeReader read = [this](const std::filesystem::path& path) { return keptFile(path); };
    const SpirvDiskCache disk(cacheDir_);
    if (auto spirv = disk.find(diskKey, read)) {
        cache_.emplace(key, *spirv);
        return std::move(*spirv);
    }

    const EShLanguage lang = toLanguage(stage);
    glslang::TShader shader(lang);
    const char* text = source.c_str();
    const char* names = name.c_str();
    shader.setStringsWithLengthsAndNames(&text, nullptr, &names, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_3);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    DirIncluder includer(includeDir_, read);
    if (!shader.parse(GetDefaultResources(), 450, false, messages, includer)) {
        throw ExecutorError("shader '" + name + "' does not compile:\n" + shader.getInfoLog());
    }
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) {
        throw ExecutorError("shader '" + name + "' does not link:\n" + program.getInfoLog());
    }
    std::vector<uint32_t> spirv;
    glslang::SpvOptions spvOptions;
    spvOptions.validate = false;
    glslang::GlslangToSpv(*program.getIntermediate(lang), spirv, &spvOptions);
    ++compilations_;
    disk.store(diskKey, includer.loaded(), spirv);
    cache_.emplace(key, spirv);
    return spirv;
}

}  // namespace skygraph
