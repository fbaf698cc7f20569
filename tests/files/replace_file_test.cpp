// files::replaceFile on real files, links and FIFOs in a fresh folder per test.
#include "replace_file.hpp"

#include "folder_events.hpp"
#include "pending_temporaries.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using skygraph::files::outputTarget;
using skygraph::files::replaceFile;
using skygraph::files::replaceFileContents;
using skygraph::files::replaceFilesContents;
using skygraph::files::temporaryBeside;
using skygraph::files::whyNotWritten;
using skygraph::test::FolderEvents;

namespace {

class ReplaceFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("skygraph-files-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    static std::string slurp(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }
    static void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
    /// What can be read now from a non-blocking descriptor.
    static std::string drain(int fd) {
        std::string out;
        char chunk[4096];
        for (ssize_t n; (n = ::read(fd, chunk, sizeof chunk)) > 0;) out.append(chunk, size_t(n));
        return out;
    }
    /// The names in `folder`, sorted: what a write left there, temporaries included.
    static std::vector<std::string> names(const fs::path& folder) {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(folder)) out.push_back(e.path().filename().string());
        std::sort(out.begin(), out.end());
        return out;
    }

    fs::path dir_;
};

TEST_F(ReplaceFile, ReplacesAFileWholeAndLeavesNoTemporary) {
    write(dir_ / "plan.json", "old contents, longer than the new");
    replaceFileContents(dir_ / "plan.json", "new");
    EXPECT_EQ(slurp(dir_ / "plan.json"), "new");
    EXPECT_EQ(names(dir_), std::vector<std::string>{"plan.json"});
}

// A private file stays private, also while its new contents are written, and one anybody may
// write stays so: the replacement takes the old file's permission bits, alone or in a set (a
// new file gets the usual 0666 & ~umask).
TEST_F(ReplaceFile, AReplacedFileKeepsItsPermissions) {
    const auto mode = [](const fs::path& p) { return fs::status(p).permissions() & fs::perms::mask; };
    write(dir_ / "private.json", "old");
    fs::permissions(dir_ / "private.json", fs::perms::owner_read | fs::perms::owner_write);
    replaceFileContents(dir_ / "private.json", "new");
    EXPECT_EQ(slurp(dir_ / "private.json"), "new");
    EXPECT_EQ(mode(dir_ / "private.json"), fs::perms::owner_read | fs::perms::owner_write);
    // And while it is written: the writer finds its temporary as private as the target.
    std::optional<fs::perms> whileWritten;
    replaceFile(dir_ / "private.json", [&](const fs::path& to) {
        std::ofstream(to, std::ios::binary | std::ios::trunc) << "newer";
        whileWritten = mode(to);
    });
    EXPECT_EQ(whileWritten, fs::perms::owner_read | fs::perms::owner_write);
    EXPECT_EQ(slurp(dir_ / "private.json"), "newer");
    write(dir_ / "cube.ktx2", "old");
    fs::permissions(dir_ / "cube.ktx2", fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                            fs::perms::group_write | fs::perms::others_write | fs::perms::others_read);
    const std::vector<fs::path> set{dir_ / "cube.ktx2", dir_ / "cube.brdf.ktx2"};
    replaceFilesContents(set, [&](size_t i) { return "new " + set[i].filename().string(); });
    EXPECT_EQ(mode(dir_ / "cube.ktx2"), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read |
                                            fs::perms::group_write | fs::perms::others_write | fs::perms::others_read);
    const mode_t mask = ::umask(0);
    ::umask(mask);
    EXPECT_EQ(static_cast<mode_t>(mode(dir_ / "cube.brdf.ktx2")), 0666 & ~mask) << "a new file";
}

