// ImGuiPass's declaration: its one slot (recording code: imgui_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo imguiPassType() {
    return {"ImGuiPass",
            {slot("target", Stage::ColorAttachment, {Access::ReadWrite}, BindAs::Default,
                  "the image the overlay is drawn over, e.g. the swapchain after tonemapping")},
            false,
            rules({}),
            "The application's Dear ImGui draw data (its current context's last ImGui::Render()), "
            "drawn over the target; nothing without a context."};
}

}  // namespace skygraph::passes
