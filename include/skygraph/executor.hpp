// The executor: runs compiled plans on a Vulkan 1.3 device. It records exactly the plan's
// barriers and derives no synchronization of its own. This header includes the executor's
// whole API; each part has its own header:
//   device.hpp        Device, DeviceOptions, PresentationOptions, ValidationMessage, ExecutorError
//   renderer.hpp      Renderer, RendererOptions, PresentStatus, PassTiming
//   swapchain.hpp     Swapchain, PresentMode, PresentRequirements, PresentImages, PresentTarget
//   shared_image.hpp  SharedImage: an image one renderer writes and another reads
//   hot_reload.hpp    HotReloader
//   image_data.hpp    ImageData, writePng, writeHdr
//   staging_buffer.hpp StagingBuffer: pixels Renderer::stageUpload hands to an UploadPass
// Recording code for pass types is pass.hpp.
#pragma once

#include <skygraph/device.hpp>
#include <skygraph/hot_reload.hpp>
#include <skygraph/image_data.hpp>
#include <skygraph/renderer.hpp>
#include <skygraph/shared_image.hpp>
#include <skygraph/staging_buffer.hpp>
#include <skygraph/swapchain.hpp>
