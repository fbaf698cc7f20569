// Hot reload of the graph file and the shader directory.
#include <skygraph/shader_compiler.hpp>

#include <skygraph/executor.hpp>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>

namespace skygraph {
namespace {

std::string readAll(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

size_t hashFile(const std::filesystem::path& p) { return std::hash<std::string>{}(readAll(p)); }

size_t hashDir(const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec))
        if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    size_t h = 0;
    for (const auto& f : files) h = h * 31 + std::hash<std::string>{}(f.string() + readAll(f));
    return h;
}

}  // namespace

HotReloader::HotReloader(Renderer& renderer, std::filesystem::path graphFile, CompileOptions options,
                         std::filesystem::path shaderDir, const PassRegistry* registry)
    : renderer_(renderer), graphFile_(std::move(graphFile)), options_(std::move(options)),
      shaderDir_(shaderDir.empty() ? ShaderCompiler::defaultIncludeDir() : std::move(shaderDir)),
      registry_(registry) {
    graphHash_ = hashFile(graphFile_);
    shaderHash_ = hashDir(shaderDir_);
}

HotReloader::Result HotReloader::poll() {
    const size_t g = hashFile(graphFile_);
    const size_t s = hashDir(shaderDir_);
    if (g == graphHash_ && s == shaderHash_) return Result::Unchanged;
    const bool graphChanged = g != graphHash_;
    graphHash_ = g;
    shaderHash_ = s;
    try {
        if (graphChanged) {
            GraphDesc graph = registry_ ? loadGraphFile(graphFile_, *registry_)
                                        : loadGraphFile(graphFile_, PassRegistry::withBuiltins());
            Plan plan = compile(graph, options_);
            renderer_.setPlan(graph, std::move(plan));
        } else {
            renderer_.reloadShaders();
        }
        lastError_.clear();
        spdlog::info("hot reload: {} reloaded", graphChanged ? graphFile_.string() : shaderDir_.string());
        return Result::Reloaded;
    } catch (const GraphError& e) {
        lastError_ = e.diagnostics().format();
    } catch (const std::exception& e) {
        lastError_ = e.what();
    }
    spdlog::warn("hot reload failed; the previous version keeps running:\n{}", lastError_);
    return Result::Failed;
}

}  // namespace skygraph
