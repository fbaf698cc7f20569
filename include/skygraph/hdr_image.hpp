// High-dynamic-range images on the CPU: Radiance .hdr (stb_image) and OpenEXR .exr.
// Used for environment maps and for writing HDR captures. No Vulkan here.
//
// Every function reports failure by throwing ImageError, whose message names the file; none
// crashes on bad input, and a save never leaves half a file under the final name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace skygraph {

/// Largest image accepted by the loaders, checked from the header before any pixel memory is
/// allocated: the largest extent a graph's image takes, 16384 x 16384 (a 4 GiB RGBA float image).
inline constexpr uint32_t kMaxHdrImageWidth = 16384;
inline constexpr uint32_t kMaxHdrImageHeight = 16384;

/// A linear-light image, 4 floats per pixel (R, G, B, A), rows top to bottom.
/// Owns its pixels; a plain value type.
struct HdrImage {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> rgba;  ///< width * height * 4 floats

    /// The pixel at (x, y); no bounds check. Points into `rgba`: valid until it is resized or
    /// destroyed.
    [[nodiscard]] const float* pixel(uint32_t x, uint32_t y) const noexcept {
        return rgba.data() + (size_t(y) * width + x) * 4;
    }
};

/// Any failure to read or write an image. what() names the file and the reason on one line,
/// with control characters shown escaped as JSON writes them ("\u000a"); file() is the path as
/// given.
class ImageError : public std::runtime_error {
public:
    ImageError(const std::filesystem::path& file, const std::string& reason);
    /// The file the error is about; valid while this exception object lives.
    [[nodiscard]] const std::filesystem::path& file() const noexcept { return file_; }

private:
    std::filesystem::path file_;
};

/// Loads `path` by its extension (.hdr or .exr, any case) and returns an image the caller owns.
/// Radiance files have alpha 1; EXR alpha comes from the A channel or is 1.
/// Non-finite pixel values are kept as they are (see countNonFinite()).
/// Throws ImageError: missing file, unknown extension, truncated or corrupt data, a file whose
/// contents are not of the format its extension names, a zero size, or a size over the limits.
[[nodiscard]] HdrImage loadHdrImage(const std::filesystem::path& path);

/// Loads a Radiance RGBE file through stb_image, whatever its extension: in any of the format's
/// eight scanline orders, top row first, and with its EXPOSURE= and COLORCORR= multipliers
/// divided out, so that the values are radiance. Throws ImageError.
[[nodiscard]] HdrImage loadRadianceHdr(const std::filesystem::path& path);

/// Loads the first part of an OpenEXR file (any compression, scanline or tiled, float, half or
/// uint channels) at full float precision, whatever its extension. A luminance-only file (Y)
/// becomes grey. The image is the file's display window: where the data window leaves part of
/// it, that part is transparent black, and data outside it is left out. Throws ImageError.
[[nodiscard]] HdrImage loadExr(const std::filesystem::path& path);

/// Saves by extension (.hdr or .exr). Reads `image` only; writes a temporary file next to
/// `path` and renames it over `path` only once it is complete. Throws ImageError.
void saveHdrImage(const std::filesystem::path& path, const HdrImage& image);

/// The bytes saveHdrImage() writes to `path` (by its extension), in memory, for a caller that
/// writes the file itself (several files replaced together, say). `path` names the file in
/// errors and chooses the format. Throws ImageError for what saveHdrImage() cannot write (an
/// empty image, one over the limits, another extension).
[[nodiscard]] std::string encodeHdrImage(const std::filesystem::path& path, const HdrImage& image);

/// Saves RGB as Radiance RGBE through stb_image_write (alpha is dropped; RGBE has ~1% precision
/// and cannot store negative or non-finite values). Atomic as saveHdrImage(). Throws ImageError.
void saveRadianceHdr(const std::filesystem::path& path, const HdrImage& image);

/// Saves RGBA as half-float OpenEXR with ZIP compression (finite values beyond +-65504 are
/// clamped to it rather than become infinite; infinities and NaNs are kept). Atomic as
/// saveHdrImage(). Throws ImageError.
void saveExr(const std::filesystem::path& path, const HdrImage& image);

/// How many floats of `image.rgba` are NaN or infinite. Loaders keep such values (they are
/// legitimate test inputs); callers that need finite data check with this.
[[nodiscard]] size_t countNonFinite(const HdrImage& image) noexcept;

}  // namespace skygraph
