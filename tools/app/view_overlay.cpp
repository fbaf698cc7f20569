// The debug overlay: Dear ImGui widgets, built each frame from the live.
#include "view_overlay.hpp"

#include <skygraph/plan.hpp>
#include <skygraph/scene.hpp>

#include <glm/glm.hpp>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

namespace skygraph::app {
namespace {

constexpr const char* kTonemappers[] = {"ACES (Narkowicz)", "ACES (Hill)", "Khronos PBR Neutral", "passthrough"};
constexpr const char* kDebugViews[] = {"none", "normal", "metallic", "roughness", "ambient occlusion"};

size_t barrierCount(const Plan& plan) {
    size_t n = plan.finalBarriers().size() + plan.inPassBarriers().size();
    for (const PlannedPass& p : plan.passes()) n += p.barriers.size();
    return n;
}

/// A combo over `names`, editing an enum stored as its index.
template <typename Enum, size_t N>
bool enumCombo(const char* label, Enum& value, const char* const (&names)[N]) {
    int index = static_cast<int>(value);
    if (!ImGui::Combo(label, &index, names, int(N))) return false;
    value = static_cast<Enum>(index);
    return true;
}

}  // namespace

ViewOverlay::ViewOverlay(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // the same layout every run (tests click on it)
    ImGui::StyleColorsDark();
    io.Fonts->Build();  // ImGui::NewFrame wants the atlas; the ImGuiPass uploads it
    ImGui_ImplGlfw_InitForVulkan(window, true);
}

ViewOverlay::~ViewOverlay() {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool ViewOverlay::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }

void ViewOverlay::frame(LiveGraph& live, double frameMs) {
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(260, 0), ImVec2(420, 10000));
    ImGui::Begin("skygraph", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove);
    ImGui::TextUnformatted(live.renderer().graph().name.c_str());
    if (const std::string error = live.error(); !error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::PushTextWrapPos(400);
        ImGui::TextUnformatted(error.c_str());
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    }
    features(live);
    sceneControls(live);
    statistics(live, frameMs);
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    const std::string rect = std::to_string(int(pos.x)) + "," + std::to_string(int(pos.y)) + " " +
                             std::to_string(int(size.x)) + "x" + std::to_string(int(size.y));
    if (rect != window_) {
        window_ = rect;
        spdlog::info("overlay: window at {}", rect);
    }
    ImGui::End();
    ImGui::Render();
}

void ViewOverlay::features(LiveGraph& live) {
    if (!ImGui::CollapsingHeader("Features", ImGuiTreeNodeFlags_DefaultOpen)) return;
    std::optional<std::pair<std::string, bool>> changed;
    std::string layout;
    for (auto [name, on] : live.features()) {
        if (ImGui::Checkbox(name.c_str(), &on)) changed.emplace(name, on);
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        // The checkbox square is at the item's left; tests click its centre.
        const float side = hi.y - lo.y;
        layout += " " + name + "=" + std::to_string(int(lo.x + side / 2)) + "," + std::to_string(int(lo.y + side / 2));
    }
    if (layout != laidOut_) {
        laidOut_ = layout;
        spdlog::info("overlay: feature checkboxes at{}", layout);
    }
    if (changed) live.setFeature(changed->first, changed->second);
}

void ViewOverlay::sceneControls(LiveGraph& live) {
    Scene* scene = live.scene();
    if (!scene || !ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) return;
    bool edited = false;
    float ev = float(scene->exposureEv);
    if (ImGui::SliderFloat("exposure (EV)", &ev, -10.0f, 10.0f, "%.2f")) {
        scene->exposureEv = ev;
        edited = true;
    }
    edited |= enumCombo("tonemapping", scene->tonemapper, kTonemappers);
    edited |= enumCombo("debug view", scene->debugView, kDebugViews);
    if (scene->environment) {
        float rotation = float(scene->environment->rotationDeg);
        if (ImGui::SliderFloat("sky rotation", &rotation, -180.0f, 180.0f, "%.1f deg")) {
            scene->environment->rotationDeg = rotation;
            edited = true;
        }
        if (scene->environment->procedural) sunControls(live, scene->environment->sunDirection);
    }
    if (edited) live.sceneChanged();
    if (const SequencePlayer* player = live.sequence()) {
        const SequenceStats& s = player->stats();
        ImGui::Text("sequence: frame %u of %u at %.3g fps; %u shown, %u late, %u dropped", s.current.value_or(0) + 1,
                    player->stream().sequence().count, player->fps(), s.shown, s.late, s.dropped);
    }
    ImGui::InputText("environment", environmentFile_.data(), environmentFile_.size());
    if (ImGui::Button("load file")) live.setEnvironmentFile(environmentFile_.data());
    ImGui::SameLine();
    if (ImGui::Button("procedural sky")) live.setEnvironmentFile({});
}

void ViewOverlay::sunControls(LiveGraph& live, const Vec3& sun) {
    // Azimuth as the camera's yaw (0 looks down -Z, positive turns left), elevation above the
    // horizon: the direction is (-sin az cos el, sin el, -cos az cos el).
    float elevation = float(glm::degrees(std::asin(std::clamp(sun[1], -1.0, 1.0))));
    float azimuth = float(glm::degrees(std::atan2(-sun[0], -sun[2])));
    bool moved = ImGui::SliderFloat("sun azimuth", &azimuth, -180.0f, 180.0f, "%.1f deg");
    moved |= ImGui::SliderFloat("sun elevation", &elevation, -10.0f, 90.0f, "%.1f deg");
    if (!moved) return;
    const double az = glm::radians(double(azimuth)), el = glm::radians(double(elevation));
    live.setSunDirection({-std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el)});
}

void ViewOverlay::statistics(LiveGraph& live, double frameMs) {
    if (!ImGui::CollapsingHeader("Plan", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const Plan& plan = live.renderer().plan();
    ImGui::Text("%zu passes, %zu culled, %zu barriers; CPU %.2f ms/frame", plan.passes().size(),
                plan.culled().size(), barrierCount(plan), frameMs);
    if (ImGui::BeginTable("timings", 2, ImGuiTableFlags_SizingFixedFit)) {
        for (const auto& t : live.renderer().completedTimings()) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(t.pass.c_str());
            ImGui::TableNextColumn();
            ImGui::Text("%7.3f ms GPU", t.milliseconds);
        }
        ImGui::EndTable();
    }
    for (const CulledPass& c : plan.culled()) ImGui::TextDisabled("culled %s: %s", c.name.c_str(), c.reason.c_str());
}

}  // namespace skygraph::app
