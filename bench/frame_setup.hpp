// What present_bench and imgui_bench share: graphs/raster.json with scenes/default.json,
// loaded, baked and attached the way `skygraph render` and `skygraph view` do it
// (tools/app/render.hpp), and the benchmarks' own command-line flags.
#pragma once

#include "app/render.hpp"

#include <skygraph/compiled_graph.hpp>
#include <skygraph/device.hpp>
#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <exception>
#include <map>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace skygraph::bench {

struct Size {
    uint32_t width = 0;
    uint32_t height = 0;
    [[nodiscard]] std::string name() const { return std::to_string(width) + "x" + std::to_string(height); }
};

/// Removes the benchmark's own `--size=WxH` flags (repeatable) from argv before Google
/// Benchmark parses the rest; `defaults` when none is given. Exits on a malformed one.
inline std::vector<Size> takeSizes(int& argc, char** argv, std::vector<Size> defaults) {
    std::vector<Size> sizes;
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg.starts_with("--size=")) {
            Size s;
            if (std::sscanf(argv[i] + 7, "%ux%u", &s.width, &s.height) != 2 || s.width == 0 || s.height == 0) {
                std::fprintf(stderr, "%s: --size wants WxH, e.g. --size=1280x720\n", argv[0]);
                std::exit(2);
            }
            sizes.push_back(s);
        } else {
            argv[kept++] = argv[i];
        }
    }
    argc = kept;
    argv[argc] = nullptr;
    return sizes.empty() ? defaults : sizes;
}

/// graphs/raster.json and scenes/default.json of this source tree.
inline app::RenderOptions rasterOptions(Size size, bool ui, const PassLibrary& passes) {
    const std::filesystem::path root = SKYGRAPH_SOURCE_DIR;
    app::RenderOptions o;
    o.graph = root / "graphs/raster.json";
    o.scene = root / "scenes/default.json";
    o.features["ui"] = ui;
    o.width = size.width;
    o.height = size.height;
    o.framesInFlight = 2;
    o.passes = &passes;
    return o;
}

/// One renderer of raster.json and the environment it samples (baked once, as `render` does,
/// the default scene's procedural sky included). Headless: the swapchain target is an image
/// of the renderer's own (CompileOptions::presentReplacement), as in `skygraph render` without
/// a read-back; presented: the Present resource stays Present, as in `skygraph view`.
struct FrameRenderer {
    app::FrameEnvironment environment;
    std::unique_ptr<Renderer> renderer;

    FrameRenderer(Device& device, const app::RenderOptions& options, bool headless) {
        app::FrameInputs inputs = app::loadFrameInputs(options);
        CompileOptions co = inputs.compile;
        if (headless) co.presentReplacement = ExternalState::TransferSrc;
        CompiledGraph compiled(inputs.graph, co);
        environment = app::bakeFrameEnvironment(device, compiled.plan(), inputs, options);
        RendererOptions ro;
        ro.framesInFlight = options.framesInFlight;
        ro.passes = inputs.passes;
        renderer = std::make_unique<Renderer>(device, std::move(compiled), ro);
        app::attachFrameInputs(*renderer, inputs, environment);
    }
};

/// The device the benchmarks run on: SKYGRAPH_BENCH_DEVICE (an index or a name substring),
/// else the default choice; validation when SKYGRAPH_VALIDATION=1 (Device reads it).
inline std::string benchDeviceName() {
    const char* name = std::getenv("SKYGRAPH_BENCH_DEVICE");
    return name ? name : "";
}

/// The benchmarks' fixtures, one per size, made on first use and kept for the run (the
/// device, the window and the pipelines are not what is measured). A fixture that cannot be
/// made skips the benchmark with its error and sets `failed` (the exit status is 1 then).
template <typename Fixture>
class Fixtures {
public:
    Fixture* get(benchmark::State& state, Size size) {
        auto& f = made_[size.name()];
        try {
            if (!f) f = std::make_unique<Fixture>(size);
        } catch (const std::exception& e) {
            made_.erase(size.name());
            failed = true;
            state.SkipWithError(e.what());
            return nullptr;
        }
        return f.get();
    }
    std::map<std::string, std::unique_ptr<Fixture>>& all() noexcept { return made_; }
    bool failed = false;

private:
    std::map<std::string, std::unique_ptr<Fixture>> made_;
};

}  // namespace skygraph::bench
