// What `skygraph view` renders and what it may change while it runs: the inputs of `render`
// (graph, scene, environment, features) and the frame renderer built from them. A change
// that needs new inputs (a feature, the environment file, a saved graph or scene file)
// rebuilds them all; one that fails keeps the last good renderer running and its message.
#pragma once

#include "environment_bake.hpp"
#include "file_watcher.hpp"
#include "render.hpp"
#include "sequence_player.hpp"

#include <skygraph/hot_reload.hpp>
#include <skygraph/renderer.hpp>

#include <future>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace skygraph::app {

class LiveGraph {
public:
    /// Loads, compiles (presented, at width x height), bakes and builds what `options`
    /// names on `device`, which must outlive it. `overlay`: the graph's feature `ui`
    /// (the ImGuiPass), unless `options.features` sets it. Throws like renderCommand's steps.
    LiveGraph(Device& device, RenderOptions options, uint32_t width, uint32_t height, bool overlay);
    ~LiveGraph();
    LiveGraph(const LiveGraph&) = delete;
    LiveGraph& operator=(const LiveGraph&) = delete;

    /// Rebuilt renderers start out bound to `swapchain` (borrowed; it must outlive the
    /// renderers), so their first frame builds nothing again.
    void presentTo(Swapchain& swapchain) noexcept { swapchain_ = &swapchain; }

    /// The renderer that presents; replaced by a rebuild, so do not keep the reference
    /// across setFeature, setEnvironmentFile or poll.
    [[nodiscard]] Renderer& renderer() noexcept { return *renderer_; }
    /// renderer().renderFrame(swapchain), with what the graph's UploadPasses copy staged
    /// first (UploadPassPixels).
    PresentStatus renderFrame(Swapchain& swapchain);
    /// The scene the passes get, edited in place by the overlay (call sceneChanged()
    /// after); null when the graph runs without one. Kept across rebuilds.
    [[nodiscard]] Scene* scene() noexcept { return scene_ ? &*scene_ : nullptr; }
    void sceneChanged();

    /// The graph's features with the values the running plan was compiled with.
    [[nodiscard]] std::vector<std::pair<std::string, bool>> features() const;
    /// Whether the running plan has feature `name` on (false when the graph lacks it).
    [[nodiscard]] bool feature(std::string_view name) const;
    /// Rebuilds with `name` forced on or off. False (error() says why) keeps what ran.
    bool setFeature(const std::string& name, bool on);
    /// Another environment: a file, or empty for the procedural sky. A file is decoded on a
    /// thread of its own (resampled to the running equirect's size when it has another, and
    /// baked at its own size by the next rebuild), then re-baked beside the frames
    /// (EnvironmentBaker) and swapped in by later polls, the frames going on with the old
    /// environment meanwhile; a file that cannot be read is reported by error() once its
    /// decoding fails, and the old environment stays. While a load or bake runs, without a
    /// baked environment, or in place of the procedural sky (whose skybox is another pass), it
    /// rebuilds at once. False (error() says why) keeps what ran.
    bool setEnvironmentFile(const std::filesystem::path& file);
    /// Moves the procedural sky's sun (unit `sun`): the skybox shows it at once, and the
    /// lighting is re-baked beside the frames and swapped in by a later poll(); a change while
    /// a bake runs is baked after it (only the latest). False when the scene's environment is
    /// not the procedural sky.
    bool setSunDirection(const Vec3& sun);
    /// Plays the scene's environment sequence: at `seconds` by the caller's clock (playback
    /// begins at the first call, and again from the first frame after a rebuild), once no
    /// bake runs, starts baking the newest decoded frame whose time has come
    /// (SequencePlayer), the frames holding the last one meanwhile. Call after poll(), which
    /// swaps a bake in. Where the graph's skybox fades (graphs/raster.json's
    /// environment_sequence), the sky fades from the previous frame's cube to the new one over
    /// one frame of the sequence (SkyFade); the lighting changes at the swap. Another
    /// environment file stops playback. Nothing happens without a sequence.
    void playSequence(double seconds);
    /// What playback has done; null without a sequence playing.
    [[nodiscard]] const SequencePlayer* sequence() const noexcept { return player_.get(); }
    /// Whether a re-bake (a file being decoded for one included) is not swapped in yet.
    [[nodiscard]] bool rebaking() const noexcept { return (baker_ && baker_->pending()) || load_.has_value(); }
    /// Swaps in a finished re-bake; rebuilds after the graph or scene file was saved, reloads
    /// shaders after a shader edit, and rebuilds, baking the environment again, after an edit
    /// to a shader the environment's bake was built from. A save whose rebuild failed is
    /// rebuilt again at the next save or shader edit, so that fixing a shader brings in the
    /// graph saved with it. True when something was reloaded (or failed: see error()).
    bool poll();

