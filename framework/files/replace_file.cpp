#include "replace_file.hpp"

#include "pending_temporaries.hpp"
#include "printable_name.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace skygraph::files {
namespace fs = std::filesystem;

namespace {

/// Whether `path` names an entry of /proc, such as /proc/self/fd/1, by the real folder it is
/// in: /dev/stdout, /dev/fd/1 and /proc/self/fd/1 all lead to a descriptor's link there.
bool inProc(const fs::path& path) {
    std::error_code ec;
    const fs::path folder = fs::canonical(path.has_parent_path() ? path.parent_path() : fs::path("."), ec);
    auto part = folder.begin();
    return !ec && folder.is_absolute() && ++part != folder.end() && *part == "proc";
}

std::error_code lastError() { return {errno ? errno : EIO, std::system_category()}; }

/// For `link` in /proc, a descriptor's link of this process (/proc/self/fd/N, where
/// /dev/stdout leads): whether descriptor N is open for writing. Reopening the link opens
/// whatever file N leads to afresh, for writing, even where N is held only to read (the
/// command line holds a standard descriptor its parent closed so, and its writes fail as a
/// closed one's would): a stream that takes no writes must not get them by another road.
/// Any other entry of /proc is left to open() to judge.
bool writableIfOwnDescriptor(const fs::path& link) {
    std::error_code ec;
    const fs::path folder = fs::canonical(link.parent_path(), ec);
    if (ec || folder != fs::path("/proc") / std::to_string(::getpid()) / "fd") return true;
    const std::string name = link.filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos || name.size() > 9) return true;
    const int flags = ::fcntl(std::stoi(name), F_GETFL);
    return flags != -1 && (flags & O_ACCMODE) != O_RDONLY;
}

/// Appends the whole of `from` to `to`, an existing FIFO, device or descriptor, opened without
/// truncating it: a shell's `>>` log is appended to, as its redirection asked. Errors name
/// `output`, the name `to` was reached by.
void appendTo(const fs::path& to, const fs::path& from, const fs::path& output) {
    std::ifstream in(from, std::ios::binary);
    if (!in) throw fs::filesystem_error("cannot write", output, std::make_error_code(std::errc::io_error));
    const int fd = ::open(to.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (fd < 0) throw fs::filesystem_error("cannot write", output, lastError());
    const auto fail = [&](std::error_code error) {
        ::close(fd);
        throw fs::filesystem_error("cannot write", output, error);
    };
    std::vector<char> chunk(1 << 16);
    while (in) {
        in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
        for (size_t done = 0, size = static_cast<size_t>(in.gcount()); done < size;) {
            const ssize_t n = ::write(fd, chunk.data() + done, size - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) fail(lastError());
            done += static_cast<size_t>(n);
        }
    }
    if (in.bad()) fail(std::make_error_code(std::errc::io_error));
    if (::close(fd) != 0) throw fs::filesystem_error("cannot write", output, lastError());
}

/// Writes `bytes` to the new file `to`, checking every step: a full disk or a file size limit
/// is an error naming `output`, never a short file.
void writeWhole(const fs::path& to, std::string_view bytes, const fs::path& output) {
    errno = 0;
    std::ofstream out(to, std::ios::binary | std::ios::trunc);
    if (!out.is_open()) throw fs::filesystem_error("cannot write", output, lastError());
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw fs::filesystem_error("cannot write", output, lastError());
}

/// The permission bits of `target` when it is a regular file.
std::optional<fs::perms> regularFileMode(const fs::path& target) {
    std::error_code ec;
    const fs::file_status status = fs::status(target, ec);
    if (ec || !fs::is_regular_file(status)) return std::nullopt;
    return status.permissions() & fs::perms::all;
}

/// A file replaced by renaming a new one over it keeps its permission bits: a private output
/// (mode 0600) stays private. Read again here, after the write, rather than kept from
/// startTemporaryLike: a mode changed meanwhile is the one kept. Best effort: a temporary the
/// user cannot change keeps the mode it was made with (what a new file gets).
void keepPermissions(const fs::path& temporary, const fs::path& target) {
    std::error_code ignored;
    if (const auto mode = regularFileMode(target)) fs::permissions(temporary, *mode, fs::perm_options::replace, ignored);
}

/// Makes the empty temporary for `target` before anything is written to it, with no more
/// permissions than `target` has (the umask may take more away): a private file's new
/// contents are never readable by others while they are written. Writers open it truncating,
/// which keeps its mode. Nothing happens when `target` is no regular file yet.
void startTemporaryLike(const fs::path& temporary, const fs::path& target) {
    const auto mode = regularFileMode(target);
    if (!mode) return;
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, static_cast<mode_t>(*mode));
    if (fd >= 0) ::close(fd);
}

