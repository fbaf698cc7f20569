// Images that one renderer writes and another renderer on the same Device reads.
#pragma once

#include <memory>
#include <string>

namespace skygraph {

/// An image that one renderer wrote and another renderer on the same Device reads, e.g. the
/// environment cube and IBL products that graphs/ibl.json builds when the environment changes
/// and graphs/raster.json samples every frame. A handle: copies share ownership of the Vulkan
/// image, which lives while any SharedImage or renderer holds it (so it may outlive the
/// renderer that made it, but not the Device). Get one from Renderer::shareImage(), hand it to
/// Renderer::importImage(). A default-constructed SharedImage is empty.
class SharedImage {
public:
    SharedImage();
    ~SharedImage();
    SharedImage(const SharedImage&);
    SharedImage& operator=(const SharedImage&);

    /// "graph 'ibl', resource 'environment'": where it came from, for messages ("nothing" when
    /// empty). The reference is valid while this SharedImage is neither destroyed nor assigned.
    [[nodiscard]] const std::string& origin() const noexcept;
    /// True for a default-constructed SharedImage, which holds no image.
    [[nodiscard]] bool empty() const noexcept { return !impl_; }

private:
    struct Impl;
    friend class Renderer;
    std::shared_ptr<const Impl> impl_;
};

}  // namespace skygraph