TEST_F(ReplaceFile, ALinkStaysALinkAndTheFileAtTheEndOfItsChainGetsTheContents) {
    fs::create_directories(dir_ / "real");
    write(dir_ / "real" / "out.png", "old");
    fs::create_symlink("real/out.png", dir_ / "second");  // relative to the link's folder
    fs::create_symlink(dir_ / "second", dir_ / "first");
    replaceFileContents(dir_ / "first", "new");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "first")));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "second")));
    EXPECT_EQ(slurp(dir_ / "real" / "out.png"), "new");
    EXPECT_EQ(names(dir_ / "real"), std::vector<std::string>{"out.png"});
    EXPECT_EQ(names(dir_), (std::vector<std::string>{"first", "real", "second"}));
}

TEST_F(ReplaceFile, ALinkToNothingYetCreatesItsTarget) {
    fs::create_symlink("made.txt", dir_ / "link");
    replaceFileContents(dir_ / "link", "made");
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link")));
    EXPECT_EQ(slurp(dir_ / "made.txt"), "made");
}

TEST_F(ReplaceFile, AFifoIsWrittenInPlaceForItsReader) {
    const fs::path fifo = dir_ / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_TRUE(outputTarget(fifo).inPlace);
    // Our own end, read and write, so that neither side waits for the other; a write that
    // replaced the FIFO leaves it empty.
    const int end = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(end, 0);
    replaceFileContents(fifo, "through the pipe");
    EXPECT_EQ(drain(end), "through the pipe");
    ::close(end);
    EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
    EXPECT_EQ(names(dir_), std::vector<std::string>{"pipe"});
}

// /dev/fd/N and /proc/self/fd/N name the descriptor, as /dev/stdout does: its file, opened
// for appending like a shell's `>>` log, is appended to and never replaced or truncated.
TEST_F(ReplaceFile, ADescriptorIsAppendedToAsItsShellOpenedIt) {
    write(dir_ / "log", "line 1\n");
    const int log = ::open((dir_ / "log").c_str(), O_WRONLY | O_APPEND);
    ASSERT_GE(log, 0);
    const auto inode = [&] {
        struct stat st {};
        ::stat((dir_ / "log").c_str(), &st);
        return st.st_ino;
    };
    const auto before = inode();
    for (const std::string prefix : {"/dev/fd/", "/proc/self/fd/"}) {
        const fs::path descriptor = prefix + std::to_string(log);
        EXPECT_TRUE(outputTarget(descriptor).inPlace) << descriptor;
        EXPECT_EQ(outputTarget(descriptor).path, descriptor);
        replaceFileContents(descriptor, prefix + "\n");
    }
    ::close(log);
    EXPECT_EQ(slurp(dir_ / "log"), "line 1\n/dev/fd/\n/proc/self/fd/\n");
    EXPECT_EQ(inode(), before) << "the log was replaced";
    EXPECT_EQ(names(dir_), std::vector<std::string>{"log"});
}

// A writer that seeks (OpenEXR) cannot write a pipe: in place, it writes a temporary of the
// system's, and the pipe gets it whole, or nothing when the writer fails.
TEST_F(ReplaceFile, InPlaceTheWriterGetsASeekableTemporaryAndTheStreamAllOrNothing) {
    const fs::path fifo = dir_ / "frames.exr";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const int end = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(end, 0);
    fs::path given;
    replaceFile(fifo, [&](const fs::path& temporary) {
        given = temporary;
        std::fstream out(temporary, std::ios::binary | std::ios::in | std::ios::out | std::ios::trunc);
        out << "header?? body";
        out.seekp(6);
        out << "ok";  // seeks back, as a writer filling in offsets does
    });
    EXPECT_EQ(drain(end), "headerok body");
    EXPECT_EQ(given.extension(), ".exr");
    EXPECT_FALSE(fs::exists(given)) << "the temporary stayed";
    EXPECT_THROW(replaceFile(fifo,
                             [&](const fs::path& temporary) {
                                 write(temporary, "half");
                                 throw std::runtime_error("the writer failed");
                             }),
                 std::runtime_error);
    EXPECT_EQ(drain(end), "") << "the stream got part of a failed write";
    ::close(end);
}