    /// Screenshots go through the plan: beginScreenshot() recompiles with the presented
    /// image read back after each frame (CompileOptions::readbacks); after one frame has
    /// been presented, finishScreenshot() writes it as a PNG (the overlay included) and
    /// compiles the plan back. False (error() says why) when either step failed.
    bool beginScreenshot();
    bool finishScreenshot(const std::filesystem::path& png);
    /// The plan's presented image, or empty.
    [[nodiscard]] std::string presentedResource() const;

    /// When the last rebuild after a saved file was installed, and the save it followed
    /// (the file's modification time), for the latency from saving to the frame on screen.
    struct Reload {
        std::filesystem::file_time_type saved{};    // the file's modification time
        std::filesystem::file_time_type noticed{};  // when poll() saw it
        std::filesystem::file_time_type rebuilt{};  // when the new renderer was installed
        bool pending = false;  // no frame of the new plan presented yet
    };
    [[nodiscard]] Reload& lastReload() noexcept { return lastReload_; }

    /// The messages of the last failed change or reload of the inputs, and of the shaders;
    /// each clears once its kind succeeds. Empty when all is well.
    [[nodiscard]] std::string error() const;
    /// Whether the graph declares feature `name`.
    [[nodiscard]] bool declares(std::string_view name) const;
    /// True once after a saved scene file replaced the scene (its camera included).
    [[nodiscard]] bool sceneReplaced() noexcept;
    /// How many rebuilds and reloads succeeded.
    [[nodiscard]] uint32_t reloads() const noexcept { return reloads_; }

private:
    struct Built;
    /// With ShaderSources::Cached (and a renderer running) the new renderer builds from the
    /// shader sources the running one was built from, and the environment's bake from the
    /// running bake's (`bakeShaders`): a shader broken on disk fails only the rebuilds that
    /// read it again, after a saved file or an edit to that bake's shaders.
    [[nodiscard]] std::unique_ptr<Built> build(const RenderOptions& options, Renderer::ShaderSources shaders,
                                               Renderer::ShaderSources bakeShaders) const;
    bool rebuild(RenderOptions options, Renderer::ShaderSources shaders, Renderer::ShaderSources bakeShaders);
    /// rebuild() with the frame's and the bake's shaders from the same sources.
    bool rebuild(RenderOptions options, Renderer::ShaderSources shaders) {
        return rebuild(std::move(options), shaders, shaders);
    }
    /// rebuild() after the graph or scene file was saved; a failure keeps the saves pending.
    void rebuildAfterSave(bool graphSaved, bool sceneSaved, std::filesystem::file_time_type saved,
                          bool reportLatency);
    /// setEnvironmentFile's re-bake beside the frames: starts decoding `file`; false when it
    /// needs a rebuild.
    bool rebakeInPlace(const std::filesystem::path& file, RenderOptions next);
    /// Once the file is decoded: starts its bake, or reports why it could not be read.
    void finishEnvironmentLoad();
    /// Whether a re-bake beside the frames is possible now (an environment is baked, the frame
    /// graph has an equirect, no bake is pending).
    [[nodiscard]] bool canRebake() const;
    /// Starts re-baking `pixels` (named `what` in the log), resampled to the running
    /// equirect's size when they differ; false when the baker cannot start one now.
    bool rebake(HdrImage pixels, const std::string& what);
    /// The baker, made on first use for an equirect of `width` x `height`.
    EnvironmentBaker& baker(uint32_t width, uint32_t height);
    /// Playback that a rebuild goes on with: the sequence and where it stood.
    struct Playback {
        EnvironmentSequence sequence;
        SequencePosition position;
        std::optional<double> origin;
    };
    /// A player for the running scene's sequence, if it has one of several frames; it goes on
    /// from `from` when that is the same sequence and the build baked the frame on screen.
    void startSequence(const std::optional<Playback>& from = std::nullopt);
    /// Ends playback, the sky left on the cube swapped in last (no fade half way).
    void stopSequence();
    /// Drops the player and the state of its bakes and fades.
    void forgetPlayback();
    void startPendingSunBake();
    void swapRebake();

