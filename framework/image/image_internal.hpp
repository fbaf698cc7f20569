// Helpers shared by the .hdr and .exr halves of skygraph_image. Not installed.
#pragma once

#include <skygraph/hdr_image.hpp>

#include <functional>
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

/// files::replaceFile(path, write), with every failure an ImageError naming `path`.
/// Writers that cannot report a failed write themselves (stb's) encode to memory and write
/// the bytes with writeBytes().
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::string& tempPath)>& write);

/// files::replaceFileContents(path, bytes): a file that cannot be written whole (a full disk,
/// a file size limit) throws ImageError naming `path` and the reason.
void writeBytes(const std::filesystem::path& path, std::string_view bytes);

/// An stb_image_write callback that appends to the std::string its context points at.
void appendToString(void* context, void* data, int size);

}  // namespace skygraph::image_detail
