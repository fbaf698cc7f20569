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
#include <type_traits>

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

struct HotReloader::State {
    Renderer* renderer;
    std::filesystem::path graphFile;
    std::filesystem::path shaderDir;
    PassRegistry ownRegistry;  ///< When none is given.
    const PassRegistry* registry = nullptr;  ///< The given one, or ownRegistry.
    size_t graphHash = 0;
    std::map<std::filesystem::path, size_t> shaderHashes;  ///< Per file under shaderDir.
    bool graphPending = false;  ///< Edited since the last reload that succeeded.
    bool shadersPending = false;
    std::string lastError;
};

HotReloader::HotReloader(Renderer& renderer, std::filesystem::path graphFile, std::filesystem::path shaderDir,
                         const PassRegistry* registry)
    : state_(std::make_unique<State>()) {
    State& st = *state_;
    st.renderer = &renderer;
    st.graphFile = std::move(graphFile);
    const bool shaderDirGiven = !shaderDir.empty();
    st.shaderDir = shaderDirGiven ? std::move(shaderDir) : renderer.shaderDir();
    st.registry = registry ? registry : &st.ownRegistry;
    if (!registry) {
        // The library's declarations first: a type it redeclares records with its factory,
        // so its graphs are parsed against its declaration, not the built-in one.
        const PassRegistry builtins = PassRegistry::withBuiltins();
        if (const PassLibrary* library = renderer.passes()) st.ownRegistry = library->registry();
        for (const std::string& name : builtins.names())
            if (!st.ownRegistry.find(name)) st.ownRegistry.add(*builtins.find(name));
    }
    // A path that is not there would be watched in vain: a typo must not pass for "no change".
    std::error_code ec;
    if (!st.graphFile.empty() && !std::filesystem::is_regular_file(st.graphFile, ec))
        throw ExecutorError("HotReloader: the graph file '" + st.graphFile.string() + "' does not exist");
    if (shaderDirGiven && !std::filesystem::is_directory(st.shaderDir, ec))
        throw ExecutorError("HotReloader: the shader directory '" + st.shaderDir.string() + "' does not exist");
    st.graphHash = hashFile(st.graphFile);
    st.shaderHashes = hashDir(st.shaderDir);
}

HotReloader::~HotReloader() = default;

// The pimpl must not add moves the class never offered: deleted copies (a copy would reload
// every change into the same renderer twice) leave no move declared, so neither is possible.
static_assert(!std::is_copy_constructible_v<HotReloader> && !std::is_move_constructible_v<HotReloader>);
static_assert(!std::is_copy_assignable_v<HotReloader> && !std::is_move_assignable_v<HotReloader>);

const std::string& HotReloader::lastError() const noexcept { return state_->lastError; }

void HotReloader::follow(Renderer& renderer) noexcept { state_->renderer = &renderer; }

HotReloader::Result HotReloader::poll() {
    State& st = *state_;
    const size_t g = hashFile(st.graphFile);
    std::map<std::filesystem::path, size_t> s = hashDir(st.shaderDir);
    // Until a save in place is written, nothing is taken from any file: a reload then would
    // read the empty file with the others.
    if (midSave(g, st.graphHash)) return Result::Unchanged;
    for (const auto& [file, hash] : s)
        if (const auto before = st.shaderHashes.find(file); before != st.shaderHashes.end() && midSave(hash, before->second))
            return Result::Unchanged;
    if (g == st.graphHash && s == st.shaderHashes) return Result::Unchanged;
    // Edits that a failed reload left unapplied are applied with this one: a fixed shader
    // must not run the graph from before an edit that failed only for the shader's sake.
    const bool graphChanged = g != st.graphHash;
    st.graphPending |= graphChanged;
    st.shadersPending |= s != st.shaderHashes;
    st.graphHash = g;
    st.shaderHashes = std::move(s);
    // Deleted while watched: keep rendering the last good plan and say so once, when it goes;
    // shader edits meanwhile go to the running plan, and the file's return (any content) is
    // the next change.
    const bool graphGone = st.graphPending && g == kMissing;
    if (graphGone && graphChanged) {
        st.lastError = st.graphFile.string() + ": the watched graph file is gone (deleted or renamed); the "
                       "previous version keeps running until it is back";
        spdlog::warn("hot reload: {}", st.lastError);
        return Result::Failed;
    }
    const bool graph = st.graphPending && !graphGone;
    try {
        if (graph) {
            GraphDesc desc = loadGraphFile(st.graphFile, *st.registry);
            // One rebuild for both: the new graph and the edited shaders run together or not at all.
            st.renderer->setGraph(st.renderer->compiled().withGraph(std::move(desc)),
                                  st.shadersPending ? Renderer::ShaderSources::Reread : Renderer::ShaderSources::Cached);
        } else {
            st.renderer->reloadShaders();
        }
        st.lastError.clear();
        spdlog::info("hot reload: {}{}{} reloaded", graph ? st.graphFile.string() : "",
                     graph && st.shadersPending ? " and " : "", st.shadersPending ? st.shaderDir.string() : "");
        if (graph) st.graphPending = false;
        st.shadersPending = false;
        return Result::Reloaded;
    } catch (const GraphError& e) {
        st.lastError = e.diagnostics().format();
    } catch (const std::exception& e) {
        st.lastError = e.what();
    }
    spdlog::warn("hot reload failed; the previous version keeps running:\n{}", st.lastError);
    return Result::Failed;
}

}  // namespace skygraph
