// Hot reload: recompiling a graph file and rebuilding shaders when they change on disk.
#pragma once

#include <skygraph/compiler.hpp>
#include <skygraph/pass_registry.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace skygraph {

class Renderer;

/// Hot reload: watches a graph file and a shader directory and, on a change, recompiles and
/// hands the result to a Renderer. A failed rebuild logs the compiler's message as a warning;
/// what keeps running then is poll()'s to say. Borrows the renderer (and the registry), which
/// must outlive it; owns its copies of the paths. Not copyable: a copy would reload every
/// change into the same renderer a second time. Use it on the renderer's thread: poll()
/// rebuilds the renderer.
class HotReloader {
public:
    enum class Result : uint8_t { Unchanged, Reloaded, Failed };

    /// Reads the watched files once, as the state later changes are measured against.
    /// `graphFile` empty: the shaders alone are watched (an application that reloads its
    /// graph itself).
    /// `shaderDir` empty: the renderer's (Renderer::shaderDir()). `registry` (borrowed) parses
    /// the reloaded graph; null: the types of the renderer's pass library (Renderer::passes())
    /// and the built-in types (PassRegistry::withBuiltins()) it does not declare, copied here:
    /// where the library declares a built-in type's name, its declaration is the one that
    /// counts, as its factory is the one that records. Both are fixed here:
    /// follow() keeps them. A reloaded graph compiles with the options the renderer's
    /// current graph was compiled with (Renderer::compiled()). Throws ExecutorError when the
    /// graph file or a `shaderDir` given does not exist.
    HotReloader(Renderer& renderer, std::filesystem::path graphFile, std::filesystem::path shaderDir = {},
                const PassRegistry* registry = nullptr);
    HotReloader(const HotReloader&) = delete;
    HotReloader& operator=(const HotReloader&) = delete;
    ~HotReloader();

    /// Checks the watched files (by content: it reads them all on every call) and, when any
    /// changed, applies every edit not yet applied in one rebuild: a changed graph is
    /// recompiled and handed to Renderer::setGraph() (with ShaderSources::Reread when the
    /// shaders changed too), a change to the shaders alone goes to Renderer::reloadShaders().
    /// Reloaded: the renderer's plan state was rebuilt, so references from its compiled(),
    /// plan() and graph() are invalid. A failed reload does not throw: it returns Failed, sets
    /// lastError(), and rebuilds nothing, so the previous plan and pipelines run and references
    /// from the renderer stay valid. Its edits stay pending, and the next poll() that sees
    /// another change (to any watched file) applies them with it: a graph edit that failed
    /// because a shader did not compile takes effect once the shader is fixed. While a watched
    /// file that held text is empty (truncated by a save in place, not written yet), nothing
    /// is reloaded, so such a save is one reload, not a failed one first.
    Result poll();
    /// The message of the last failed reload; empty after a success. The reference is valid
    /// until the next poll().
    [[nodiscard]] const std::string& lastError() const noexcept;

    /// Applies later edits to `renderer` (borrowed like the first) instead: one that replaced
    /// the watched renderer. What was seen so far stays the state changes are measured against,
    /// and edits a failed reload left pending stay pending, so that an edit saved while the
    /// replacement was being built is still applied to it.
    void follow(Renderer& renderer) noexcept;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace skygraph
