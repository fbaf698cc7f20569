// `skygraph view`'s debug overlay: Dear ImGui controls over the frame, drawn by the graph's
// ImGuiPass. It edits the running graph (features, scene settings, the environment file) and
// shows what runs (per-pass GPU times, culled passes and why, barrier count, errors).
#pragma once

#include "live_graph.hpp"

#include <array>
#include <string>

struct GLFWwindow;

namespace skygraph::app {

class ViewOverlay {
public:
    /// Makes the ImGui context (current from here on) and its GLFW backend on `window`, which
    /// must outlive the overlay. The backend chains the window's callbacks, so set those first.
    /// Make the overlay before the renderers: their ImGuiPass takes the current context.
    explicit ViewOverlay(GLFWwindow* window);
    /// Destroy after every renderer that draws the context.
    ~ViewOverlay();
    ViewOverlay(const ViewOverlay&) = delete;
    ViewOverlay& operator=(const ViewOverlay&) = delete;

    /// Builds this frame's controls and applies what the user changed to `live`. Call once
    /// per frame before rendering it; `frameMs` is the CPU time of the last frame.
    void frame(LiveGraph& live, double frameMs);
    /// Whether the pointer is over the overlay (the camera then ignores it).
    [[nodiscard]] bool wantsMouse() const;

private:
    void features(LiveGraph& live);
    void sceneControls(LiveGraph& live);
    void sunControls(LiveGraph& live, const Vec3& sun);
    void statistics(LiveGraph& live, double frameMs);

    std::array<char, 1024> environmentFile_{};
    std::string laidOut_;  // the controls' positions, logged once per layout
    std::string window_;   // the overlay's rectangle, likewise
};

}  // namespace skygraph::app
