// Writing a whole file so that whoever reads it sees the old contents or the new, never part:
// every file the libraries and the tool write for a user is written through here.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace skygraph::files {

/// Where a write meant for `path` lands. A symbolic link is followed to the file at the end of
/// its chain, so the link stays a link and its target gets the contents. A FIFO, terminal or
/// other device there is written in place (`inPlace`): its reader takes the bytes as they come
/// and there is no file to replace. So is a descriptor's link in /proc (/dev/stdout,
/// /dev/fd/N, /proc/self/fd/N): the stream a shell's redirection set up is written, not the
/// file it may lead to; one of this process's descriptors that is closed or only read from
/// takes nothing (EBADF). Anything else, a regular file or nothing yet, is replaced.
struct OutputTarget {
    std::filesystem::path path;
    bool inPlace = false;
};

/// A folder an output needs does not exist: the output's own, or the system's temporary folder
/// that a stream's temporary is written in. path1() is the output, path2() the folder.
class MissingFolder : public std::filesystem::filesystem_error {
public:
    MissingFolder(const std::filesystem::path& output, const std::filesystem::path& folder, bool temporaryFolder);
    /// Whether the folder is the system's temporary folder ($TMPDIR).
    [[nodiscard]] bool temporaryFolder() const noexcept { return temporaryFolder_; }

private:
    bool temporaryFolder_;
};

/// Resolves `path` as described above. Throws std::filesystem::filesystem_error for a folder,
/// a loop of links, a link that cannot be read, or a descriptor that takes no writes.
[[nodiscard]] OutputTarget outputTarget(const std::filesystem::path& path);

/// outputTarget(), checked before any work is done for it: not a folder and, unless written
/// in place, in a folder that exists. Throws std::filesystem::filesystem_error naming `path`
/// (EISDIR for a folder), MissingFolder for a missing folder.
[[nodiscard]] OutputTarget writableOutputTarget(const std::filesystem::path& path);

/// Where a write to `path` lands, absolute, with links and dots resolved; empty where that
/// cannot be told (a folder, a loop of links: writing there fails and says why).
[[nodiscard]] std::filesystem::path landingPath(const std::filesystem::path& path);

/// The first of `inputs` that is the same file as `output` (an existing file, through links
/// and other names): writing `output` would destroy it. Empty names are skipped.
[[nodiscard]] std::optional<std::filesystem::path> sameFileAmong(const std::filesystem::path& output,
                                                                 std::span<const std::filesystem::path> inputs);

/// The first two of `outputs` (as indices, i < j) that one file would take: the same path
/// once links and dots are resolved, followed to where a write lands (outputTarget()) even
/// before anything is there, or an existing file under two names (a hard link). The second
/// write would replace the first. Empty names are skipped.
[[nodiscard]] std::optional<std::pair<size_t, size_t>> twoNamesOfOneFile(std::span<const std::filesystem::path> outputs);

/// Why a write that threw `error` (from the functions here) failed, in words for a message
/// that names the output already: "it is a folder", "the folder 'F' does not exist" (for
/// MissingFolder; the system's temporary folder says that TMPDIR names it), a descriptor that
/// takes no writes, or the system's
/// reason (for OldFileKept, followed by where the old file is kept).
[[nodiscard]] std::string whyNotWritten(const std::filesystem::filesystem_error& error);

/// A name for a temporary beside `target`: hidden, unique to this process and call, and ending
/// in the target's extension (writers that choose the format by extension keep choosing it).
[[nodiscard]] std::filesystem::path temporaryBeside(const std::filesystem::path& target);

/// Calls write(p) for p a temporary beside writableOutputTarget(path).path (which throws as it
/// says when there is no such place), then renames p over that
/// target. In place, p is in the system's temporary folder and, once written, is appended to
/// the target, which is opened without truncating it (a `>>` log is appended to) and gets
/// nothing if write fails; a temporary folder that does not exist throws MissingFolder before
/// write is called. If write throws or the rename or copy fails, removes the temporary
/// and leaves a replaced target as it was: write's exception is rethrown, a failed rename or
/// copy throws std::filesystem::filesystem_error.
void replaceFile(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);

/// A failure part way through replaceFilesContents()'s renames, after which an old file could
/// not be put back: it is kept under a hidden name beside its output. path1() is the output,
/// path2() the name it is kept under.
class OldFileKept : public std::filesystem::filesystem_error {
public:
    OldFileKept(const std::filesystem::path& output, const std::filesystem::path& kept, std::error_code why);
};

/// replaceFile() with `bytes` as the contents. A temporary that cannot be made or written (a
/// missing folder, a full disk) throws std::filesystem::filesystem_error naming `path`.
void replaceFileContents(const std::filesystem::path& path, std::string_view bytes);

/// Replaces each of `paths` with the bytes contents(i) makes for paths[i], all or none. Each
/// file is written once: contents(i) is called once per path, in order, and its bytes are
/// written to one temporary (beside the writableOutputTarget() of paths[i], which throws as it
/// says; in the system's temporary folder for one written in place) and dropped, so that one
/// file's bytes are held at a time. Once all are written, each FIFO or device gets its bytes
/// (appended, as replaceFile() does), then each temporary is renamed over its target, once.
/// Each old file is kept under a hidden name (a hard link) until every rename is done; when
/// one fails, the targets renamed so far get their old files back (one that did not exist is
/// removed). Whatever fails, no temporary is left and a file not renamed is as it was (a FIFO
/// or device written before has had its bytes); an exception of contents is rethrown, any
/// other failure throws std::filesystem::filesystem_error whose path1() is the paths[i] it
/// concerns: MissingFolder, and OldFileKept for an old file that could not be put back. On a
/// filesystem without hard links the old files cannot be kept, and a failure part way leaves
/// the targets renamed so far replaced. Throws std::invalid_argument, writing nothing, where
/// twoNamesOfOneFile(paths) finds two: one would be replaced by the other.
void replaceFilesContents(std::span<const std::filesystem::path> paths,
                          const std::function<std::string(size_t)>& contents);

}  // namespace skygraph::files
