// UploadPass's declaration: one slot, written by a copy (recording code: upload_pass.cpp).
#include "builtin_pass_types.hpp"
#include "param_rules.hpp"

namespace skygraph::passes {

PassTypeInfo uploadPassType() {
    return {"UploadPass",
            {slot("target", Stage::Transfer, {Access::Write}, BindAs::Default,
                  "mip 0 of every layer of an image, or a whole buffer")},
            false, rules({}),
            "Copies the pixels the application staged for this frame (Renderer::stageUpload) into `target`. "
            "A copy runs on any queue: on the transfer queue it overlaps the other queues' work."};
}

}  // namespace skygraph::passes