TEST_F(ReplaceFile, ADeviceIsWrittenInPlace) {
    const skygraph::files::OutputTarget null = outputTarget("/dev/null");
    EXPECT_TRUE(null.inPlace);
    EXPECT_EQ(null.path, fs::path("/dev/null"));
    EXPECT_FALSE(outputTarget(dir_ / "nothing yet").inPlace);
}

// Whatever file a shell redirected standard output to, /dev/stdout is written as the stream
// (appending to a `>>` log), never replaced by a new file.
TEST_F(ReplaceFile, StandardOutputIsTheStreamNotTheFileItWasRedirectedTo) {
    const skygraph::files::OutputTarget out = outputTarget("/dev/stdout");
    EXPECT_TRUE(out.inPlace);
    EXPECT_EQ(out.path, fs::path("/dev/stdout"));
    fs::create_symlink("/dev/stdout", dir_ / "to-stdout");
    EXPECT_EQ(outputTarget(dir_ / "to-stdout").path, dir_ / "to-stdout");
    EXPECT_TRUE(outputTarget(dir_ / "to-stdout").inPlace);
}

TEST_F(ReplaceFile, AFolderOrALoopOfLinksIsRefusedAndLeftAlone) {
    fs::create_directories(dir_ / "folder");
    EXPECT_THROW(replaceFileContents(dir_ / "folder", "x"), fs::filesystem_error);
    fs::create_symlink("folder", dir_ / "to-folder");
    EXPECT_THROW(replaceFileContents(dir_ / "to-folder", "x"), fs::filesystem_error);
    fs::create_symlink("loop-b", dir_ / "loop-a");
    fs::create_symlink("loop-a", dir_ / "loop-b");
    try {
        replaceFileContents(dir_ / "loop-a", "x");
        ADD_FAILURE() << "a loop of links was written";
    } catch (const fs::filesystem_error& e) {
        EXPECT_EQ(e.code(), std::make_error_code(std::errc::too_many_symbolic_link_levels));
    }
    EXPECT_EQ(names(dir_), (std::vector<std::string>{"folder", "loop-a", "loop-b", "to-folder"}));
    EXPECT_TRUE(fs::is_empty(dir_ / "folder"));
}

TEST_F(ReplaceFile, AWriteThatFailsLeavesTheFileAsItWasAndNoTemporary) {
    write(dir_ / "sky.exr", "precious");
    fs::path given;
    EXPECT_THROW(replaceFile(dir_ / "sky.exr",
                             [&](const fs::path& temporary) {
                                 given = temporary;
                                 write(temporary, "half");
                                 throw std::runtime_error("disk full");
                             }),
                 std::runtime_error);
    EXPECT_EQ(given.parent_path(), dir_);
    EXPECT_EQ(slurp(dir_ / "sky.exr"), "precious");
    EXPECT_EQ(names(dir_), std::vector<std::string>{"sky.exr"});
}

// A set of files replaced together (cubemap's outputs): all of them, and nothing left beside.
TEST_F(ReplaceFile, ReplacesASetOfFilesTogether) {
    write(dir_ / "cube.ktx2", "old cube");
    const fs::path witness = dir_.parent_path() / (dir_.filename().string() + "-witness");
    fs::remove(witness);
    fs::create_hard_link(dir_ / "cube.ktx2", witness);  // counts the old file's names
    const std::vector<fs::path> set{dir_ / "cube.ktx2", dir_ / "cube.brdf.ktx2"};
    replaceFilesContents(set, [&](size_t i) { return "new " + set[i].filename().string(); });
    EXPECT_EQ(slurp(dir_ / "cube.ktx2"), "new cube.ktx2");
    EXPECT_EQ(slurp(dir_ / "cube.brdf.ktx2"), "new cube.brdf.ktx2");
    EXPECT_EQ(fs::hard_link_count(witness), 1u) << "the old file's kept name is left";
    fs::remove(witness);
    EXPECT_EQ(names(dir_), (std::vector<std::string>{"cube.brdf.ktx2", "cube.ktx2"}));
}

