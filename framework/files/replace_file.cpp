#include "replace_file.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <string>
#include <system_error>

namespace skygraph::files {
namespace fs = std::filesystem;

namespace {
bool isUnderProc(const fs::path& p) {
    const fs::path normal = p.lexically_normal();
    auto part = normal.begin();
    return normal.is_absolute() && ++part != normal.end() && *part == "proc";
}
}  // namespace

OutputTarget outputTarget(const fs::path& path) {
    constexpr int kMostLinks = 40;  // Linux's own limit on a path's links (ELOOP)
    fs::path at = path;
    for (int links = 0; fs::is_symlink(fs::symlink_status(at)); ++links) {
        if (links == kMostLinks)
            throw fs::filesystem_error("cannot write", path, std::make_error_code(std::errc::too_many_symbolic_link_levels));
        const fs::path to = fs::read_symlink(at);
        at = to.is_absolute() ? to : at.parent_path() / to;
        // /dev/stdout and /dev/fd/N lead to /proc's links to open descriptors: writing the file
        // such a link names would replace a shell's `>>` log instead of appending to the stream.
        if (isUnderProc(at)) return {path, true};
    }
    std::error_code ec;
    const fs::file_status status = fs::status(at, ec);
    if (fs::is_directory(status))
        throw fs::filesystem_error("cannot write", path, std::make_error_code(std::errc::is_a_directory));
    return {at, fs::exists(status) && !fs::is_regular_file(status)};
}

fs::path temporaryBeside(const fs::path& target) {
    static std::atomic<uint32_t> calls{0};  // threads of one process write beside one target too
    fs::path temporary = target;
    temporary.replace_filename("." + target.stem().string() + ".partial" + std::to_string(::getpid()) + "-" +
                               std::to_string(calls++) + target.extension().string());
    return temporary;
}

void replaceFile(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    const OutputTarget target = outputTarget(path);
    if (target.inPlace) {
        write(target.path);
        return;
    }
    const fs::path temporary = temporaryBeside(target.path);
    std::error_code ignored;
    try {
        write(temporary);
        fs::rename(temporary, target.path);
    } catch (...) {
        fs::remove(temporary, ignored);
        throw;
    }
}

void replaceFileContents(const fs::path& path, std::string_view bytes) {
    replaceFile(path, [&](const fs::path& to) {
        std::ofstream out(to, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close();
        if (!out) throw fs::filesystem_error("cannot write", to, std::make_error_code(std::errc::io_error));
    });
}

}  // namespace skygraph::files