/// Where a stream's temporary is written; throws naming `path` and the folder when it is missing.
fs::path systemTemporaryFolder(const fs::path& path) {
    const char* named = std::getenv("TMPDIR");
    const fs::path folder = named && *named ? fs::path(named) : fs::path("/tmp");
    std::error_code ec;
    if (!fs::is_directory(folder, ec))
        throw MissingFolder(path, folder, named && *named);
    return folder;
}

/// One file of a set replaced together: `temporary`, written beside `target` (an
/// outputTarget() that is not in place), takes its place; errors name `output`, the name the
/// target was reached by.
struct Replacement {
    fs::path temporary;
    fs::path target;
    fs::path output;
};

/// replaceFilesContents()'s renames, all or none, as it describes them.
void renameAllOrNone(std::span<const Replacement> replacements) {
    const size_t n = replacements.size();
    std::vector<fs::path> kept(n);  // a hard link to the file the target was, if it was one
    std::vector<bool> existed(n);
    // The kept links, until their target is renamed: then a kept link may be the old file's
    // only name, which a rollback needs.
    std::vector<std::unique_ptr<PendingTemporary>> pending(n);
    std::error_code ignored;
    const auto removeKept = [&] {
        for (const fs::path& keep : kept)
            if (!keep.empty()) fs::remove(keep, ignored);
    };
    size_t renamed = 0;
    try {
        for (size_t i = 0; i < n; ++i) {
            std::error_code ec;
            const fs::file_status status = fs::symlink_status(replacements[i].target, ec);
            if (status.type() == fs::file_type::none) throw fs::filesystem_error("cannot write", replacements[i].output, ec);
            existed[i] = fs::exists(status);
            if (!existed[i]) continue;
            const fs::path keep = temporaryBeside(replacements[i].target);
            pending[i] = std::make_unique<PendingTemporary>(keep);
            fs::create_hard_link(replacements[i].target, keep, ec);
            if (!ec) kept[i] = keep;
        }
        for (size_t i = 0; i < n; ++i)
            if (existed[i]) keepPermissions(replacements[i].temporary, replacements[i].target);
        for (; renamed < n; ++renamed) {
            std::error_code ec;
            fs::rename(replacements[renamed].temporary, replacements[renamed].target, ec);
            if (ec) throw fs::filesystem_error("cannot write", replacements[renamed].output, ec);
            pending[renamed].reset();
        }
    } catch (...) {
        for (size_t i = renamed; i < n; ++i) fs::remove(replacements[i].temporary, ignored);
        for (size_t i = 0; i < renamed; ++i) {
            if (kept[i].empty()) {
                if (!existed[i]) fs::remove(replacements[i].target, ignored);
                continue;
            }
            std::error_code ec;
            fs::rename(kept[i], replacements[i].target, ec);
            if (!ec) {
                kept[i].clear();
                continue;
            }
            // The kept link is the old file's last name now: it stays, and the error says where.
            const fs::path keep = std::exchange(kept[i], {});
            removeKept();
            throw OldFileKept(replacements[i].output, keep, ec);
        }
        removeKept();
        throw;
    }
    removeKept();
}

}  // namespace