// Each file of a set is written once, into one temporary beside it, and renamed into place
// once; its bytes are asked for once, in order.
TEST_F(ReplaceFile, EachFileOfASetIsWrittenOnceAndRenamedOnce) {
    write(dir_ / "cube.ktx2", "old cube");
    const std::vector<fs::path> set{dir_ / "cube.ktx2", dir_ / "cube.irradiance.ktx2", dir_ / "cross.exr"};
    FolderEvents events(dir_);
    std::vector<size_t> asked;
    replaceFilesContents(set, [&](size_t i) {
        asked.push_back(i);
        return "new " + set[i].filename().string();
    });
    const FolderEvents::Counts counts = events.take();
    EXPECT_EQ(asked, (std::vector<size_t>{0, 1, 2}));
    EXPECT_EQ(counts.renamedTo, (std::map<std::string, int>{{"cross.exr", 1}, {"cube.irradiance.ktx2", 1}, {"cube.ktx2", 1}}));
    EXPECT_EQ(counts.written.size(), set.size()) << "one temporary each";
    for (const auto& [name, times] : counts.written) {
        EXPECT_EQ(name.front(), '.') << name << " was written under its own name";
        EXPECT_EQ(times, 1) << name;
        EXPECT_EQ(counts.created.count(name), 1u) << name;
    }
    EXPECT_EQ(names(dir_), (std::vector<std::string>{"cross.exr", "cube.irradiance.ktx2", "cube.ktx2"}));
}

// The third rename fails (a folder took its target's name after the check): the first target
// gets its old file back, the second, new, is removed, no temporary is left, and the error
// names the output whose rename failed.
TEST_F(ReplaceFile, ASetThatCannotBeRenamedWholeIsPutBackAsItWas) {
    write(dir_ / "cube.ktx2", "old cube");
    const std::vector<fs::path> set{dir_ / "cube.ktx2", dir_ / "cube.irradiance.ktx2", dir_ / "cube.prefiltered.ktx2"};
    try {
        replaceFilesContents(set, [&](size_t i) {
            if (i == 2) fs::create_directories(set[2] / "inside");
            return "new " + set[i].filename().string();
        });
        ADD_FAILURE() << "renamed a file over a folder";
    } catch (const fs::filesystem_error& e) {
        EXPECT_EQ(e.path1(), set[2]);
        EXPECT_EQ(whyNotWritten(e), "it is a folder");
    }
    EXPECT_EQ(slurp(dir_ / "cube.ktx2"), "old cube");
    EXPECT_EQ(fs::hard_link_count(dir_ / "cube.ktx2"), 1u);
    EXPECT_TRUE(fs::is_directory(dir_ / "cube.prefiltered.ktx2" / "inside"));
    EXPECT_EQ(names(dir_), (std::vector<std::string>{"cube.ktx2", "cube.prefiltered.ktx2"}));
}

// Bytes that cannot be made (an image that does not encode) or a file that cannot be written
// (its folder is missing) leave every file as it was and no temporary; the error is the
// encoder's, or names the output.
TEST_F(ReplaceFile, ASetThatCannotBeWrittenWholeLeavesEveryFileAsItWas) {
    write(dir_ / "cube.ktx2", "old cube");
    const std::vector<fs::path> set{dir_ / "cube.ktx2", dir_ / "cube.brdf.ktx2"};
    EXPECT_THROW(replaceFilesContents(set,
                                      [&](size_t i) -> std::string {
                                          if (i == 1) throw std::runtime_error("cannot encode");
                                          return "new";
                                      }),
                 std::runtime_error);
    EXPECT_EQ(slurp(dir_ / "cube.ktx2"), "old cube");
    EXPECT_EQ(names(dir_), std::vector<std::string>{"cube.ktx2"});
    const std::vector<fs::path> missing{dir_ / "cube.ktx2", dir_ / "nowhere" / "cross.exr"};
    try {
        replaceFilesContents(missing, [](size_t) { return std::string("new"); });
        ADD_FAILURE() << "wrote into a folder that does not exist";
    } catch (const skygraph::files::MissingFolder& e) {
        EXPECT_EQ(e.path1(), missing[1]);
    }
    EXPECT_EQ(slurp(dir_ / "cube.ktx2"), "old cube");
    EXPECT_EQ(names(dir_), std::vector<std::string>{"cube.ktx2"});
}

