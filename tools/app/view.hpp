// `skygraph view` as one call: the graph and scene of `render`, presented in a GLFW window
// through the executor's Swapchain until the window closes (or for a number of frames).
// Application code: GLFW lives here and in tests, never in the libraries.
#pragma once

#include "render.hpp"

#include <skygraph/swapchain.hpp>

#include <cstdint>

namespace skygraph::app {

/// `skygraph view`: options as parsed by the command line. A plain value; it borrows only
/// `frame.passes`.
struct ViewOptions {
    /// Graph, scene, features, window size (width, height), validation, device, frames in
    /// flight and the environment, as `render` takes them; `frame.frames` and the output
    /// options are not used.
    RenderOptions frame;
    /// Frames to present before quitting; 0: until the window is closed.
    uint32_t frames = 0;
    PresentMode presentMode = PresentMode::Fifo;
    /// Left-drag orbits the camera about the point it looks at, the wheel moves it closer.
    bool orbit = true;
    /// The debug overlay (Dear ImGui, drawn by the graph's ImGuiPass): the graph's feature
    /// `ui` is turned on unless `frame.features` sets it.
    bool overlay = true;
};

/// Opens the window, renders into it and returns the command line's exit status: 0 when
/// closed (or after `frames` frames) with no validation message under `frame.validate`, 1
/// otherwise, or when there is no display (one line on stderr suggesting `skygraph render`).
/// Never throws. Escape, SIGINT and SIGTERM close the window like its close button.
int viewCommand(const ViewOptions& options);

}  // namespace skygraph::app