OutputTarget outputTarget(const fs::path& path) {
    constexpr int kMostLinks = 40;  // Linux's own limit on a path's links (ELOOP)
    fs::path at = path;
    for (int links = 0;; ++links) {
        // The stream a shell set up, not the file it may lead to: writing that file would
        // replace a `>>` log rather than append to it.
        if (inProc(at)) {
            if (!writableIfOwnDescriptor(at))
                throw fs::filesystem_error("cannot write", path, std::make_error_code(std::errc::bad_file_descriptor));
            return {path, true};
        }
        if (!fs::is_symlink(fs::symlink_status(at))) break;
        if (links == kMostLinks)
            throw fs::filesystem_error("cannot write", path, std::make_error_code(std::errc::too_many_symbolic_link_levels));
        const fs::path to = fs::read_symlink(at);
        at = to.is_absolute() ? to : at.parent_path() / to;
    }
    std::error_code ec;
    const fs::file_status status = fs::status(at, ec);
    if (fs::is_directory(status))
        throw fs::filesystem_error("cannot write", path, std::make_error_code(std::errc::is_a_directory));
    return {at, fs::exists(status) && !fs::is_regular_file(status)};
}

OutputTarget writableOutputTarget(const fs::path& path) {
    const OutputTarget target = outputTarget(path);
    const fs::path folder = target.path.parent_path();
    std::error_code ec;
    if (!target.inPlace && !folder.empty() && !fs::is_directory(folder, ec)) throw MissingFolder(path, folder, false);
    return target;
}

std::optional<fs::path> sameFileAmong(const fs::path& output, std::span<const fs::path> inputs) {
    std::error_code ec;
    if (output.empty() || !fs::exists(output, ec)) return std::nullopt;
    for (const fs::path& input : inputs)
        if (!input.empty() && fs::equivalent(input, output, ec)) return input;
    return std::nullopt;
}

fs::path landingPath(const fs::path& p) {
    fs::path landing = p;
    try {
        landing = outputTarget(p).path;  // a dangling link is followed: weakly_canonical leaves it
    } catch (const fs::filesystem_error&) {
        return {};  // a folder or a loop of links
    }
    // Absolute first: a relative path none of whose parts exists stays relative, so "a.svg"
    // would not meet "./a.svg".
    std::error_code ec;
    fs::path full = fs::absolute(landing, ec);
    if (!ec) full = fs::weakly_canonical(full, ec);
    return ec ? fs::path() : full;
}

std::optional<std::pair<size_t, size_t>> twoNamesOfOneFile(std::span<const fs::path> outputs) {
    std::vector<fs::path> landing(outputs.size());
    for (size_t i = 0; i < outputs.size(); ++i)
        if (!outputs[i].empty()) landing[i] = landingPath(outputs[i]);
    for (size_t j = 1; j < outputs.size(); ++j)
        for (size_t i = 0; i < j; ++i) {
            if (outputs[i].empty() || outputs[j].empty()) continue;
            if ((!landing[i].empty() && landing[i] == landing[j]) || sameFileAmong(outputs[j], outputs.subspan(i, 1)))
                return std::pair{i, j};
        }
    return std::nullopt;
}

MissingFolder::MissingFolder(const fs::path& output, const fs::path& folder, bool temporaryFolder)
    : fs::filesystem_error("cannot write", output, folder, std::make_error_code(std::errc::no_such_file_or_directory)),
      temporaryFolder_(temporaryFolder) {}

OldFileKept::OldFileKept(const fs::path& output, const fs::path& kept, std::error_code why)
    : fs::filesystem_error("cannot put the old file back", output, kept, why) {}

std::string whyNotWritten(const fs::filesystem_error& error) {
    if (dynamic_cast<const OldFileKept*>(&error))
        return error.code().message() + "; the old file could not be put back: it is kept as '" +
               printableName(error.path2().string()) + "'";
    if (const auto* missing = dynamic_cast<const MissingFolder*>(&error))
        return "the folder '" + printableName(missing->path2().string()) + "' does not exist" +
               (missing->temporaryFolder() ? " (TMPDIR names it: a stream is written through a temporary there)" : "");
    if (error.code() == std::errc::is_a_directory) return "it is a folder";
    if (error.code() == std::errc::bad_file_descriptor) return "it names a descriptor that is closed or not open for writing";
    return error.code().message();
}