// A stream in a set (here /dev/null) gets its bytes from a temporary in TMPDIR, which is gone
// afterwards; without that folder, nothing of the set is written.
TEST_F(ReplaceFile, AStreamInASetIsWrittenThroughTheSystemsTemporaryFolder) {
    struct Tmpdir {
        explicit Tmpdir(const fs::path& dir) {
            if (const char* before = std::getenv("TMPDIR")) previous = before;
            ::setenv("TMPDIR", dir.c_str(), 1);
        }
        ~Tmpdir() {
            if (previous) ::setenv("TMPDIR", previous->c_str(), 1);
            else ::unsetenv("TMPDIR");
        }
        std::optional<std::string> previous;
    };
    fs::create_directories(dir_ / "tmp");
    const std::vector<fs::path> set{dir_ / "cube.ktx2", "/dev/null"};
    {
        const Tmpdir tmp(dir_ / "tmp");
        replaceFilesContents(set, [](size_t) { return std::string("new"); });
    }
    EXPECT_EQ(slurp(dir_ / "cube.ktx2"), "new");
    EXPECT_TRUE(fs::is_empty(dir_ / "tmp"));
    fs::remove(dir_ / "cube.ktx2");
    {
        const Tmpdir tmp(dir_ / "no such folder");
        EXPECT_THROW(replaceFilesContents(set, [](size_t) { return std::string("new"); }), skygraph::files::MissingFolder);
    }
    EXPECT_EQ(names(dir_), std::vector<std::string>{"tmp"});
}

// An old file that a failed set could not put back is kept under a hidden name, and the
// reason says where.
// A descriptor of this process that takes no writes (held only to read, as the command line
// holds a standard one its parent closed, or closed): reopening its /proc link for writing
// would reach the file behind it, so its names are refused.
TEST_F(ReplaceFile, ADescriptorThatTakesNoWritesIsRefusedByEveryName) {
    write(dir_ / "behind.txt", "kept");
    const int readOnly = ::open((dir_ / "behind.txt").c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(readOnly, 0);
    const int closed = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    ASSERT_GE(closed, 0);
    ::close(closed);
    for (const int fd : {readOnly, closed})
        for (const std::string prefix : {"/dev/fd/", "/proc/self/fd/"}) {
            const fs::path name = prefix + std::to_string(fd);
            try {
                replaceFileContents(name, "new");
                ADD_FAILURE() << name << " was written";
            } catch (const fs::filesystem_error& e) {
                EXPECT_EQ(e.code(), std::errc::bad_file_descriptor) << name;
                EXPECT_EQ(whyNotWritten(e), "it names a descriptor that is closed or not open for writing");
            }
        }
    ::close(readOnly);
    EXPECT_EQ(slurp(dir_ / "behind.txt"), "kept");
    EXPECT_EQ(names(dir_), std::vector<std::string>{"behind.txt"});
}

// Outputs of one command that one file would take: through a link (to nothing yet too),
// dots, a relative name, or a hard link. replaceFilesContents() refuses them before writing:
// the second file replaced the first.
TEST_F(ReplaceFile, TwoNamesOfOneFileAreFoundAndASetNamingOneTwiceIsRefused) {
    const fs::path a = dir_ / "a.txt", b = dir_ / "b.txt";
    fs::create_symlink("a.txt", dir_ / "link.txt");  // to nothing yet
    std::vector<fs::path> outputs{b, a, dir_ / "link.txt"};
    EXPECT_EQ(skygraph::files::twoNamesOfOneFile(outputs), (std::pair<size_t, size_t>{1, 2}));
    outputs = {a, dir_ / "sub" / ".." / "a.txt"};
    fs::create_directory(dir_ / "sub");
    EXPECT_EQ(skygraph::files::twoNamesOfOneFile(outputs), (std::pair<size_t, size_t>{0, 1}));
    std::ofstream(b) << "old b";
    fs::create_hard_link(b, dir_ / "hard.txt");
    outputs = {dir_ / "hard.txt", a, b};
    EXPECT_EQ(skygraph::files::twoNamesOfOneFile(outputs), (std::pair<size_t, size_t>{0, 2}));
    outputs = {a, b, fs::path()};
    EXPECT_EQ(skygraph::files::twoNamesOfOneFile(outputs), std::nullopt);

    outputs = {a, dir_ / "link.txt"};
    bool called = false;
    EXPECT_THROW(replaceFilesContents(outputs, [&](size_t) { return called = true, std::string("x"); }),
                 std::invalid_argument);
    EXPECT_FALSE(called);
    EXPECT_FALSE(fs::exists(a));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 4) << "no temporary left";
}

