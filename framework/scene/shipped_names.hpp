// Names in the shipped graphs (graphs/raster.json, graphs/ibl.json, graphs/pathtrace.json)
// and built-in data that product code relies on: the features a scene decides (this library's
// sceneFeatures()), the resources and pass types the command line edits and connects, and the
// names it gives built-in text in messages. Renaming one in a graph file means renaming it
// here. Private to the build tree: the scene library and the application (tools/app) include
// it; the pass types' own names are declared with them in passes/.
#pragma once

#include <string_view>

namespace skygraph::shipped {

// Features of graphs/raster.json that a scene decides (sceneFeatures()).
inline constexpr std::string_view kGeometryFeature = "geometry";
inline constexpr std::string_view kSkyboxFeature = "skybox";
inline constexpr std::string_view kEnvironmentFileFeature = "environment_file";
inline constexpr std::string_view kSampleCubemapFeature = "sample_cubemap";
inline constexpr std::string_view kEnvironmentSequenceFeature = "environment_sequence";
/// The debug overlay (ImGuiPass), which `skygraph view` turns on.
inline constexpr std::string_view kOverlayFeature = "ui";

// The feature of graphs/ibl.json under which its own UploadPass, on the transfer queue,
// copies the equirect in at every bake (EnvironmentBaker) rather than a setup before the
// first (a file's one bake).
inline constexpr std::string_view kStreamedEquirectFeature = "streamed_equirect";

// Resources of graphs/ibl.json and of the frame graphs that import its products.
/// The equirect image a scene's environment file is loaded into.
inline constexpr std::string_view kEquirect = "equirect";
/// The environment cube with its mip chain.
inline constexpr std::string_view kEnvironment = "environment";
inline constexpr std::string_view kEnvironmentPrevious = "environment_previous";
inline constexpr std::string_view kIrradiance = "irradiance";
/// GGX-prefiltered specular, one roughness per mip.
inline constexpr std::string_view kPrefiltered = "prefiltered";
inline constexpr std::string_view kBrdfLut = "brdf_lut";

// Pass types of graphs/ibl.json whose passes and params the application edits.
inline constexpr std::string_view kEquirectToCubemapPass = "EquirectToCubemapPass";
inline constexpr std::string_view kCubemapMipPass = "CubemapMipPass";
inline constexpr std::string_view kIrradiancePass = "IrradiancePass";
inline constexpr std::string_view kPrefilterPass = "PrefilterPass";
/// The pass type whose staged pixels `render`, `check` and `view` provide (UploadPassPixels).
inline constexpr std::string_view kUploadPass = "UploadPass";
/// CubemapMipPass's slot of the level it reads.
inline constexpr std::string_view kCubemapMipSourceSlot = "source";
/// IrradiancePass's and PrefilterPass's samples per texel.
inline constexpr std::string_view kSamplesParam = "samples";
/// EquirectToCubemapPass's taps per cube texel (N x N).
inline constexpr std::string_view kSupersampleParam = "supersample";

// Graph files, and the names built-in text carries in messages.
/// The environment graph's file name, looked for beside a frame graph file.
inline constexpr std::string_view kEnvironmentGraphFile = "ibl.json";
inline constexpr std::string_view kBuiltinEnvironmentGraphName = "<built-in ibl.json>";
inline constexpr std::string_view kBuiltinFrameGraphName = "<built-in raster.json>";
inline constexpr std::string_view kBuiltinSceneName = "<built-in default scene>";
/// What `skygraph cubemap` calls the environment graph it runs in messages.
inline constexpr std::string_view kCubemapGraphName = "graphs/ibl.json";

}  // namespace skygraph::shipped
