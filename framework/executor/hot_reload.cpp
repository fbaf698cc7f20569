// Hot reload of the graph file and the shader directory.
#include <skygraph/shader_compiler.hpp>

#include <skygraph/hot_reload.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>

#include "read_file.hpp"

#include <spdlog/spdlog.h>

#include <functional>
#include <map>
#include <optional>

namespace skygraph {
namespace {

/// A watched file that is missing (deleted, or renamed away mid-save) hashes apart from
/// every content, so that its return is seen as a change even with the same text.
constexpr size_t kMissing = 0x6d697373696e67;  // "missing"
/// An empty file, told apart from every content so that midSave() can see it.
constexpr size_t kEmpty = 0x656d707479;  // "empty"

size_t hashFile(const std::filesystem::path& p) {
    const std::optional<std::string> text = files::readFile(p);
    if (!text) return kMissing;
    return text->empty() ? kEmpty : std::hash<std::string>{}(*text);
}

/// A file that held text and is empty now was truncated by a save in place not written yet.
bool midSave(size_t now, size_t before) { return now == kEmpty && before != kEmpty; }

std::map<std::filesystem::path, size_t> hashDir(const std::filesystem::path& dir) {
    // error_code overloads throughout: files deleted or the directory removed while it is
    // listed must not throw out of poll(); what is gone simply hashes differently.
    std::map<std::filesystem::path, size_t> files;
    std::error_code ec;
    for (std::filesystem::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (it->is_regular_file(ec)) files.emplace(it->path(), hashFile(it->path()));
    return files;
}

}  // namespace

HotReloader::HotReloader(Renderer& renderer, std::filesystem::path graphFile, std::filesystem::path shaderDir,
                         const PassRegistry* registry)
    : renderer_(&renderer), graphFile_(std::move(graphFile)),
      shaderDir_(shaderDir.empty() ? renderer.shaderDir() : std::move(shaderDir)),
      registry_(registry ? registry : &ownRegistry_) {
    if (!registry) {
        // The library's declarations first: a type it redeclares records with its factory,
        // so its graphs are parsed against its declaration, not the built-in one.
        const PassRegistry builtins = PassRegistry::withBuiltins();
        if (const PassLibrary* library = renderer.passes()) ownRegistry_ = library->registry();
        for (const std::string& name : builtins.names())
            if (!ownRegistry_.find(name)) ownRegistry_.add(*builtins.find(name));
    }
    graphHash_ = hashFile(graphFile_);
    shaderHashes_ = hashDir(shaderDir_);
}

HotReloader::Result HotReloader::poll() {
    const size_t g = hashFile(graphFile_);
    std::map<std::filesystem::path, size_t> s = hashDir(shaderDir_);
    // Until a save in place is written, nothing is taken from any file: a reload then would
    // read the empty file with the others.
    if (midSave(g, graphHash_)) return Result::Unchanged;
    for (const auto& [file, hash] : s)
        if (const auto before = shaderHashes_.find(file); before != shaderHashes_.end() && midSave(hash, before->second))
            return Result::Unchanged;
    if (g == graphHash_ && s == shaderHashes_) return Result::Unchanged;
    // Edits that a failed reload left unapplied are applied with this one: a fixed shader
    // must not run the graph from before an edit that failed only for the shader's sake.
    const bool graphChanged = g != graphHash_;
    graphPending_ |= graphChanged;
    shadersPending_ |= s != shaderHashes_;
    graphHash_ = g;
    shaderHashes_ = std::move(s);
    // Deleted while watched: keep rendering the last good plan and say so once, when it goes;
    // shader edits meanwhile go to the running plan, and the file's return (any content) is
    // the next change.
    const bool graphGone = graphPending_ && g == kMissing;
    if (graphGone && graphChanged) {
        lastError_ = graphFile_.string() + ": the watched graph file is gone (deleted or renamed); the "
                     "previous version keeps running until it is back";
        spdlog::warn("hot reload: {}", lastError_);
        return Result::Failed;
    }
    const bool graph = graphPending_ && !graphGone;
    try {
        if (graph) {
            GraphDesc desc = loadGraphFile(graphFile_, *registry_);
            // One rebuild for both: the new graph and the edited shaders run together or not at all.
            renderer_->setGraph(renderer_->compiled().withGraph(std::move(desc)),
                               shadersPending_ ? Renderer::ShaderSources::Reread : Renderer::ShaderSources::Cached);
        } else {
            renderer_->reloadShaders();
        }
        lastError_.clear();
        spdlog::info("hot reload: {}{}{} reloaded", graph ? graphFile_.string() : "",
                     graph && shadersPending_ ? " and " : "", shadersPending_ ? shaderDir_.string() : "");
        if (graph) graphPending_ = false;
        shadersPending_ = false;
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