TEST_F(ReplaceFile, AnOldFileThatCannotBePutBackSaysWhereItIsKept) {
    const skygraph::files::OldFileKept e(dir_ / "cube.ktx2", dir_ / ".cube.partial1-0.ktx2",
                                         std::make_error_code(std::errc::permission_denied));
    EXPECT_EQ(e.path1(), dir_ / "cube.ktx2");
    EXPECT_EQ(whyNotWritten(e), std::make_error_code(std::errc::permission_denied).message() +
                                    "; the old file could not be put back: it is kept as '" +
                                    (dir_ / ".cube.partial1-0.ktx2").string() + "'");
}

// A name as long as a folder takes (255 bytes) is written: its temporary's stem gives way.
TEST_F(ReplaceFile, ANameOfTheLongestAFolderTakesIsWritten) {
    const std::string name = std::string(251, 'a') + ".exr";
    replaceFileContents(dir_ / name, "long");
    EXPECT_EQ(slurp(dir_ / name), "long");
    EXPECT_EQ(names(dir_), std::vector<std::string>{name});
    const fs::path temporary = temporaryBeside(dir_ / name);
    EXPECT_LE(temporary.filename().string().size(), 255u);
    EXPECT_EQ(temporary.extension(), ".exr");
}

TEST_F(ReplaceFile, TemporariesAreHiddenUniqueAndKeepTheExtension) {
    const fs::path a = temporaryBeside(dir_ / "cube.ktx2"), b = temporaryBeside(dir_ / "cube.ktx2");
    EXPECT_NE(a, b);
    EXPECT_EQ(a.parent_path(), dir_);
    EXPECT_EQ(a.extension(), ".ktx2");
    EXPECT_EQ(a.filename().string().front(), '.');
}

// What a signal handler removes: the files named by live registrations, and only those. The
// registration of a temporary that replaceFile is writing is one of them.
TEST_F(ReplaceFile, PendingTemporariesAreRemovedUntilTheirWriteEnds) {
    using skygraph::files::PendingTemporary;
    using skygraph::files::removePendingTemporaries;
    const fs::path done = dir_ / ".done.partial", pending = dir_ / ".pending.partial";
    std::ofstream(done) << "renamed into place";
    { const PendingTemporary registration(done); }
    std::ofstream(pending) << "half written";
    {
        const PendingTemporary registration(pending);
        removePendingTemporaries();
        EXPECT_FALSE(fs::exists(pending));
    }
    EXPECT_TRUE(fs::exists(done));
    replaceFile(dir_ / "out.txt", [&](const fs::path& temporary) {
        std::ofstream(temporary) << "half";
        removePendingTemporaries();
        EXPECT_FALSE(fs::exists(temporary));
        std::ofstream(temporary) << "whole";
    });
    EXPECT_EQ(slurp(dir_ / "out.txt"), "whole");
    EXPECT_EQ(names(dir_), (std::vector<std::string>{".done.partial", "out.txt"}));
}

}  // namespace