    Device& device_;
    Swapchain* swapchain_ = nullptr;
    RenderOptions options_;
    uint32_t width_, height_;
    bool overlay_;
    std::optional<Scene> scene_;
    /// Re-bakes of the running environment graph; made at the first, dropped by a rebuild.
    /// Declared before built_: the frames that sample its products go first.
    std::unique_ptr<EnvironmentBaker> baker_;
    std::optional<HdrImage> rebakeEquirect_;  ///< The pixels being re-baked, for the frame's own equirect.
    /// An environment file decoded, resampled and staged on a thread of its own.
    struct LoadedEnvironment {
        std::shared_ptr<StagingBuffer> staged;
        std::optional<HdrImage> pixels;  ///< kept only when the frame samples the equirect itself
    };
    struct EnvironmentLoad {
        std::filesystem::path file;
        RenderOptions next;  ///< what runs once it is baked
        std::future<LoadedEnvironment> result;
    };
    std::optional<EnvironmentLoad> load_;
    /// The last load's staging buffer, reused by the next load once no bake holds it (freeing
    /// host-visible memory where a bake lets go of it would cost the frame's thread).
    std::shared_ptr<StagingBuffer> loadStaging_;
    std::optional<Vec3> pendingSun_;           ///< A sun direction not baked yet.
    std::unique_ptr<SequencePlayer> player_;
    bool sequenceBaking_ = false;  ///< The pending re-bake is a sequence frame.
    /// The environment cube the frames sample: what a sequence's sky fades from at a swap.
    SharedImage environmentShown_;
    std::optional<double> playbackOrigin_;  ///< The clock at the player's first playSequence().
    bool fadeStarting_ = false;         ///< A swap began a fade; playSequence() notes when.
    std::optional<double> fadeStart_;  ///< Playback seconds at which the running fade began.
    std::unique_ptr<Built> built_;
    Renderer* renderer_ = nullptr;
    std::optional<FileWatcher> graphWatcher_, sceneWatcher_;
    /// The environment graph's file (graphs/ibl.json beside the graph), watched from the start
    /// when there is a graph file, so that one saved there later is built too.
    std::filesystem::path environmentGraphFile_;
    std::optional<FileWatcher> environmentGraphWatcher_;
    std::unique_ptr<HotReloader> shaderWatcher_;
    std::string error_, shaderError_;
    std::string bakeShaderError_;  // an edited shader of the environment's bake did not build
    /// A rebuild brought a bake back from the sources of one that was not running: the next
    /// poll checks them against the files, as after an edit.
    bool checkBakeShaders_ = false;
    bool sceneReplaced_ = false;
    bool graphSavePending_ = false, sceneSavePending_ = false;  // saved, but its build failed
    uint32_t reloads_ = 0;
    Reload lastReload_;
};

}  // namespace skygraph::app
