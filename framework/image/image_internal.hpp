// Helpers shared by the .hdr and .exr halves of skygraph_image. Not installed.
#pragma once

#include <skygraph/hdr_image.hpp>

#include <string>
#include <string_view>

namespace skygraph::image_detail {

/// Throws ImageError unless `path` names an existing regular file.
void requireReadableFile(const std::filesystem::path& path);

/// Throws ImageError for a zero or negative size, or one over kMaxHdrImageWidth/Height; called
/// with the size from the header, before anything is allocated for the pixels.
void requireLoadableSize(const std::filesystem::path& path, int64_t width, int64_t height);

/// What the first bytes of a file look like ("a PNG image", ...), for "not an X file" messages;
/// empty when unrecognised.
[[nodiscard]] std::string sniffFormat(std::string_view firstBytes);

/// Throws ImageError for an empty image, a pixel vector of the wrong size, or one over the limits.
void requireWritable(const std::filesystem::path& path, const HdrImage& image);

/// files::replaceFileContents(path, bytes): a file that cannot be written whole (a full disk,
/// a file size limit) throws ImageError naming `path` and the reason. Every writer encodes to
/// memory and writes through here, so that a write is checked whole in one place (stb's file
/// writers report a full disk as success).
void writeBytes(const std::filesystem::path& path, std::string_view bytes);

/// The bytes saveRadianceHdr() and saveExr() write to `path` (named in errors only).
[[nodiscard]] std::string encodeRadianceHdr(const std::filesystem::path& path, const HdrImage& image);
[[nodiscard]] std::string encodeExr(const std::filesystem::path& path, const HdrImage& image);

/// An stb_image_write callback that appends to the std::string its context points at.
void appendToString(void* context, void* data, int size);

}  // namespace skygraph::image_detail
