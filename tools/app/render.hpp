// `skygraph render` as one call: compile a graph file, bake the environment it imports (graphs/
// ibl.json, once), render headless and write the swapchain target (or another resource).
// Application code: the command line links it, and so do the tests that render through it.
#pragma once

#include "environment_graph.hpp"

#include <array>
#include <skygraph/compiled_graph.hpp>
#include <skygraph/compiler.hpp>
#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>
#include <skygraph/hdr_image.hpp>
#include <skygraph/pass_registry.hpp>
#include <skygraph/plan.hpp>
#include <skygraph/scene.hpp>
#include <skygraph/staging_buffer.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace skygraph {
class Device;
class PassLibrary;
class Renderer;
class ShaderCompiler;
}

namespace skygraph::app {

/// `skygraph render`: options as parsed by the command line. A plain value; it borrows only
/// `passes`.
struct RenderOptions {
    std::filesystem::path graph;     ///< Required unless `graphText` is given.
    /// A graph in memory (the built-in default); used instead of `graph` when not empty.
    std::string graphText;
    /// A scene file (scenes/*.json). It decides the features (no objects: no forward pass;
    /// no environment: no skybox) and is handed to the passes; `features` still override.
    std::filesystem::path scene;
    std::string sceneText;           ///< A scene in memory; used instead of `scene` when not empty.
    /// The environment pipeline (graphs/ibl.json), run once when the scene's environment is a
    /// file, for the products the plan imports by name (`environment`, `irradiance`, ...).
    /// Named, it must exist; empty: ibl.json beside `graph`, when there is one.
    std::filesystem::path environmentGraph;
    std::string environmentGraphText;  ///< A graph in memory (the built-in one); wins over the file.
    /// Size the environment cube and the prefiltered cube for the view (output height and
    /// the scene camera's field of view, environment_graph.hpp), the graph's declared extents
    /// being the largest allowed. false: build them at the declared extents.
    bool fitEnvironmentToView = true;
    /// Replaces the scene's environment: an .hdr or .exr file, or, empty, the procedural sky.
    /// Unset: the scene's own.
    std::optional<std::filesystem::path> environmentFile;
    /// A frame of a sequence to bake the environment from, instead of the first, when the
    /// scene's sequence is that one: the view's rebuilds go on with playback. One that cannot
    /// be read is logged, and the first frame stands in (FrameInputs::sequenceFrame says which).
    struct SequenceFrame {
        EnvironmentSequence sequence;
        uint32_t frame = 0;
    };
    std::optional<SequenceFrame> sequenceFrame;
    /// Replaces the procedural sky's sun direction (unit) of the scene; ignored for a file.
    std::optional<std::array<double, 3>> sunDirection;
    FeatureValues features;          ///< Overrides of the graph's defaults.
    /// CompileOptions::aliasing: false gives every transient resource memory of its own.
    bool aliasing = true;
    /// CompileOptions::shareTransientsAcrossFrames: false gives each frame in flight heaps of its own.
    bool shareHeapsAcrossFrames = true;
    /// CompileOptions::clobberTransients: each transient is poisoned before its first use.
    bool clobberTransients = false;
    uint32_t width = 256;
    uint32_t height = 256;
    uint32_t frames = 3;
    uint32_t framesInFlight = 2;
    /// .png, .hdr or .exr. Empty: skygraph.png (or skygraph.<outputFormat>) when there is an
    /// image to write, else no file.
    std::filesystem::path output;
    /// "png", "hdr" or "exr"; empty: by the extension of `output`. Needed for a name without
    /// one of those extensions (/dev/stdout, a FIFO).
    std::string outputFormat;
    /// Resource to write instead of the swapchain target, e.g. "hdr_color" as .exr
    /// (CompileOptions::readbacks). A graph with neither writes no file.
    std::string readback;
    bool validate = false;           ///< Validation + sync validation; fail on any message.
    std::string device;
    /// Pass implementations (e.g. PassLibrary::withBuiltins() from skygraph_passes); borrowed
    /// for the call. Null: the built-in declarations, every pass recorded as Generic.
    const PassLibrary* passes = nullptr;
    /// Called after each frame is submitted with (frames submitted so far, `frames`), e.g. to
    /// draw a progress bar. May be empty.
    std::function<void(uint32_t submitted, uint32_t total)> onFrameSubmitted;
};

/// What `render` and `view` share before compiling: the graph and the scene loaded, the
/// environment file read (and the environment sized for the view), and the compile options the
/// scene, the features, the size and the memory options give. A plain value; borrows
/// RenderOptions::passes.
struct FrameInputs {
    PassRegistry registry;  ///< The declarations the graph was loaded with.
    /// The recording code: RenderOptions::passes, else Generic for every pass type.
    const PassLibrary* passes = nullptr;
    GraphDesc graph;
    std::optional<Scene> scene;
    std::optional<HdrImage> environment;  ///< The scene's environment: its file, or the procedural sky rendered to an equirect.
    /// The frame of the scene's sequence that `environment` is: RenderOptions::sequenceFrame's,
    /// or 0 (the first) when that one is not this sequence's or could not be read.
    uint32_t sequenceFrame = 0;
    std::optional<EnvironmentSizes> environmentSizes;
    /// Features, output size, aliasing and clobbering; the caller adds presentation or
    /// read-backs.
    CompileOptions compile;
};

/// Loads what `options` names. Throws GraphError for graph and scene files, std::exception
/// for others (an unreadable environment file).
[[nodiscard]] FrameInputs loadFrameInputs(const RenderOptions& options);

/// The environment a frame samples, baked once (graphs/ibl.json) for what `plan` imports.
struct FrameEnvironment {
    std::unique_ptr<Renderer> renderer;  ///< Owns the products; null when nothing was baked.
    std::set<std::string, std::less<>> products;
    /// The environment graph as baked, sized like the frame's imports: what a re-bake with
    /// another equirect of the same width runs (startBackgroundBake). Empty with no bake.
    std::optional<GraphDesc> graph;
};

/// The environment graph file a build reads: RenderOptions::environmentGraph (which must
/// exist), else graphs/ibl.json's name beside the graph file (read when it exists). Empty when
/// the build reads it from memory (environmentGraphText) or has no graph file.
[[nodiscard]] std::filesystem::path environmentGraphFile(const RenderOptions& options);

/// Bakes the environment products `plan` (compiled from inputs.graph) samples, when the scene
/// has an environment file; nothing otherwise. `shaders`: the bake builds from the shader
/// sources that compiler keeps (bakeEnvironment()), e.g. the last bake's, not from the files
/// on disk. The result must outlive the frame renderer's use of the products.
[[nodiscard]] FrameEnvironment bakeFrameEnvironment(Device& device, const Plan& plan, const FrameInputs& inputs,
                                                    const RenderOptions& options,
                                                    std::shared_ptr<ShaderCompiler> shaders = nullptr);

/// Hands `renderer` the scene (FrameData), the baked products (importImage) and the
/// environment file's pixels (setExternalImage; moved out of `inputs`).
void attachFrameInputs(Renderer& renderer, FrameInputs& inputs, const FrameEnvironment& environment);

/// What the UploadPasses of a frame graph copy in every frame of `render`, `check` and
/// `view`, which have no pixels of their own to stream: the scene's environment for the
/// equirect, zeros for anything else. Owns its staging buffers (made once).
class UploadPassPixels {
public:
    UploadPassPixels() = default;
    /// For each UploadPass of `renderer`'s plan, a staging buffer on `device` holding
    /// `environment` (float RGBA of the target's size) for the equirect, else zeros.
    UploadPassPixels(Device& device, const Renderer& renderer, const std::optional<HdrImage>& environment);
    /// Stages them for `renderer`'s next frame (Renderer::stageUpload).
    void stageFor(Renderer& renderer) const;

private:
    std::vector<std::pair<std::string, std::shared_ptr<const StagingBuffer>>> staged_;
};

/// A headless run: the environment baked for it and the frame's renderer, idle. Destroying it
/// destroys the renderer before the environment whose products it imported.
struct RenderedFrames {
    FrameEnvironment environment;
    std::unique_ptr<Renderer> renderer;
};

/// Throws `e` as a GraphError named at the declaration in `graph` of the resource it names,
/// with the output size (`compiled`'s, when given) for an extent that follows it; named at
/// `graph`'s file when it names no resource of `graph` (all of them together past a limit).
[[noreturn]] void throwAtDeclaration(const GraphDesc& graph, const DeviceCapacityError& e,
                                     const CompileOptions* compiled);
/// Throws `e` as a GraphError named at the declaration in `graph` of the resource it names;
/// `e` as it is when `graph` declares no such resource.
[[noreturn]] void throwAtDeclaration(const GraphDesc& graph, const UnsupportedResourceError& e);

/// Throws `e`, a resource of inputs.graph that the device cannot hold when compiled with
/// `compiled`, named where its size comes from: the scene's environment file for the
/// equirect (as a SceneError), else as throwAtDeclaration() does.
[[noreturn]] void throwCapacityError(const FrameInputs& inputs, const CompileOptions& compiled,
                                     const DeviceCapacityError& e);

/// Renders options.frames frames of `compiled` (compiled from inputs.graph, headless) on
/// `device` with what `inputs` holds (the scene, the environment), options.framesInFlight in
/// flight, and waits for them. Throws what the executor throws.
[[nodiscard]] RenderedFrames renderFrames(Device& device, CompiledGraph compiled, FrameInputs& inputs,
                                          const RenderOptions& options);

/// Compiles and renders a graph file, writing the swapchain target. Returns the command
/// line's exit status (0 ok, 1 user error with a message on stderr). Never throws. Everything
/// it creates (device, renderers) is gone when it returns; only the output file remains.
int renderCommand(const RenderOptions& options);

}  // namespace skygraph::app
