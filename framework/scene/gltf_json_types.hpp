// The JSON types the glTF 2.0 schema gives the properties skygraph reads. tinygltf skips a
// property of the wrong type (a string where an index belongs, an object where an array
// belongs) as if it were absent; this check turns each into an error with its JSON path. It
// reads the JSON first, with the checks tinygltf lacks (depth, repeated keys).
#pragma once

#include <skygraph/diagnostics.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace skygraph {

/// What is wrong with a .glb's header, JSON chunk and BIN chunk as containers (size, version,
/// lengths, chunk type), in words; empty when nothing is. tinygltf says only "Invalid glTF
/// binary", and reads a BIN chunk up to its header's 8 bytes past the end.
[[nodiscard]] std::string glbProblem(std::string_view bytes);

/// The JSON chunk of a .glb file's bytes, which glbProblem() found nothing wrong with; a view
/// into `bytes`.
[[nodiscard]] std::string_view glbJsonChunk(std::string_view bytes);

/// Adds an error to `diagnostics` (file `file`; `binary`: the text is a .glb's JSON chunk) for
/// malformed JSON (with its line and column in a .gltf), nesting deeper than the JSON readers
/// allow, repeated keys, and every property whose JSON type the glTF schema forbids: indices
/// that are not non-negative integers, objects or arrays of the wrong kind, numbers that are
/// strings, names that are not strings, extensions that are not objects. True when nothing
/// was wrong.
bool checkGltfJsonTypes(const std::string& jsonText, const std::string& file, bool binary, Diagnostics& diagnostics);

/// A uri percent-decoded as tinygltf 2.7 does it (its urldecode), or, with `plusIsSpace` off,
/// as RFC 3986 (which glTF follows) does: a '+' in a path is a '+', not the space of an HTML
/// form.
[[nodiscard]] std::string decodeUri(const std::string& uri, bool plusIsSpace);

/// The file that a buffer's or an image's `uri` (not a data URI) names, as the loader reads it:
/// percent-decoded as RFC 3986 does (a '+' stays one) and joined to `baseDir`, the glTF
/// file's folder.
[[nodiscard]] std::filesystem::path uriFile(const std::filesystem::path& baseDir, const std::string& uri);

/// Why `path`, a file a glTF names, cannot be read as one: "does not exist", "is a directory",
/// "is not a regular file", "cannot be read (REASON)"; empty for a regular file.
[[nodiscard]] std::string notARegularFile(const std::filesystem::path& path);

/// Why `uri` (not a data URI) names no file skygraph reads, in words, or empty: glTF uris are
/// relative to the glTF file's folder, and an absolute path or a file: URI is refused.
[[nodiscard]] std::string absoluteUriProblem(const std::string& uri);

}  // namespace skygraph