fs::path temporaryBeside(const fs::path& target) {
    static std::atomic<uint32_t> calls{0};  // threads of one process write beside one target too
    const std::string suffix =
        ".partial" + std::to_string(::getpid()) + "-" + std::to_string(calls++) + target.extension().string();
    // A name of the longest a folder takes (NAME_MAX) leaves no room for the suffix: its stem gives way.
    constexpr size_t kLongestName = 255;
    const std::string stem = target.stem().string().substr(0, kLongestName - 1 - std::min(suffix.size(), kLongestName - 1));
    fs::path temporary = target;
    temporary.replace_filename("." + stem + suffix);
    return temporary;
}

void replaceFile(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    const OutputTarget target = writableOutputTarget(path);
    // In place, the temporary is the system's: writers that seek (OpenEXR) cannot write a pipe,
    // and a stream gets the file whole or nothing of it.
    const fs::path temporary = temporaryBeside(target.inPlace ? systemTemporaryFolder(path) / target.path.filename()
                                                              : target.path);
    const PendingTemporary pending(temporary);
    std::error_code ignored;
    try {
        if (!target.inPlace) startTemporaryLike(temporary, target.path);
        write(temporary);
        if (target.inPlace) {
            appendTo(target.path, temporary, path);
        } else {
            keepPermissions(temporary, target.path);
            fs::rename(temporary, target.path);
        }
    } catch (...) {
        fs::remove(temporary, ignored);
        throw;
    }
    if (target.inPlace) fs::remove(temporary, ignored);
}

void replaceFileContents(const fs::path& path, std::string_view bytes) {
    replaceFile(path, [&](const fs::path& to) { writeWhole(to, bytes, path); });
}

void replaceFilesContents(std::span<const fs::path> paths, const std::function<std::string(size_t)>& contents) {
    if (const auto two = twoNamesOfOneFile(paths))
        throw std::invalid_argument("replaceFilesContents: '" + printableName(paths[two->second].string()) +
                                    "' and '" + printableName(paths[two->first].string()) +
                                    "' are one file: one would replace the other");
    std::vector<fs::path> temporaries(paths.size());
    std::vector<OutputTarget> targets(paths.size());
    std::vector<std::unique_ptr<PendingTemporary>> pending;
    std::error_code ignored;
    const auto removeTemporaries = [&] {
        for (const fs::path& t : temporaries)
            if (!t.empty()) fs::remove(t, ignored);
    };
    try {
        for (size_t i = 0; i < paths.size(); ++i) {
            targets[i] = writableOutputTarget(paths[i]);
            // In place, as replaceFile() does: the stream gets the file whole, once all are made.
            temporaries[i] = temporaryBeside(targets[i].inPlace
                                                  ? systemTemporaryFolder(paths[i]) / targets[i].path.filename()
                                                  : targets[i].path);
            pending.push_back(std::make_unique<PendingTemporary>(temporaries[i]));
            if (!targets[i].inPlace) startTemporaryLike(temporaries[i], targets[i].path);
            writeWhole(temporaries[i], contents(i), paths[i]);
        }
        for (size_t i = 0; i < paths.size(); ++i)
            if (targets[i].inPlace) {
                appendTo(targets[i].path, temporaries[i], paths[i]);
                fs::remove(std::exchange(temporaries[i], {}), ignored);
            }
    } catch (...) {
        removeTemporaries();
        throw;
    }
    std::vector<Replacement> replacements;
    for (size_t i = 0; i < paths.size(); ++i)
        if (!targets[i].inPlace) replacements.push_back({temporaries[i], targets[i].path, paths[i]});
    renameAllOrNone(replacements);  // removes the temporaries it does not rename
}

}  // namespace skygraph::files
