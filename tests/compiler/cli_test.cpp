// `skygraph compile` as users call it (docs/graph-format.md, "Command line"): exit status 0
// on success, 1 on a user error with the message on stderr and nothing half-written, 2 on
// misuse of the command line.
#include "cli_fixture.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/shading_math.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string_view>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using namespace skygraph::cli_test;
namespace fs = std::filesystem;

const char* kBadGraph = R"({
  "version": 1, "name": "bad",
  "resources": {
    "hdr": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output" },
    "out": { "type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
             "external": true, "final": "Present" }
  },
  "passes": [
    { "name": "tonemap", "type": "TonemappingPass",
      "uses": { "hdr": "Read@Fragment", "out": "Write@ColorAttachment" },
      "params": { "operator": "foo" } }
  ]
})";

/// A small graph with one optional pass, for culling, formats and --watch.
const char* kWatchedGraph = R"({
  "version": 1, "name": "watched", "features": { "blur": true },
  "resources": {
    "a":   { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output" },
    "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": "output",
             "external": true, "final": "TransferSrc" }
  },
  "passes": [
    { "name": "draw", "type": "Generic", "uses": { "a": "Write@ColorAttachment" } },
    { "name": "blur", "type": "Generic", "if": "blur", "uses": { "a": "ReadWrite@Compute" } },
    { "name": "present", "type": "Generic", "uses": { "a": "Read@Fragment", "out": "Write@ColorAttachment" } }
  ]
})";

TEST_F(Cli, CompileRasterAsJson) {
    const CliRun r = run({"compile", "graphs/raster.json", "--format", "json"});
    ASSERT_EQ(r.status, 0) << r.err;
    nlohmann::json plan;
    ASSERT_NO_THROW(plan = nlohmann::json::parse(r.out)) << r.out;
    ASSERT_TRUE(plan.is_object());
    for (const char* key : {"graph", "features", "passes", "final", "culled"})
        EXPECT_TRUE(plan.contains(key)) << key << " missing in " << r.out;
    EXPECT_EQ(plan["graph"], "raster");
    // The shipped graph grows features and alternative passes; these stay on by default.
    EXPECT_EQ(plan["features"]["geometry"], true) << plan["features"];
    EXPECT_EQ(plan["features"]["skybox"], true) << plan["features"];
    std::vector<std::string> names;
    for (const auto& p : plan["passes"]) {
        names.push_back(p["name"].get<std::string>());
        EXPECT_TRUE(p["type"].is_string());
        EXPECT_TRUE(p["barriers"].is_array());
    }
    EXPECT_EQ(names, (std::vector<std::string>{"forward_ibl", "skybox", "tonemap"}));
    ASSERT_TRUE(plan["culled"].is_array());
    for (const auto& c : plan["culled"]) {
        EXPECT_TRUE(c["pass"].is_string()) << c;
        EXPECT_TRUE(c["reason"].is_string()) << c;
    }
    // The swapchain ends in PRESENT_SRC.
    bool present = false;
    for (const auto& b : plan["final"])
        present |= b["resource"] == "swapchain" && b["newLayout"] == "VK_IMAGE_LAYOUT_PRESENT_SRC_KHR";
    EXPECT_TRUE(present) << plan["final"].dump(2);
}

TEST_F(Cli, FeatureOffCullsWithAReason) {
    const fs::path graph = writeGraph("watched.json", kWatchedGraph);
    const CliRun r = run({"compile", graph.string(), "--format", "json", "--feature", "blur=off"});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto plan = nlohmann::json::parse(r.out);
    EXPECT_EQ(plan["features"]["blur"], false);
    ASSERT_EQ(plan["culled"].size(), 1u) << plan["culled"].dump();
    EXPECT_EQ(plan["culled"][0]["pass"], "blur");
    EXPECT_EQ(plan["culled"][0]["reason"], "feature 'blur' is off");
}

TEST_F(Cli, OutputFileMatchesStdout) {
    const CliRun toStdout = run({"compile", "graphs/raster.json", "--format", "json"});
    ASSERT_EQ(toStdout.status, 0);
    const fs::path out = dir_ / "work" / "plan.json";
    const CliRun toFile = run({"compile", "graphs/raster.json", "--format", "json", "-o", out.string()});
    ASSERT_EQ(toFile.status, 0) << toFile.err;
    EXPECT_EQ(toFile.out, "");
    EXPECT_EQ(slurp(out), toStdout.out);
    EXPECT_EQ(workFiles(), std::vector<std::string>{"plan.json"});  // no temporary left
}

// -o through a link writes the file the link names and keeps the link; -o /dev/stdout writes
// the stream the shell redirected (here to the fixture's file), replacing no file.
TEST_F(Cli, OutputThroughALinkOrToStandardOutput) {
    const CliRun toStdout = run({"compile", "graphs/raster.json", "--format", "json"});
    ASSERT_EQ(toStdout.status, 0);
    fs::create_directories(dir_ / "work" / "plans");
    std::ofstream(dir_ / "work" / "plans" / "raster.json") << "an older plan";
    fs::create_symlink("plans/raster.json", dir_ / "work" / "current.json");
    const CliRun viaLink =
        run({"compile", "graphs/raster.json", "--format", "json", "-o", (dir_ / "work" / "current.json").string()});
    ASSERT_EQ(viaLink.status, 0) << viaLink.err;
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "work" / "current.json")));
    EXPECT_EQ(slurp(dir_ / "work" / "plans" / "raster.json"), toStdout.out);
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir_ / "work" / "plans")) left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"raster.json"});  // no temporary left beside the target

    const CliRun viaStdout = run({"compile", "graphs/raster.json", "--format", "json", "-o", "/dev/stdout"});
    ASSERT_EQ(viaStdout.status, 0) << viaStdout.err;
    EXPECT_EQ(viaStdout.out, toStdout.out);

    // Redirected with `>>`, standard output appends to the log: the log is not replaced.
    const fs::path log = dir_ / "work" / "log.txt";
    std::ofstream(log) << "earlier\n";
    const std::string command = "cd " + quote(kSource.string()) + " && " + quote(kCli.string()) +
                                " compile graphs/raster.json --format json -o /dev/stdout >> " + quote(log.string());
    EXPECT_EQ(std::system(command.c_str()), 0);
    EXPECT_EQ(slurp(log), "earlier\n" + toStdout.out);
}

TEST_F(Cli, TextAndDotFormats) {
    const CliRun text = run({"compile", "graphs/raster.json"});
    ASSERT_EQ(text.status, 0) << text.err;
    EXPECT_NE(text.out.find("tonemap"), std::string::npos) << text.out;
    const fs::path graph = writeGraph("watched.json", kWatchedGraph);
    const CliRun dot = run({"compile", graph.string(), "--format", "dot", "--feature", "blur=off"});
    ASSERT_EQ(dot.status, 0) << dot.err;
    EXPECT_EQ(dot.out.rfind("digraph", 0), 0u) << dot.out;
    EXPECT_NE(dot.out.find("feature 'blur' is off"), std::string::npos) << dot.out;
}

// What runs before the first frame is part of what `compile` shows, in every format.
TEST_F(Cli, EveryFormatShowsTheSetupBeforeTheFirstFrame) {
    const CliRun text = run({"compile", "graphs/pathtrace.json"});
    ASSERT_EQ(text.status, 0) << text.err;
    EXPECT_NE(text.out.find("setup, once before the first frame:"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("initialize accumulation (Clear)"), std::string::npos) << text.out;
    const CliRun json = run({"compile", "graphs/pathtrace.json", "--format", "json"});
    ASSERT_EQ(json.status, 0) << json.err;
    const auto plan = nlohmann::json::parse(json.out);
    ASSERT_TRUE(plan.contains("setup")) << json.out;
    EXPECT_EQ(plan["setup"]["passes"][0]["name"], "initialize accumulation");
    const CliRun dot = run({"compile", "graphs/pathtrace.json", "--format", "dot"});
    ASSERT_EQ(dot.status, 0) << dot.err;
    EXPECT_NE(dot.out.find("cluster_setup"), std::string::npos) << dot.out;
    EXPECT_NE(dot.out.find("initialize accumulation"), std::string::npos) << dot.out;
}

TEST_F(Cli, EveryShippedGraphCompiles) {
    for (const char* g : {"graphs/raster.json", "graphs/pathtrace.json", "graphs/ibl.json"}) {
        const CliRun r = run({"compile", g, "--format", "json"});
        EXPECT_EQ(r.status, 0) << g << ": " << r.err;
        EXPECT_TRUE(nlohmann::json::accept(r.out)) << g;
    }
}

TEST_F(Cli, BadGraphExitsOneAndWritesNothing) {
    const fs::path graph = writeGraph("bad.json", kBadGraph);
    const fs::path out = dir_ / "work" / "plan.json";
    const CliRun r = run({"compile", graph.string(), "--format", "json", "-o", out.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find(graph.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("passes[0].params.operator"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("pass 'tonemap'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(workFiles().empty());
}

TEST_F(Cli, BadGraphLeavesAnExistingOutputUntouched) {
    const fs::path graph = writeGraph("bad.json", kBadGraph);
    const fs::path out = dir_ / "work" / "plan.json";
    std::ofstream(out) << "previous plan\n";
    const CliRun r = run({"compile", graph.string(), "-o", out.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(slurp(out), "previous plan\n");
    EXPECT_EQ(workFiles(), std::vector<std::string>{"plan.json"});
}

TEST_F(Cli, MalformedGraphReportsLineAndColumn) {
    const fs::path graph = writeGraph("broken.json", "{\n  \"version\": 1,\n  \"name\": \n}\n");
    const CliRun r = run({"compile", graph.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(graph.string() + ":4:1:"), std::string::npos) << r.err;
}

TEST_F(Cli, MissingGraphFileExitsOne) {
    const fs::path out = dir_ / "work" / "plan.json";
    const CliRun r = run({"compile", (dir_ / "nope.json").string(), "-o", out.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("nope.json"), std::string::npos) << r.err;
    EXPECT_TRUE(workFiles().empty());
}

TEST_F(Cli, AGraphFileThatIsEndlessOrADirectoryExitsOne) {
    const CliRun endless = run({"compile", "/dev/zero"});
    EXPECT_EQ(endless.status, 1) << endless.err;
    EXPECT_NE(endless.err.find("error: /dev/zero: is larger than 256 MiB, the most a graph file may be"),
              std::string::npos)
        << endless.err;
    const CliRun folder = run({"compile", dir_.string()});
    EXPECT_EQ(folder.status, 1) << folder.err;
    EXPECT_NE(folder.err.find("error: " + dir_.string() + ": cannot read the file"), std::string::npos) << folder.err;
}

TEST_F(Cli, UnwritableOutputExitsOne) {
    const fs::path out = dir_ / "work" / "no_such_dir" / "plan.json";
    const CliRun r = run({"compile", "graphs/raster.json", "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("cannot write '" + out.string() + "': the folder '" + out.parent_path().string() +
                         "' does not exist"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(workFiles().empty());
    // A folder where the file would go: the rename's reason, and no temporary left.
    fs::create_directories(dir_ / "work" / "plan");
    const CliRun folder = run({"compile", "graphs/raster.json", "-o", (dir_ / "work" / "plan").string()});
    EXPECT_EQ(folder.status, 1) << folder.err;
    EXPECT_NE(folder.err.find("plan': it is a folder"), std::string::npos) << folder.err;
    EXPECT_EQ(workFiles(), std::vector<std::string>{"plan"});
}

// What the system refuses part way through a write names the output and the reason, and
// leaves nothing: a file size limit (as a full disk would; SIGXFSZ ignored, so the write fails
// with EFBIG), and a TMPDIR that does not exist for an output that is a stream.
TEST_F(Cli, WritesTheSystemRefusesNameTheOutputAndLeaveNothing) {
    const fs::path png = dir_ / "work" / "frame.png";
    const CliRun cut = run({"-q", "render", "--width", "64", "--height", "64", "-o", png.string()},
                           "trap '' XFSZ; ulimit -f 1; ");
    EXPECT_EQ(cut.status, 1) << cut.err;
    EXPECT_NE(cut.err.find("'" + png.string() + "': cannot write: File too large"), std::string::npos) << cut.err;
    EXPECT_TRUE(workFiles().empty());
    // cubemap writes each product to a temporary first: the error still names the product.
    ASSERT_EQ(run({"-q", "sky-sequence", (dir_ / "sky%d.exr").string(), "--frames", "1", "--width", "32"}).status, 0);
    const fs::path cube = dir_ / "work" / "cube.ktx2";
    const CliRun cutCube = run({"-q", "cubemap", (dir_ / "sky0.exr").string(), "-o", cube.string(), "--size", "32"},
                               "trap '' XFSZ; ulimit -f 8; ");
    EXPECT_EQ(cutCube.status, 1) << cutCube.err;
    EXPECT_NE(cutCube.err.find("'" + cube.string() + "': cannot write: File too large"), std::string::npos)
        << cutCube.err;
    EXPECT_TRUE(workFiles().empty());

    const std::string missing = (dir_ / "no such folder").string();
    const CliRun stream = run({"compile", "graphs/raster.json", "-o", "/dev/null"}, "export TMPDIR=" + quote(missing) + "; ");
    EXPECT_EQ(stream.status, 1) << stream.err;
    EXPECT_NE(stream.err.find("cannot write '/dev/null': the folder '" + missing + "' does not exist (TMPDIR names it"),
              std::string::npos)
        << stream.err;
}

TEST_F(Cli, StandardOutputThatCannotBeWrittenExitsOne) {
    // /dev/full fails every write, as a full disk does: the plan was not printed.
    for (const char* format : {"text", "json"}) {
        const std::string command = std::string(SKYGRAPH_CLI) + " compile " + SKYGRAPH_SOURCE_DIR +
                                    "/graphs/raster.json --format " + format + " >/dev/full 2>" +
                                    (dir_ / "err.txt").string();
        const int status = std::system(command.c_str());
        ASSERT_TRUE(WIFEXITED(status)) << format;
        EXPECT_EQ(WEXITSTATUS(status), 1) << format;
        const std::string text = slurp(dir_ / "err.txt");
        EXPECT_NE(text.find("error: cannot write to standard output"), std::string::npos) << text;
    }
}

// Standard output or error closed by the parent (`>&-`): the next file opened took its number,
// so `-o /dev/stdout` wrote the plan into the output's own temporary, which was then removed
// (exit 0, nothing written), and log lines went into whatever file held fd 2. Now every write
// to a closed standard descriptor fails and says so, and other files get none of it.
TEST_F(Cli, ClosedStandardDescriptorsTakeNoWritesByAnyName) {
    const auto shell = [&](const std::string& tail) {
        const std::string command = std::string(SKYGRAPH_CLI) + " -v compile " + SKYGRAPH_SOURCE_DIR +
                                    "/graphs/raster.json " + tail;
        const int status = std::system(command.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    const std::string err = " 2>" + (dir_ / "err.txt").string();
    for (const char* name : {"/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"}) {
        EXPECT_EQ(shell(std::string("-o ") + name + " >&-" + err), 1) << name;
        EXPECT_NE(slurp(dir_ / "err.txt").find(std::string("cannot write '") + name +
                                               "': it names a descriptor that is closed or not open for writing"),
                  std::string::npos)
            << slurp(dir_ / "err.txt");
    }
    EXPECT_EQ(shell(">&-" + err), 1);
    EXPECT_NE(slurp(dir_ / "err.txt").find("error: cannot write to standard output"), std::string::npos);
    // Standard error closed: the message has nowhere to go, the exit status still says it.
    EXPECT_EQ(shell("-o /dev/stderr 2>&-"), 1);
    EXPECT_EQ(shell("-o " + (dir_ / "plan.txt").string() + " 2>&-"), 0) << "other outputs are written";
    EXPECT_NE(slurp(dir_ / "plan.txt").find("[0] forward_ibl (ForwardPass)"), std::string::npos);
}

// An output stream whose reader is gone ends the run with SIGPIPE, as it would any program,
// and the temporary the plan was written to first (in TMPDIR) goes with it.
TEST_F(Cli, AStreamWhoseReaderIsGoneEndsTheRunWithoutItsTemporary) {
    const fs::path temporaries = dir_ / "tmp";
    fs::create_directories(temporaries);
    int ends[2];
    ASSERT_EQ(::pipe(ends), 0);
    ::close(ends[0]);  // no reader
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, ends[1], 1);
    posix_spawn_file_actions_addclose(&actions, ends[1]);
    posix_spawn_file_actions_addchdir_np(&actions, kSource.c_str());
    posix_spawnattr_t attributes;  // SIGPIPE as a shell leaves it, whatever the test runner does
    posix_spawnattr_init(&attributes);
    sigset_t pipeSignal;
    sigemptyset(&pipeSignal);
    sigaddset(&pipeSignal, SIGPIPE);
    posix_spawnattr_setsigdefault(&attributes, &pipeSignal);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
    std::string tmpdir = "TMPDIR=" + temporaries.string();
    std::vector<char*> environment;
    for (char** e = environ; *e; ++e)
        if (std::string_view(*e).substr(0, 7) != "TMPDIR=") environment.push_back(*e);
    environment.push_back(tmpdir.data());
    environment.push_back(nullptr);
    std::vector<std::string> args{kCli.string(), "compile", "graphs/raster.json", "-o", "/dev/stdout"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    ASSERT_EQ(posix_spawn(&pid, kCli.c_str(), &actions, &attributes, argv.data(), environment.data()), 0);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    ::close(ends[1]);
    int raw = 0;
    ASSERT_EQ(::waitpid(pid, &raw, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(raw) && WTERMSIG(raw) == SIGPIPE) << raw;
    EXPECT_TRUE(fs::is_empty(temporaries));
}

TEST_F(Cli, UnknownFeatureExitsOne) {
    const fs::path out = dir_ / "work" / "plan.json";
    const CliRun r = run({"compile", "graphs/raster.json", "--feature", "nosuch=on", "-o", out.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("unknown feature 'nosuch'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("graphs/raster.json"), std::string::npos) << r.err;
    EXPECT_TRUE(workFiles().empty());
}

TEST_F(Cli, BadFeatureValueExitsTwo) {
    for (const char* flag : {"skybox=maybe", "skybox", "=on", "skybox=ON"}) {
        const CliRun r = run({"compile", "graphs/raster.json", "--feature", flag});
        EXPECT_EQ(r.status, 2) << flag << ": " << r.err;
        EXPECT_EQ(r.out, "") << flag;
        EXPECT_NE(r.err.find("--feature"), std::string::npos) << flag << ": " << r.err;
    }
}

TEST_F(Cli, AFeatureGivenTwiceExitsTwo) {
    // Even with the same value: a script that sets a feature twice has lost track of it.
    for (const char* second : {"skybox=off", "skybox=on"}) {
        const CliRun r = run({"compile", "graphs/raster.json", "--feature", "skybox=on", "--feature", second});
        EXPECT_EQ(r.status, 2) << second << ": " << r.err;
        EXPECT_EQ(r.out, "") << second;
        EXPECT_NE(r.err.find("--feature gives feature 'skybox' twice"), std::string::npos) << second << ": " << r.err;
    }
}

// Paths and words from the command line are shown with control characters escaped, as names
// from files are: a bell or a line break in one would ring or split the message.
TEST_F(Cli, CommandLineTextIsShownEscaped) {
    const auto controlCharacters = [](const std::string& text) {
        return std::count_if(text.begin(), text.end(), [](char c) {
            return c != '\n' && (static_cast<unsigned char>(c) < 0x20 || c == 0x7f);
        });
    };
    const fs::path out = dir_ / "work" / "no\a_dir" / "plan.json";
    const std::string shown = (dir_ / "work").string() + "/no\\u0007_dir";
    const CliRun unwritable = run({"compile", "graphs/raster.json", "-o", out.string()});
    EXPECT_EQ(unwritable.status, 1) << unwritable.err;
    EXPECT_NE(unwritable.err.find("cannot write '" + shown + "/plan.json': the folder '" + shown + "' does not exist"),
              std::string::npos)
        << unwritable.err;
    const CliRun feature = run({"compile", "graphs/raster.json", "--feature", "sky\abox=maybe"});
    EXPECT_EQ(feature.status, 2) << feature.err;
    EXPECT_NE(feature.err.find("got 'sky\\u0007box=maybe'"), std::string::npos) << feature.err;
    const CliRun command = run({"comp\nile"});
    EXPECT_EQ(command.status, 2) << command.err;
    EXPECT_NE(command.err.find("unknown command 'comp\\u000aile'"), std::string::npos) << command.err;
    // CLI11's own messages too, prefixed as every error is.
    const CliRun option = run({"compile", "graphs/raster.json", "--bo\ngus"});
    EXPECT_EQ(option.status, 2) << option.err;
    EXPECT_NE(option.err.find("error: The following argument was not expected: --bo\\u000agus"), std::string::npos)
        << option.err;
    std::vector<CliRun> runs{unwritable, feature, command, option};
#if SKYGRAPH_CLI_HAS_RENDER
    // Refused before any device is made.
    const CliRun render = run({"render", "-o", (dir_ / "work" / "frame\a.jpg").string()});
    EXPECT_EQ(render.status, 1) << render.err;
    EXPECT_NE(render.err.find("frame\\u0007.jpg': its extension must be"), std::string::npos) << render.err;
    // Either command's output of the wrong kind is a problem with the input, as documented.
    const CliRun cubemap = run({"cubemap", "sky.hdr", "-o", "sky\a.png"});
    EXPECT_EQ(cubemap.status, 1) << cubemap.err;
    EXPECT_NE(cubemap.err.find("'sky\\u0007.png': cannot write: its extension must be .ktx2"), std::string::npos)
        << cubemap.err;
    const CliRun cross = run({"cubemap", "sky.hdr", "-o", "sky.KTX2", "--cross", "cross.png"});
    EXPECT_EQ(cross.status, 1) << cross.err;
    EXPECT_NE(cross.err.find("'cross.png': cannot write --cross: its extension must be .hdr or .exr"),
              std::string::npos)
        << cross.err;
    runs.insert(runs.end(), {render, cubemap, cross});
#endif
    for (const CliRun& r : runs) EXPECT_EQ(controlCharacters(r.err), 0) << r.err;
    EXPECT_TRUE(workFiles().empty());
}

#if SKYGRAPH_CLI_HAS_RENDER
// An output named only by an extension ("-o .ktx2") has the extension it needs and no name
// before it: said so, not that its extension is missing; exit 1 and nothing written.
TEST_F(Cli, AnOutputNamedOnlyByItsExtensionIsSaidToHaveNoStem) {
    const fs::path cube = dir_ / "work" / ".ktx2", cross = dir_ / "work" / ".EXR", frame = dir_ / "work" / ".png";
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"cubemap", "sky.hdr", "-o", cube.string()},
         "error: -o '" + cube.string() + "': the file name has no stem, only an extension (e.g. sky.ktx2)\n"},
        {{"cubemap", "sky.hdr", "-o", (dir_ / "work" / "sky.ktx2").string(), "--cross", cross.string()},
         "error: --cross '" + cross.string() + "': the file name has no stem, only an extension (e.g. cross.EXR)\n"},
        {{"render", "-o", frame.string()},
         "skygraph render: -o '" + frame.string() + "': the file name has no stem, only an extension (e.g. "
         "frame.png)\n"},
    };
    for (const auto& [args, message] : cases) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 1) << args.back() << ": " << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("its extension must be"), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty()) << args.back();
    }
}
#endif

TEST_F(Cli, MisuseExitsTwo) {
    const std::vector<std::vector<std::string>> cases{
        {"compile", "graphs/raster.json", "--bogus"},
        {"compile", "graphs/raster.json", "--format", "yaml"},
        {"compile"},
        {},
        {"frobnicate"},
        {"compile", "graphs/raster.json", "-o"},
    };
    for (const auto& args : cases) {
        std::string shown;
        for (const auto& a : args) shown += a + " ";
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << shown << "\nstdout: " << r.out << "\nstderr: " << r.err;
        EXPECT_NE(r.err, "") << shown;
    }
}

TEST_F(Cli, HelpExitsZero) {
    const CliRun r = run({"compile", "--help"});
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("--feature"), std::string::npos) << r.out;
}

// -v and -q contradict each other: neither silently wins, before or after the command's name.
TEST_F(Cli, VerboseAndQuietTogetherAreMisuse) {
    for (const auto& args : std::vector<std::vector<std::string>>{{"-v", "-q", "compile", "graphs/raster.json"},
                                                                  {"compile", "graphs/raster.json", "-q", "-v"},
                                                                  {"-q", "compile", "graphs/raster.json", "--verbose"}}) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << args[0] << ": " << r.err;
        EXPECT_NE(r.err.find("--verbose excludes --quiet"), std::string::npos) << r.err;
        EXPECT_EQ(r.out, "") << "no plan";
    }
}

// ---- compile: output size and transient memory -------------------------------------------

/// The shipped deferred frame, whose 22 transient resources share memory.
const fs::path kDeferred = kSource / "graphs" / "deferred.json";

/// python3's XML parser on `svg`: "ok N" with N the <rect class="placement"> elements, or its error.
std::string parseSvgWithPython(const fs::path& svg, const fs::path& scratch) {
    const std::string cmd =
        "python3 -c \"import sys, xml.etree.ElementTree as E\n"
        "root = E.parse(sys.argv[1]).getroot()\n"
        "assert root.tag == '{http://www.w3.org/2000/svg}svg', root.tag\n"
        "print('ok', sum(1 for e in root.iter('{http://www.w3.org/2000/svg}rect') if e.get('class') == 'placement'))\" " +
        quote(svg.string()) + " >" + quote(scratch.string()) + " 2>&1";
    const int status = std::system(cmd.c_str());
    std::string printed = slurp(scratch);
    while (!printed.empty() && printed.back() == '\n') printed.pop_back();
    return status == 0 ? printed : "python3 failed: " + printed;
}

/// Whether a barrier of `plan` takes over memory that other resources of the frame used (and
/// not only what the previous frame used).
bool anyBarrierAliases(const nlohmann::json& plan) {
    for (const auto& pass : plan["passes"])
        for (const auto& b : pass["barriers"])
            if (b.contains("aliases") && !b["aliases"].empty()) return true;
    return false;
}

// docs/graph-format.md: the deferred frame's bloom chain needs an output whose longer side is
// at least 64 pixels, and a smaller one names the chain.
TEST_F(Cli, TheDeferredFrameNeedsALongerSideOf64) {
    EXPECT_EQ(run({"compile", kDeferred.string(), "--width", "64", "--height", "1"}).status, 0);
    EXPECT_EQ(run({"compile", kDeferred.string(), "--width", "1", "--height", "64"}).status, 0);
    const CliRun small = run({"compile", kDeferred.string(), "--width", "63", "--height", "63"});
    EXPECT_EQ(small.status, 1);
    EXPECT_NE(small.err.find("resources.bloom_down.mips: resource 'bloom_down': 6 levels is more than a 31x31 image has (5)"),
              std::string::npos)
        << small.err;
    // With bloom off no pass that runs uses the chain: it is never created, and not checked.
    const CliRun bloomOff = run({"compile", kDeferred.string(), "--width", "63", "--height", "63", "--feature",
                                 "bloom=off"});
    EXPECT_EQ(bloomOff.status, 0) << bloomOff.err;
}

TEST_F(Cli, MemorySvgIsWrittenWhole) {
    const fs::path svg = dir_ / "work" / "memory.svg";
    const CliRun r = run({"compile", kDeferred.string(), "--format", "json", "--memory-svg", svg.string()});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto plan = nlohmann::json::parse(r.out);  // the plan still goes to stdout
    const size_t placements = plan["memory"]["placements"].size();
    EXPECT_EQ(placements, 22u);
    EXPECT_EQ(parseSvgWithPython(svg, dir_ / "python"), "ok " + std::to_string(placements));
    EXPECT_EQ(workFiles(), std::vector<std::string>{"memory.svg"});  // no temporary left
    const std::string first = slurp(svg);
    ASSERT_EQ(run({"compile", kDeferred.string(), "--memory-svg", svg.string()}).status, 0);
    EXPECT_EQ(slurp(svg), first);  // the same plan draws the same picture, whatever the format
}

TEST_F(Cli, NoAliasAndPlacementChooseHowTransientsShareMemory) {
    const CliRun shared = run({"compile", kDeferred.string(), "--format", "json"});
    ASSERT_EQ(shared.status, 0) << shared.err;
    const auto aliased = nlohmann::json::parse(shared.out)["memory"];
    EXPECT_EQ(aliased["strategy"], "bestFitBySize");
    EXPECT_LT(aliased["heapBytes"], aliased["unaliasedBytes"]) << aliased.dump(1);
    EXPECT_TRUE(anyBarrierAliases(nlohmann::json::parse(shared.out)));

    const CliRun own = run({"compile", kDeferred.string(), "--format", "json", "--no-alias"});
    ASSERT_EQ(own.status, 0) << own.err;
    const auto plan = nlohmann::json::parse(own.out);
    EXPECT_EQ(plan["memory"]["strategy"], "unaliased");
    EXPECT_EQ(plan["memory"]["heapBytes"], plan["memory"]["unaliasedBytes"]);
    EXPECT_EQ(plan["memory"]["unaliasedBytes"], aliased["unaliasedBytes"]);
    EXPECT_FALSE(anyBarrierAliases(plan));
    // Each resource still takes over its own bytes from the previous frame: the frames share
    // the heaps unless --heaps-per-frame.
    for (const auto& p : plan["memory"]["placements"]) {
        EXPECT_TRUE(p["aliases"].empty()) << p;
        EXPECT_EQ(p["previousFrameAliases"], nlohmann::json::array({p["resource"]})) << p;
    }
    const CliRun perFrame = run({"compile", kDeferred.string(), "--format", "json", "--no-alias", "--heaps-per-frame"});
    ASSERT_EQ(perFrame.status, 0) << perFrame.err;
    const auto separate = nlohmann::json::parse(perFrame.out);
    EXPECT_FALSE(separate["memory"]["sharedAcrossFrames"]);
    for (const auto& pass : separate["passes"])
        for (const auto& b : pass["barriers"]) EXPECT_FALSE(b.contains("aliases")) << b;

    const CliRun firstUse = run({"compile", kDeferred.string(), "--format", "json", "--placement", "first-use"});
    ASSERT_EQ(firstUse.status, 0) << firstUse.err;
    EXPECT_EQ(nlohmann::json::parse(firstUse.out)["memory"]["strategy"], "firstUseOrder");
}

TEST_F(Cli, WidthAndHeightSetTheOutputSize) {
    const CliRun small = run({"compile", kDeferred.string(), "--format", "json", "--width", "640", "--height", "360"});
    ASSERT_EQ(small.status, 0) << small.err;
    const auto plan = nlohmann::json::parse(small.out);
    EXPECT_EQ(plan["output"], nlohmann::json::array({640, 360}));
    const auto full = nlohmann::json::parse(run({"compile", kDeferred.string(), "--format", "json"}).out);
    EXPECT_EQ(full["output"], nlohmann::json::array({1920, 1080}));
    EXPECT_LT(plan["memory"]["unaliasedBytes"], full["memory"]["unaliasedBytes"]);
}

TEST_F(Cli, BadSizesAndMemoryFlagsAreMisuse) {
    const std::string svg = (dir_ / "work" / "memory.svg").string();
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"--width", "0"}, "--width"},
        {{"--height", "16385"}, "--height"},
        {{"--width", "wide"}, "--width"},
        {{"--width", "-5"}, "--width"},
        {{"--placement", "worst-fit"}, "--placement"},
        {{"--no-alias", "--placement", "first-use"}, "--placement"},
        {{"--memory-svg"}, "--memory-svg"},
        {{"--watch-iterations", "2"}, "requires --watch"},
        {{"--watch-interval-ms", "100"}, "requires --watch"},
    };
    for (const auto& [flags, named] : cases) {
        std::vector<std::string> args{"compile", kDeferred.string(), "-o", (dir_ / "work" / "plan.txt").string()};
        if (flags != std::vector<std::string>{"--memory-svg"}) args.insert(args.end(), {"--memory-svg", svg});
        args.insert(args.end(), flags.begin(), flags.end());
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << flags[0] << ": " << r.err;
        EXPECT_NE(r.err.find(named), std::string::npos) << flags[0] << ": " << r.err;
        EXPECT_TRUE(workFiles().empty()) << flags[0];
    }
}

// A word or a fraction given for a number is named as such, not as a number out of range (a
// range check) or one that cannot be converted (none); a number out of range still says so.
TEST_F(Cli, AValueThatIsNotANumberIsSaidToBeNone) {
    const std::string plan = (dir_ / "work" / "plan.txt").string();
    std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"compile", "graphs/raster.json", "-o", plan, "--width", "abc"}, "error: --width: 'abc' is not a number\n"},
        {{"compile", "graphs/raster.json", "-o", plan, "--height", "1.5"},
         "error: --height: '1.5' is not a whole number in decimal digits\n"},
        {{"compile", "graphs/raster.json", "-o", plan, "--watch", "--watch-iterations", "many"},
         "error: --watch-iterations: 'many' is not a number\n"},
        {{"compile", "graphs/raster.json", "-o", plan, "--width", "0"},
         "error: --width: Value 0 not in range 1 to 16384"},
        // Decimal only: CLI11 alone reads "0x20" as 32 and " 64" as 64.
        {{"compile", "graphs/raster.json", "-o", plan, "--width", "0x20"}, "error: --width: '0x20' is not a number\n"},
        {{"compile", "graphs/raster.json", "-o", plan, "--width", " 64"}, "error: --width: ' 64' is not a number\n"},
        // A thousand, but not in the digits a count is written in.
        {{"compile", "graphs/raster.json", "-o", plan, "--width", "1e3"},
         "error: --width: '1e3' is not a whole number in decimal digits\n"},
    };
#if SKYGRAPH_CLI_HAS_RENDER
    cases.push_back({{"render", "--frames", "lots"}, "error: --frames: 'lots' is not a number\n"});
    cases.push_back({{"view", "--height", "tall"}, "error: --height: 'tall' is not a number\n"});
    cases.push_back({{"check", "graphs/raster.json", "--jobs", "all"}, "error: --jobs: 'all' is not a number\n"});
    cases.push_back({{"cubemap", "sky.hdr", "-o", (dir_ / "work" / "sky.ktx2").string(), "--samples", "many"},
                     "error: --samples: 'many' is not a number\n"});
    cases.push_back({{"sky-sequence", (dir_ / "work" / "sky%d.exr").string(), "--width", "wide"},
                     "error: --width: 'wide' is not a number\n"});
#endif
    for (const auto& [args, message] : cases) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << args[0] << " " << args.back() << ": " << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty()) << args[0] << " " << args.back();
    }
    // Leading zeros are decimal, not octal: 010 is ten.
    const CliRun padded = run({"compile", "graphs/raster.json", "--width", "032", "--height", "010"});
    EXPECT_EQ(padded.status, 0) << padded.err;
    EXPECT_NE(padded.out.find("32x10"), std::string::npos) << padded.out.substr(0, 300);
    EXPECT_EQ(padded.out.find("32x8"), std::string::npos) << padded.out.substr(0, 300);
}

TEST_F(Cli, UnwritableMemorySvgExitsOneAndWritesNothing) {
    const fs::path plan = dir_ / "work" / "plan.json";
    const fs::path missingDir = dir_ / "work" / "no_such_dir" / "memory.svg";
    const CliRun r = run({"compile", kDeferred.string(), "--memory-svg", missingDir.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("memory.svg"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");  // nor the plan: nothing is written
    EXPECT_TRUE(workFiles().empty());

    // A folder where the file should go: the temporary written beside it is removed again.
    fs::create_directories(dir_ / "work" / "taken.svg" / "inside");
    const CliRun taken = run({"compile", kDeferred.string(), "--memory-svg", (dir_ / "work" / "taken.svg").string(),
                              "-o", plan.string()});
    EXPECT_EQ(taken.status, 1) << taken.err;
    EXPECT_NE(taken.err.find("taken.svg"), std::string::npos) << taken.err;
    EXPECT_EQ(workFiles(), std::vector<std::string>{"taken.svg"});
    // And the other way round: the plan's -o is the folder, and the picture is not left behind.
    const CliRun planTaken = run({"compile", kDeferred.string(), "--memory-svg", (dir_ / "work" / "picture.svg").string(),
                                  "-o", (dir_ / "work" / "taken.svg").string()});
    EXPECT_EQ(planTaken.status, 1) << planTaken.err;
    EXPECT_NE(planTaken.err.find("taken.svg"), std::string::npos) << planTaken.err;
    EXPECT_EQ(workFiles(), std::vector<std::string>{"taken.svg"});

    // A graph that does not compile leaves an earlier picture as it was.
    const fs::path svg = dir_ / "work" / "memory.svg";
    std::ofstream(svg) << "earlier picture\n";
    const CliRun bad = run({"compile", writeGraph("bad.json", kBadGraph).string(), "--memory-svg", svg.string()});
    EXPECT_EQ(bad.status, 1);
    EXPECT_EQ(slurp(svg), "earlier picture\n");
}

TEST_F(Cli, DotShowsTheHeapsAndWhoTakesOverWhoseMemory) {
    const fs::path dot = dir_ / "work" / "plan.dot";
    const CliRun r = run({"compile", kDeferred.string(), "--format", "dot", "-o", dot.string()});
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string text = slurp(dot);
    EXPECT_NE(text.find("subgraph \"cluster_heap0\""), std::string::npos) << text;
    // hdr_scene takes over shadow_map's memory (text plan: "hdr_scene ... after shadow_map").
    EXPECT_NE(text.find("\"res:shadow_map\" -> \"res:hdr_scene\" [style=dashed, color=\"#7a5cc6\", fontcolor=\"#7a5cc6\", "
                        "label=\"memory\""),
              std::string::npos)
        << text;
    const auto plan = nlohmann::json::parse(run({"compile", kDeferred.string(), "--format", "json"}).out);
    size_t aliases = 0;
    for (const auto& p : plan["memory"]["placements"]) aliases += p["aliases"].size();
    size_t memoryEdges = 0;
    for (size_t at = text.find("label=\"memory\""); at != std::string::npos; at = text.find("label=\"memory\"", at + 1))
        ++memoryEdges;
    EXPECT_EQ(memoryEdges, aliases);
    if (std::system("command -v dot >/dev/null 2>&1") == 0) {  // graphviz reads it
        const std::string cmd = "dot -Tsvg " + quote(dot.string()) + " -o " + quote((dir_ / "dot.svg").string());
        EXPECT_EQ(std::system(cmd.c_str()), 0);
    }
}

// ---- Every subcommand documents itself; -v / -q; exit statuses across subcommands ----------

/// Subcommand names from `skygraph --help` ("Subcommands:" then one "  name  description" each),
/// so a subcommand added later is covered without editing this test.
std::vector<std::string> subcommandsFromHelp(const std::string& help) {
    std::vector<std::string> names;
    const auto at = help.find("Subcommands:");
    if (at == std::string::npos) return names;
    std::istringstream lines(help.substr(at));
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line) && line.rfind("  ", 0) == 0) {
        std::istringstream words(line);
        std::string name;
        words >> name;
        names.push_back(name);
    }
    return names;
}

// A resource that only culled passes use was declared once per such pass and without a label,
// so graphviz showed its id, "res:lonely", where every other resource shows its bare name.
TEST_F(Cli, DotDeclaresAResourceOnlyCulledPassesUseOnceUnderItsName) {
    const fs::path graph = writeGraph("orphan.json", R"({"version": 1, "name": "t", "features": {"f": true},
      "resources": {
        "img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
        "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true,
                "final": "TransferSrc"},
        "lonely": {"type": "buffer", "size": 16},
        "say \"hi\"": {"type": "buffer", "size": 16}},
      "passes": [
        {"name": "a", "type": "Generic", "uses": {"img": "Write@Compute"}},
        {"name": "b", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}},
        {"name": "orphan", "type": "Generic", "if": "!f", "uses": {"lonely": "Write@Compute"}},
        {"name": "culled", "type": "Generic", "uses": {"lonely": "Write@Compute", "say \"hi\"": "Write@Compute"}}]})");
    const CliRun r = run({"compile", graph.string(), "--format", "dot"});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto declarations = [&](const std::string& node) {  // statements of the node alone, not of an edge
        const std::string statement = "\n  " + node + " [";
        size_t n = 0;
        for (size_t at = r.out.find(statement); at != std::string::npos; at = r.out.find(statement, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(declarations("\"res:lonely\""), 1u) << r.out;
    EXPECT_NE(r.out.find("\"res:lonely\" [shape=ellipse, style=dashed, fontcolor=\"#888888\", label=\"lonely\"];"),
              std::string::npos) << r.out;
    EXPECT_EQ(declarations(R"("res:say \"hi\"")"), 1u) << r.out;
    EXPECT_NE(r.out.find(R"(label="say \"hi\""];)"), std::string::npos) << r.out;
    // Both culled passes still draw their edge to it.
    EXPECT_NE(r.out.find("\"pass:orphan\" -> \"res:lonely\""), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"pass:culled\" -> \"res:lonely\""), std::string::npos) << r.out;
}

TEST_F(Cli, EverySubcommandHasHelp) {
    const CliRun top = run({"--help"});
    ASSERT_EQ(top.status, 0) << top.err;
    const std::vector<std::string> names = subcommandsFromHelp(top.out);
    EXPECT_NE(std::find(names.begin(), names.end(), "compile"), names.end()) << top.out;
#if SKYGRAPH_CLI_HAS_RENDER
    EXPECT_NE(std::find(names.begin(), names.end(), "render"), names.end()) << top.out;
#endif
    for (const auto& name : names) {
        const CliRun r = run({name, "--help"});
        EXPECT_EQ(r.status, 0) << name << ": " << r.err;
        EXPECT_NE(r.out.find("Usage:"), std::string::npos) << name << ": " << r.out;
        EXPECT_NE(r.out.find("--help"), std::string::npos) << name << ": " << r.out;
        // A flag that turns a setting off reads as the plain flag, not CLI11's "--no-alias{false}".
        EXPECT_EQ(r.out.find("{false}"), std::string::npos) << name << ": " << r.out;
        EXPECT_EQ(r.err, "") << name;
    }
}

TEST_F(Cli, VerboseLogsDebugToStderrAndLeavesThePlanAlone) {
    const CliRun plain = run({"compile", "graphs/pathtrace.json"});
    ASSERT_EQ(plain.status, 0) << plain.err;
    EXPECT_EQ(plain.err, "");
    for (const auto& args : std::vector<std::vector<std::string>>{{"-v", "compile", "graphs/pathtrace.json"},
                                                                  {"compile", "graphs/pathtrace.json", "-v"}}) {
        const CliRun verbose = run(args);
        ASSERT_EQ(verbose.status, 0) << verbose.err;
        EXPECT_EQ(verbose.out, plain.out);  // logs never go to stdout, where plans go
        EXPECT_NE(verbose.err.find("debug: graphs/pathtrace.json: "), std::string::npos) << verbose.err;
        EXPECT_NE(verbose.err.find(" passes run, "), std::string::npos) << verbose.err;
    }
}

TEST_F(Cli, MisuseOfAnySubcommandExitsTwo) {
    std::vector<std::vector<std::string>> cases{
        {"--progress", "sometimes", "compile", "graphs/raster.json"},
        {"compile", "graphs/raster.json", "--watch", "--watch-interval-ms", "1"},
        {"compile", "graphs/raster.json", "--watch-iterations", "many"},
        {"run", "graphs/raster.json"},
    };
#if SKYGRAPH_CLI_HAS_RENDER
    cases.push_back({"render", "--width", "0"});
    cases.push_back({"render", "--frames", "lots"});
    cases.push_back({"render", "--feature", "skybox"});
    cases.push_back({"render", "a.json", "b.json"});
    // Empty names would silently mean the default (skygraph.png, the first device).
    cases.push_back({"render", "-o", ""});
    cases.push_back({"render", "--device", ""});
    cases.push_back({"render", "--readback", ""});
    cases.push_back({"compile", "graphs/raster.json", "-o", ""});
#endif
    for (const auto& args : cases) {
        std::string shown;
        for (const auto& a : args) shown += a + " ";
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << shown << "\nstderr: " << r.err;
        EXPECT_NE(r.err, "") << shown;
        EXPECT_TRUE(workFiles().empty()) << shown;
    }
}

TEST_F(Cli, AnUnknownCommandIsNamedWithTheCommandsThereAre) {
    const CliRun r = run({"run", "graphs/raster.json"});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("error: unknown command 'run'; commands: compile"), std::string::npos) << r.err;
}

#if SKYGRAPH_CLI_HAS_RENDER
TEST_F(Cli, RenderUserErrorsExitOneAndWriteNothing) {
    const fs::path graph = writeGraph("bad.json", kBadGraph);
    const std::string out = (dir_ / "work" / "out.png").string();
    fs::create_directories(dir_ / "folder.png");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"render", graph.string(), "-o", out}, "error: " + graph.string() + ": passes[0].params.operator"},
        {{"render", (dir_ / "nope.json").string(), "-o", out}, "nope.json"},
        {{"render", "graphs/raster.json", "--feature", "nosuch=on", "-o", out}, "unknown feature 'nosuch'"},
        {{"render", "graphs/raster.json", "-o", (dir_ / "work" / "out.jpg").string()},
         "its extension must be .png, .hdr or .exr"},
        {{"render", graph.string(), "-o", graph.string()}, "its extension must be"},
        {{"render", "graphs/raster.json", "-o", (dir_ / "work" / "frame").string()},
         "its extension must be .png, .hdr or .exr, or --format must say which"},
        {{"render", "graphs/raster.json", "-o", out, "--format", "exr"},
         "-o '" + out + "' names a .png file but --format is exr"},
        {{"render", "graphs/raster.json", "-o", (dir_ / "work" / "out.jpg").string(), "--format", "png"},
         "names a .jpg file but --format is png"},
        {{"render", "graphs/raster.json", "-o", (dir_ / "work" / "missing" / "out.png").string()},
         "the folder '" + (dir_ / "work" / "missing").string() + "' does not exist"},
        {{"render", "graphs/raster.json", "-o", (dir_ / "folder.png").string()},
         "cannot write '" + (dir_ / "folder.png").string() + "': it is a folder"},
    };
    for (const auto& [args, message] : cases) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 1) << args[1] << ": " << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty()) << args[1];
    }
}

// An environment of a NaN would spread through every filtered product and light the whole
// frame with it (a black frame and exit 0, before): refused, named where the scene names it.
TEST_F(Cli, RenderRefusesAnEnvironmentThatIsNotFinite) {
    skygraph::HdrImage sky{8, 4, std::vector<float>(8 * 4 * 4, 1.0f)};
    sky.rgba[5] = std::numeric_limits<float>::quiet_NaN();
    const fs::path exr = dir_ / "nan.exr";
    skygraph::saveExr(exr, sky);
    const fs::path scene = writeGraph("scene.json", R"({
      "camera": { "position": [0.0, 1.7, 0.0], "fov_y_deg": 70.0, "near": 0.1 },
      "environment": { "file": "nan.exr", "sampling": "cubemap" }, "objects": [] })");
    const CliRun r = run({"render", "--scene", scene.string(), "--width", "16", "--height", "16", "-o",
                          (dir_ / "work" / "out.png").string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("error: " + scene.string() + ": environment.file: '" + exr.string() +
                         "': 1 pixel values are NaN or infinite"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(workFiles().empty());
}

// A frame graph whose environment inputs disagree with what the environment pipeline bakes or
// the scene's file gives is refused naming the graph's declaration: a cube of one level where
// graphs/ibl.json bakes a chain, and an equirect declared as a buffer.
TEST_F(Cli, RenderNamesTheDeclarationOfAnEnvironmentInputThatDisagrees) {
    const skygraph::HdrImage sky{16, 8, std::vector<float>(16 * 8 * 4, 0.5f)};
    skygraph::saveExr(dir_ / "sky.exr", sky);
    const fs::path scene = writeGraph("scene.json", R"({
      "camera": { "position": [0.0, 1.7, 0.0], "fov_y_deg": 70.0, "near": 0.1 },
      "environment": { "file": "sky.exr" }, "objects": [] })");
    const std::string out = R"("out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8],
                                        "external": true, "final": "TransferSrc" })";
    const fs::path cube = writeGraph("cube.json", R"({ "version": 1, "name": "cube", "resources": { )" + out + R"(,
        "environment": { "type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [8, 8], "external": true,
                         "initial": "ShaderRead" } },
      "passes": [ { "name": "p", "type": "Generic", "uses": { "out": "Write@ColorAttachment",
                                                             "environment": "Read@Fragment" } } ] })");
    const fs::path buffer = writeGraph("buffer.json", R"({ "version": 1, "name": "buffer", "resources": { )" + out +
                                                          R"(,
        "equirect": { "type": "buffer", "size": 16, "external": true, "initial": "ShaderRead" } },
      "passes": [ { "name": "p", "type": "Generic", "uses": { "out": "Write@ColorAttachment",
                                                             "equirect": "Read@Compute" } } ] })");
    const fs::path procedural = fs::path(SKYGRAPH_SOURCE_DIR) / "scenes/default.json";
    fs::copy_file(fs::path(SKYGRAPH_SOURCE_DIR) / "graphs/ibl.json", dir_ / "ibl.json");  // the environment graph
    const std::vector<std::tuple<fs::path, fs::path, std::string>> cases = {
        {cube, procedural, "resources.environment: importImage: resource 'environment' from graph 'ibl'"},
        {buffer, scene, "resources.equirect: setExternalImage: 'equirect' is a buffer, not an external image"},
    };
    for (const auto& [graph, sceneFile, expected] : cases) {
        const CliRun r = run({"render", graph.string(), "--scene", sceneFile.string(), "--readback", "out", "--width",
                              "8", "--height", "8", "-o", (dir_ / "work" / "out.png").string()});
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find("error: " + graph.string() + ": " + expected), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty());
    }
}

// What the device refuses is named in the graph: a format it cannot make with the plan's
// usages at the resource's declaration, and all the resources together past the memory cap at
// the graph's file.
TEST_F(Cli, RenderNamesTheGraphOfWhatTheDeviceRefuses) {
    const fs::path e5 = writeGraph("e5.json", R"({ "version": 1, "name": "e5", "resources": {
        "x": { "type": "image2d", "format": "E5B9G9R9_UFLOAT_PACK32", "extent": [16, 16] },
        "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16], "external": true,
                 "final": "TransferSrc" } },
      "passes": [ { "name": "w", "type": "Generic", "uses": { "x": "Write@ColorAttachment" } },
                  { "name": "r", "type": "Generic", "uses": { "x": "Read@Fragment", "out": "Write@ColorAttachment" } } ] })");
    const fs::path raster = fs::path(SKYGRAPH_SOURCE_DIR) / "graphs/raster.json";
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"render", e5.string(), "--readback", "out"},
         "error: " + e5.string() + ": resources.x: resource 'x': the device cannot create a E5B9G9R9_UFLOAT_PACK32 "
                                   "image of 16x16 with the usages the plan needs ("},
        {{"render", raster.string(), "--width", "8192", "--height", "8192"},
         "error: " + raster.string() + ": the plan's resources need "},
    };
    for (auto [args, expected] : cases) {
        args.insert(args.end(), {"-o", (dir_ / "work" / "out.png").string()});
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty());
    }
}

// -o naming a file the render reads is refused before anything is rendered: the environment
// file and a sequence's later frames are inputs as much as the graph and the scene are.
TEST_F(Cli, RenderRefusesToWriteOverItsEnvironmentFiles) {
    const skygraph::HdrImage sky{8, 4, std::vector<float>(8 * 4 * 4, 0.5f)};
    fs::create_directories(dir_ / "frames");
    for (const char* name : {"sky.exr", "frames/sky_000.exr", "frames/sky_001.exr", "frames/sky_002.exr"})
        skygraph::saveExr(dir_ / name, sky);
    const fs::path fileScene = writeGraph("file_scene.json", R"({
      "camera": { "position": [0.0, 1.7, 0.0], "fov_y_deg": 70.0, "near": 0.1 },
      "environment": { "file": "sky.exr" }, "objects": [] })");
    const fs::path sequenceScene = writeGraph("sequence_scene.json", R"({
      "camera": { "position": [0.0, 1.7, 0.0], "fov_y_deg": 70.0, "near": 0.1 },
      "environment": { "sequence": "frames/sky_%03d.exr" }, "objects": [] })");
    const std::vector<std::pair<fs::path, fs::path>> cases = {
        {fileScene, dir_ / "sky.exr"},
        {sequenceScene, dir_ / "frames" / "sky_000.exr"},
        {sequenceScene, dir_ / "frames" / "sky_002.exr"},
    };
    for (const auto& [scene, input] : cases) {
        const auto before = fs::last_write_time(input);
        const CliRun r = run({"render", "--scene", scene.string(), "--width", "8", "--height", "8", "-o",
                              input.string()});
        EXPECT_EQ(r.status, 1) << input << r.err;
        EXPECT_NE(r.err.find("-o '" + input.string() + "' is the input '"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("it would be overwritten"), std::string::npos) << r.err;
        EXPECT_EQ(fs::last_write_time(input), before) << input;
        EXPECT_EQ(skygraph::loadExr(input).rgba, sky.rgba) << input;
    }
}

// The plan and the memory picture named as one file: the plan, written second, would replace
// the picture, which exited 0.
TEST_F(Cli, CompileRefusesOneFileForThePlanAndThePicture) {
    const fs::path out = dir_ / "work" / "both.out";
    for (const fs::path& svg : {out, dir_ / "work" / "." / "both.out"}) {
        const CliRun r = run({"compile", "graphs/raster.json", "-o", out.string(), "--memory-svg", svg.string()});
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find("-o and --memory-svg both name '" + out.string() + "'"), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty());
    }
    // Relative names of a file not there yet, from the folder it would be written in: one
    // with a part that exists ("."), one without any.
    const CliRun r = run({"compile", (kSource / "graphs" / "raster.json").string(), "-o", "both.out", "--memory-svg",
                          "./both.out"},
                         "cd " + quote((dir_ / "work").string()) + " && ");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("-o and --memory-svg both name 'both.out'"), std::string::npos) << r.err;
    EXPECT_TRUE(workFiles().empty());
}

// A symbolic link to the other output's name, made before either file is there: a write through
// it lands on the other output, though no existing file is under two names yet.
TEST_F(Cli, CompileRefusesALinkFromOneOutputToTheOther) {
    const fs::path work = dir_ / "work";
    fs::create_symlink("picture.svg", work / "plan_link.txt");   // one link, relative
    fs::create_symlink(work / "plan_link.txt", work / "chain.svg");  // two links, the first absolute
    struct Outputs {
        fs::path plan, picture;
    };
    for (const auto& [plan, picture] : {Outputs{work / "plan_link.txt", work / "picture.svg"},
                                        Outputs{work / "picture.svg", work / "plan_link.txt"},
                                        Outputs{work / "chain.svg", work / "picture.svg"}}) {
        const CliRun r = run({"compile", "graphs/pathtrace.json", "-o", plan.string(), "--memory-svg", picture.string()});
        EXPECT_EQ(r.status, 1) << plan << " " << picture << ": " << r.err;
        EXPECT_NE(r.err.find("-o and --memory-svg both name '" + plan.string() + "'"), std::string::npos) << r.err;
        std::vector<std::string> files = workFiles();
        std::sort(files.begin(), files.end());
        EXPECT_EQ(files, (std::vector<std::string>{"chain.svg", "plan_link.txt"})) << "nothing written";
    }
}

// --memory-svg naming standard output while the plan is printed there: the picture went first,
// and the plan after it (a pipe) or over it from the file's start (a redirection to a file),
// which exited 0.
TEST_F(Cli, CompileRefusesStandardOutputForThePictureWhileThePlanIsPrintedThere) {
    std::ofstream(dir_ / "stdout").flush();  // there before the run, for a hard link to it
    fs::create_hard_link(dir_ / "stdout", dir_ / "another_name.svg");
    for (const std::string& picture : {std::string("/dev/stdout"), std::string("/proc/self/fd/1"),
                                       (dir_ / "stdout").string(), (dir_ / "another_name.svg").string()})
        for (const char* format : {"text", "dot"}) {
            const CliRun r = run({"compile", "graphs/async.json", "--format", format, "--memory-svg", picture});
            EXPECT_EQ(r.status, 1) << picture << " " << format << ": " << r.err;
            EXPECT_NE(r.err.find("--memory-svg '" + picture + "' is standard output, where the plan is printed"),
                      std::string::npos) << r.err;
            EXPECT_EQ(r.out, "") << picture << " " << format << ": nothing written";
        }
    const std::string piped = "cd " + quote(kSource.string()) + " && { " + quote(kCli.string()) +
                              " compile graphs/raster.json --memory-svg /dev/stdout 2>/dev/null; echo $? >" +
                              quote((dir_ / "status").string()) + "; } | cat >" + quote((dir_ / "piped").string());
    ASSERT_EQ(std::system(piped.c_str()), 0);
    EXPECT_EQ(slurp(dir_ / "status"), "1\n");
    EXPECT_EQ(slurp(dir_ / "piped"), "");
    // A device is no file to read back: /dev/null takes the picture and the plan alike.
    const std::string discarded = "cd " + quote(kSource.string()) + " && " + quote(kCli.string()) +
                                  " compile graphs/raster.json --memory-svg /dev/null >/dev/null";
    EXPECT_EQ(std::system(discarded.c_str()), 0);
    // Another file for the picture, or the plan to a file and the picture to standard output.
    const fs::path svg = dir_ / "work" / "picture.svg";
    const CliRun apart = run({"compile", "graphs/raster.json", "--memory-svg", svg.string()});
    EXPECT_EQ(apart.status, 0) << apart.err;
    EXPECT_EQ(apart.out.find("<svg"), std::string::npos) << apart.out;
    EXPECT_NE(slurp(svg).find("</svg>"), std::string::npos);
    const fs::path plan = dir_ / "work" / "plan.txt";
    const CliRun swapped = run({"compile", "graphs/raster.json", "-o", plan.string(), "--memory-svg", "/dev/stdout"});
    EXPECT_EQ(swapped.status, 0) << swapped.err;
    EXPECT_NE(swapped.out.find("</svg>"), std::string::npos) << swapped.out;
    EXPECT_EQ(slurp(plan), run({"compile", "graphs/raster.json"}).out);
}

// An environment image that cannot be read is named with the scene key that names it.
TEST_F(Cli, RenderNamesTheSceneKeyOfAnUnreadableEnvironment) {
    fs::create_directories(dir_ / "frames");
    for (const char* name : {"sky.hdr", "frames/sky_000.hdr", "frames/sky_001.hdr"})
        std::ofstream(dir_ / name) << "#?RADIANCE\n";  // a header and nothing after it
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"("file": "sky.hdr")", "environment.file: '" + (dir_ / "sky.hdr").string() + "'"},
        {R"("sequence": "frames/sky_%03d.hdr")",
         "environment.sequence: '" + (dir_ / "frames" / "sky_000.hdr").string() + "'"},
    };
    for (const auto& [environment, shown] : cases) {
        const fs::path scene = writeGraph("scene.json", R"({ "camera": { "position": [0, 1, 4] },
          "environment": { )" + environment + R"( }, "objects": [] })");
        const CliRun r = run({"render", "--scene", scene.string(), "--width", "8", "--height", "8", "-o",
                              (dir_ / "work" / "out.png").string()});
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_NE(r.err.find(scene.string() + ": " + shown), std::string::npos) << r.err;
        EXPECT_TRUE(workFiles().empty());
    }
}

// `render -o PIPE`: the image goes to the FIFO's reader whole, a PNG or an EXR (whose writer
// seeks, so it is written to a temporary first); the FIFO stays.
TEST_F(Cli, RenderWritesItsImageIntoAFifo) {
    for (const std::string name : {"frames.png", "frames.exr"}) {
        SCOPED_TRACE(name);
        const fs::path fifo = dir_ / "work" / name;
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        // Our own end, read and write, so that neither side waits for the other: an image of
        // 8x6 pixels fits the pipe's buffer, and a render that replaced the FIFO leaves it empty.
        const int end = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK);
        ASSERT_GE(end, 0);
        const CliRun r = run({"render", "--width", "8", "--height", "6", "-o", fifo.string()});
        std::string image;
        char chunk[4096];
        for (ssize_t n; (n = ::read(end, chunk, sizeof chunk)) > 0;) image.append(chunk, size_t(n));
        ::close(end);
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
        if (name == "frames.exr") {
            // Read back as a file: the bytes are the whole EXR.
            const fs::path copy = dir_ / "copy.exr";
            std::ofstream(copy, std::ios::binary) << image;
            const skygraph::HdrImage exr = skygraph::loadExr(copy);
            EXPECT_EQ(exr.width, 8u);
            EXPECT_EQ(exr.height, 6u);
            continue;
        }
        ASSERT_GE(image.size(), 24u);
        EXPECT_EQ(image.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
        const auto bigEndian = [&](size_t at) {
            return uint32_t(uint8_t(image[at])) << 24 | uint32_t(uint8_t(image[at + 1])) << 16 |
                   uint32_t(uint8_t(image[at + 2])) << 8 | uint32_t(uint8_t(image[at + 3]));
        };
        EXPECT_EQ(bigEndian(16), 8u);  // IHDR's width and height
        EXPECT_EQ(bigEndian(20), 6u);
    }
    std::vector<std::string> left = workFiles();
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"frames.exr", "frames.png"}));
}

// An output that is one of the command's inputs is refused before anything is written: the
// graph for compile and check, the equirect for cubemap, and for render a file a scene's glTF
// model reads (its texture).
TEST_F(Cli, OutputsThatNameAnInputAreRefused) {
    const fs::path graph = dir_ / "graph.json";
    fs::copy_file(kSource / "graphs/raster.json", graph);
    const std::string before = slurp(graph);
    const fs::path model = dir_ / "box";
    fs::copy(fs::path("/usr/share/assimp/models/glTF2/BoxTextured-glTF"), model);
    const fs::path texture = model / "CesiumLogoFlat.png";
    const std::string textureBytes = slurp(texture);
    const fs::path scene = writeGraph("scene.json", R"({"camera": {"position": [0, 1, 4]}, "environment": null,
      "objects": [{"type": "gltf", "file": "box/BoxTextured.gltf"}]})");
    const fs::path sky = dir_ / "sky.hdr";
    skygraph::saveRadianceHdr(sky, skygraph::HdrImage{8, 4, std::vector<float>(8 * 4 * 4, 0.5f)});
    const std::string skyBytes = slurp(sky);
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"compile", graph.string(), "-o", graph.string()}, "-o '" + graph.string() + "' is the input"},
        {{"compile", graph.string(), "--memory-svg", graph.string()}, "--memory-svg '" + graph.string() + "' is the input"},
        {{"check", graph.string(), "--no-run", "--junit", graph.string()}, "--junit '" + graph.string() + "' is the input"},
        {{"cubemap", sky.string(), "-o", (dir_ / "work" / "cube.ktx2").string(), "--cross", sky.string()},
         "an output '" + sky.string() + "' is the input"},
        {{"render", "--scene", scene.string(), "--width", "8", "--height", "8", "-o", texture.string()},
         "-o '" + texture.string() + "' is the input '" + texture.string() + "'"},
    };
    for (const auto& [args, message] : cases) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 1) << args[0] << ": " << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    }
    EXPECT_EQ(slurp(graph), before);
    EXPECT_EQ(slurp(texture), textureBytes);
    EXPECT_EQ(slurp(sky), skyBytes);
    EXPECT_TRUE(workFiles().empty());
    for (const std::vector<std::string>& args : {std::vector<std::string>{"compile", ""}, {"check", ""},
                                                {"view", ""}, {"view", "--scene", ""}, {"cubemap", sky.string(), "-o", ""}}) {
        const CliRun r = run(args);
        EXPECT_EQ(r.status, 2) << args[0] << " with an empty name: " << r.err;
    }
}

// Names in scene and glTF files may hold control characters (a glTF file's names are free
// text; Linux file names take any byte but '/'): the scene renders, and what `render` prints
// about them (the scene's lines, the environment's, an input that -o would overwrite) shows
// them escaped as JSON writes them, so that none rings the terminal or breaks a line.
TEST_F(Cli, RenderShowsControlCharactersInSceneAndGltfNamesEscaped) {
    const fs::path box = fs::path("/usr/share/assimp/models/glTF2/BoxTextured-glTF");
    fs::create_directories(dir_ / "box");
    fs::copy_file(box / "BoxTextured0.bin", dir_ / "box" / "BoxTextured0.bin");
    fs::copy_file(box / "CesiumLogoFlat.png", dir_ / "box" / "logo\a.png");
    nlohmann::json gltf = nlohmann::json::parse(slurp(box / "BoxTextured.gltf"));
    gltf["nodes"][1]["name"] = "node\a";
    gltf["meshes"][0]["name"] = "mesh\n";
    gltf["materials"][0]["name"] = "\x1b[31mmaterial";
    gltf["images"][0]["uri"] = "logo\a.png";
    std::ofstream(dir_ / "box" / "box.gltf") << gltf.dump();
    skygraph::saveExr(dir_ / "sky\a.exr", skygraph::HdrImage{8, 4, std::vector<float>(8 * 4 * 4, 0.5f)});
    const fs::path scene = writeGraph("scene.json", R"({"camera": {"position": [0, 1, 4]},
      "environment": {"file": "sky\u0007.exr"}, "objects": [{"type": "gltf", "file": "box/box.gltf"}]})");
    const auto controlCharacters = [](const std::string& text) {
        return std::count_if(text.begin(), text.end(), [](char c) {
            return c != '\n' && (static_cast<unsigned char>(c) < 0x20 || c == 0x7f);
        });
    };

    const CliRun r = run({"render", "--scene", scene.string(), "--width", "8", "--height", "8", "-o",
                          (dir_ / "work" / "out.png").string()});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("environment is '" + dir_.string() + "/sky\\u0007.exr'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("environment: " + dir_.string() + "/sky\\u0007.exr ("), std::string::npos) << r.err;
    EXPECT_EQ(controlCharacters(r.err), 0) << r.err;

    const fs::path texture = dir_ / "box" / "logo\a.png";
    const std::string shown = dir_.string() + "/box/logo\\u0007.png";
    const CliRun refused = run({"render", "--scene", scene.string(), "--width", "8", "--height", "8", "-o",
                                texture.string()});
    EXPECT_EQ(refused.status, 1) << refused.err;
    EXPECT_NE(refused.err.find("-o '" + shown + "' is the input '" + shown + "'"), std::string::npos) << refused.err;
    EXPECT_EQ(controlCharacters(refused.err), 0) << refused.err;
    EXPECT_EQ(slurp(texture), slurp(box / "CesiumLogoFlat.png"));
}

// The log says what sets each scene feature: the scene, or a --feature that overrules it.
TEST_F(Cli, RenderSaysWhichFeaturesTheCommandLineOverrules) {
    const CliRun r = run({"render", "--width", "8", "--height", "8", "--feature", "geometry=off", "--feature",
                          "skybox=on", "-o", (dir_ / "out.png").string()});
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("scene: geometry = on: the scene has"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("feature geometry = off: --feature overrules the scene's on"), std::string::npos) << r.err;
    // skybox=on agrees with the scene: nothing to say.
    EXPECT_EQ(r.err.find("feature skybox = on: --feature overrules"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("skybox = on, environment_file = off, sample_cubemap = off: environment is the procedural "
                         "sky, evaluated per pixel"),
              std::string::npos)
        << r.err;
}

// `render -o /dev/stdout --format F` writes the image to standard output (logs go to stderr),
// and --format names the format of a file whose name says none.
TEST_F(Cli, RenderWritesTheFormatItIsToldToStandardOutput) {
    const CliRun png = run({"render", "--width", "8", "--height", "6", "-o", "/dev/stdout", "--format", "png"});
    EXPECT_EQ(png.status, 0) << png.err;
    ASSERT_GE(png.out.size(), 24u);
    EXPECT_EQ(png.out.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    const CliRun exr = run({"render", "--width", "8", "--height", "6", "-o", "/dev/stdout", "--format", "exr"});
    EXPECT_EQ(exr.status, 0) << exr.err;
    const fs::path copy = dir_ / "copy.exr";
    std::ofstream(copy, std::ios::binary) << exr.out;
    const skygraph::HdrImage image = skygraph::loadExr(copy);
    EXPECT_EQ(image.width, 8u);
    EXPECT_EQ(image.height, 6u);
    const fs::path frame = dir_ / "work" / "frame";
    const CliRun hdr = run({"render", "--width", "8", "--height", "6", "-o", frame.string(), "--format", "hdr"});
    EXPECT_EQ(hdr.status, 0) << hdr.err;
    EXPECT_TRUE(slurp(frame).starts_with("#?RADIANCE")) << slurp(frame).substr(0, 16);
    const CliRun unknown = run({"render", "-o", "/dev/stdout", "--format", "jpg"});
    EXPECT_EQ(unknown.status, 2) << unknown.err;
    EXPECT_NE(unknown.err.find("--format"), std::string::npos) << unknown.err;
    EXPECT_EQ(unknown.out, "");
}

// The presented image holds sRGB-encoded values, which a PNG keeps; .hdr and .exr hold linear
// ones, so `render` decodes it for them (it wrote the encoded values, byte/255, which a viewer
// then encoded again).
TEST_F(Cli, RenderWritesThePresentedImageToHdrAndExrAsLinearValues) {
    const fs::path png = dir_ / "work" / "f.png", exr = dir_ / "work" / "f.exr", hdr = dir_ / "work" / "f.hdr";
    for (const fs::path& out : {png, exr, hdr}) {
        const CliRun r = run({"render", "--width", "8", "--height", "6", "-o", out.string()});
        ASSERT_EQ(r.status, 0) << r.err;
    }
    const std::string bytes = slurp(png);
    int w = 0, h = 0, n = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> encoded(
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &n, 4),
        stbi_image_free);
    ASSERT_TRUE(encoded) << stbi_failure_reason();
    ASSERT_EQ(w, 8);
    ASSERT_EQ(h, 6);
    const skygraph::HdrImage fromExr = skygraph::loadExr(exr), fromHdr = skygraph::loadRadianceHdr(hdr);
    size_t midTones = 0;
    for (size_t i = 0; i < size_t(w) * size_t(h) * 4; ++i) {
        if (i % 4 == 3) continue;
        const float byte = float(encoded.get()[i]) / 255.0f, linear = skygraph::math::srgbDecode(byte);
        midTones += std::abs(linear - byte) > 0.05f;
        EXPECT_NEAR(fromExr.rgba[i], linear, 1e-3f) << "value " << i << ", PNG byte " << int(encoded.get()[i]);
        EXPECT_NEAR(fromHdr.rgba[i], linear, 0.01f) << "value " << i << ", PNG byte " << int(encoded.get()[i]);
    }
    EXPECT_GT(midTones, 0u) << "the frame has values that decoding changes";
}

// A bounded plane whose extent holds the square an infinite one is drawn as, around the
// camera, draws as the infinite plane: drawn at its own size (1e9) lavapipe lost it and the
// frame showed only the sky. A smaller one draws as itself.
TEST_F(Cli, AVastBoundedPlaneRendersAsTheInfiniteOne) {
    const auto render = [&](const std::string& halfExtent) {
        const fs::path scene = dir_ / "work" / "plane.json", out = dir_ / "work" / "plane.png";
        std::ofstream(scene) << R"({"objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0])" +
                                    (halfExtent.empty() ? "" : ", \"half_extent\": " + halfExtent) + "}]}";
        const CliRun r = run({"render", "--scene", scene.string(), "--width", "32", "--height", "24", "-o", out.string()});
        EXPECT_EQ(r.status, 0) << r.err;
        return slurp(out);
    };
    const std::string infinite = render("");
    EXPECT_TRUE(render("1e9") == infinite);
    EXPECT_TRUE(render("1e6") == infinite);
    EXPECT_FALSE(render("2") == infinite) << "a plane 4 wide under the camera leaves sky below the horizon";
}

// A PNG that cannot be written (a folder where it would go) is refused before the render,
// leaves no temporary behind, and never touches a file of a temporary's old name.
TEST_F(Cli, RenderThatCannotWriteItsPngLeavesNothingBehind) {
    fs::create_directories(dir_ / "work" / "out.png");  // a directory where the file would go
    std::ofstream(dir_ / "work" / "out.png.tmp") << "precious";
    const CliRun r = run({"render", "--width", "8", "--height", "8", "-o", (dir_ / "work" / "out.png").string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("cannot write '" + (dir_ / "work" / "out.png").string() + "': it is a folder"),
              std::string::npos)
        << r.err;
    std::vector<std::string> left = workFiles();
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"out.png", "out.png.tmp"}));
    EXPECT_EQ(slurp(dir_ / "work" / "out.png.tmp"), "precious");
}

// A graph without a Present image: a compute-only bake writes nothing unless asked, and then
// only an image it names.
const char* kComputeOnlyGraph = R"({
  "version": 1, "name": "bake",
  "resources": {
    "field": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16],
               "external": true, "final": "ShaderRead" },
    "table": { "type": "buffer", "size": 256, "external": true, "final": "ShaderRead" }
  },
  "passes": [ { "name": "bake", "type": "Generic", "uses": { "field": "Write@Compute", "table": "Write@Compute" } } ]
})";

TEST_F(Cli, RenderOfAGraphWithoutAPresentImageRendersValidatesAndExitsZero) {
    const fs::path graph = writeGraph("bake.json", kComputeOnlyGraph);
    const CliRun r = run({"render", graph.string(), "--frames", "2", "--validate"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("graph 'bake' has no Present image that a pass uses: no file is written"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("wrote"), std::string::npos) << r.err;

    const fs::path out = dir_ / "work" / "field.exr";
    const CliRun named = run({"render", graph.string(), "--frames", "2", "--validate", "--readback", "field",
                              "-o", out.string()});
    ASSERT_EQ(named.status, 0) << named.err;
    EXPECT_TRUE(fs::exists(out));
}

// An output of the graph that no pass of the chosen features writes holds only the
// placeholder it arrives with: reading it back is refused, naming the images passes write.
TEST_F(Cli, RenderRefusesToReadBackAnOutputNoPassWrites) {
    const fs::path graph = writeGraph("switch.json", R"({
      "version": 1, "name": "switch", "features": { "compute": false },
      "resources": {
        "field": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16],
                   "external": true, "final": "ShaderRead" },
        "other": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16],
                   "external": true, "final": "ShaderRead" }
      },
      "passes": [ { "name": "a", "type": "Generic", "if": "compute", "uses": { "field": "Write@Compute" } },
                  { "name": "b", "type": "Generic", "uses": { "other": "Write@Compute" } } ]
    })");
    const fs::path out = dir_ / "work" / "out.exr";
    const CliRun r = run({"render", graph.string(), "--readback", "field", "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find(graph.string() + ": cannot read back 'field': it is an output of the graph, and no pass that "
                         "runs with these features writes it; the images its passes write: other"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(workFiles().empty());
    const CliRun on = run({"render", graph.string(), "--feature", "compute=on", "--readback", "field", "-o", out.string()});
    EXPECT_EQ(on.status, 0) << on.err;
    EXPECT_TRUE(fs::exists(out));
}

// The executor reads back only the formats it converts to floats; another is refused before
// any frame, named in the graph file at the resource's declaration.
TEST_F(Cli, RenderNamesTheGraphFileOfAReadBackOfAFormatItCannotWrite) {
    const fs::path graph = writeGraph("counts.json", R"({
      "version": 1, "name": "counts",
      "resources": {
        "counts": { "type": "image2d", "format": "R32_UINT", "extent": [16, 16],
                    "external": true, "final": "ShaderRead" }
      },
      "passes": [ { "name": "count", "type": "Generic", "uses": { "counts": "Write@Compute" } } ]
    })");
    const fs::path out = dir_ / "work" / "counts.exr";
    const CliRun r = run({"render", graph.string(), "--readback", "counts", "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("error: " + graph.string() + ": resources.counts: resource 'counts': cannot read back "
                         "'counts': its format R32_UINT is not supported for read-back"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(workFiles().empty());
}

// The name came from the command line, not the graph file: it was reported at the file's
// `resources`, as if the file had named it there.
TEST_F(Cli, RenderNamesTheReadbackOptionOfAResourceTheGraphLacks) {
    const fs::path graph = kSource / "graphs/raster.json";
    const fs::path out = dir_ / "work" / "out.exr";
    const CliRun r = run({"render", graph.string(), "--readback", "NONE", "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("skygraph render: " + graph.string() + ": cannot read back 'NONE' (--readback): the graph "
                         "has no resource of that name; the images its passes write: "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("hdr_color"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("resources"), std::string::npos) << r.err;
    EXPECT_TRUE(workFiles().empty());
}

TEST_F(Cli, RenderWithAnOutputButNothingToWriteSaysWhatToNameAndWritesNothing) {
    const fs::path graph = writeGraph("bake.json", kComputeOnlyGraph);
    const fs::path out = dir_ / "work" / "out.png";
    const CliRun r = run({"render", graph.string(), "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("skygraph render: " + graph.string() + ": nothing to write to -o '" + out.string() +
                         "': the graph has no Present image that a pass uses; add --readback NAME with one of the "
                         "images its passes write: field"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(workFiles().empty());
    const CliRun buffer = run({"render", graph.string(), "--readback", "table", "-o", out.string()});
    EXPECT_EQ(buffer.status, 1) << buffer.err;
    EXPECT_NE(buffer.err.find("cannot read back 'table': it is a buffer"), std::string::npos) << buffer.err;
    EXPECT_TRUE(workFiles().empty());
    // An existing folder as -o: said so, not that its name lacks an extension.
    const CliRun folder = run({"render", graph.string(), "--readback", "field", "-o", (dir_ / "work").string()});
    EXPECT_EQ(folder.status, 1) << folder.err;
    EXPECT_NE(folder.err.find("cannot write '" + (dir_ / "work").string() + "': it is a folder"), std::string::npos)
        << folder.err;
    EXPECT_TRUE(workFiles().empty());
}

// The built-in graph and scene on lavapipe under validation; the bar counts frames when asked
// for, and stays out of logs (stderr is a file here) when not.
TEST_F(Cli, RenderDrawsAProgressBarOnlyWhenAskedOrOnATerminal) {
    const fs::path out = dir_ / "work" / "out.png";
    const CliRun withBar = run({"--progress", "always", "render", "--width", "16", "--height", "16", "--frames",
                                "4", "--validate", "-o", out.string()});
    ASSERT_EQ(withBar.status, 0) << withBar.err;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_NE(withBar.err.find("render [##############################] 4/4 frames"), std::string::npos)
        << withBar.err;
    EXPECT_NE(withBar.err.find("info: wrote "), std::string::npos) << withBar.err;

    const CliRun quiet = run({"render", "--width", "16", "--height", "16", "--frames", "2", "-q", "--validate",
                              "-o", out.string()});
    ASSERT_EQ(quiet.status, 0) << quiet.err;
    // No bar (stderr is not a terminal) and no info lines (-q); lavapipe's own warning may remain.
    EXPECT_EQ(quiet.err.find("render ["), std::string::npos) << quiet.err;
    EXPECT_EQ(quiet.err.find("info:"), std::string::npos) << quiet.err;
}

// The memory options reach the compile of the frame: it renders under validation without
// sharing memory, and `view` takes the same flags.
TEST_F(Cli, RenderAndViewTakeTheMemoryOptions) {
    const fs::path out = dir_ / "work" / "out.png";
    const CliRun r = run({"render", "--width", "16", "--height", "16", "--frames", "2", "--validate", "--no-alias",
                          "-o", out.string()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(out));
    for (const char* command : {"render", "view"}) {
        const CliRun help = run({command, "--help"});
        ASSERT_EQ(help.status, 0) << help.err;
        EXPECT_NE(help.out.find("--no-alias"), std::string::npos) << command << ": " << help.out;
        EXPECT_NE(help.out.find("--clobber-transients"), std::string::npos) << command << ": " << help.out;
    }
}

// The flags that turn a setting off take effect: with --no-fit-environment the cubes are baked
// at the graph's declared sizes, not sized for the 16-pixel-tall view.
TEST_F(Cli, RenderNoFitEnvironmentBakesAtTheDeclaredSizes) {
    const std::vector<std::string> args{"render", "--width", "16", "--height", "16", "--frames", "1", "-o",
                                        (dir_ / "work" / "out.png").string()};
    const CliRun fitted = run(args);
    ASSERT_EQ(fitted.status, 0) << fitted.err;
    EXPECT_NE(fitted.err.find("for a 16-pixel-tall view"), std::string::npos) << fitted.err;
    std::vector<std::string> declared = args;
    declared.push_back("--no-fit-environment");
    const CliRun r = run(declared);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("for a 16-pixel-tall view"), std::string::npos) << r.err;
}
#endif

// ---- compile --watch ----------------------------------------------------------------------


std::string replaced(std::string text, const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
    return text;
}

/// Saves `text` the way editors do: a new file renamed over the old one.
void saveAtomically(const fs::path& path, const std::string& text) {
    const fs::path temp = path.string() + ".swp";
    std::ofstream(temp) << text;
    fs::rename(temp, path);
}

TEST_F(Cli, WatchRecompilesOnSaveAndPrintsThePlanDiff) {
    const fs::path graph = writeGraph("watched.json", kWatchedGraph);
    const fs::path out = dir_ / "work" / "plan.txt";
    const pid_t pid = spawn({"compile", graph.string(), "--watch", "--watch-interval-ms", "20",
                             "--watch-iterations", "2", "-o", out.string()});
    ASSERT_TRUE(waitFor([&] { return fs::exists(out); }, 20)) << slurp(dir_ / "stderr");
    const std::string first = slurp(out);
    EXPECT_NE(first.find("] blur (Generic)"), std::string::npos) << first;

    // A save that turns the feature off: the diff removes the pass and adds the culled entry.
    const std::string blurOff = replaced(kWatchedGraph, R"("blur": true)", R"("blur": false)");
    saveAtomically(graph, blurOff);
    ASSERT_TRUE(waitFor([&] { return slurp(dir_ / "stdout").find("@@") != std::string::npos; }, 20))
        << slurp(dir_ / "stderr");
    ASSERT_TRUE(waitFor([&] { return slurp(out) != first; }, 20));
    const std::string diff = slurp(dir_ / "stdout");
    EXPECT_EQ(diff.rfind("--- plan (before)\n+++ plan (now)\n@@ -", 0), 0u) << diff;
    EXPECT_NE(diff.find("\n-[1] blur (Generic)\n"), std::string::npos) << diff;
    EXPECT_NE(diff.find("\n+    blur: feature 'blur' is off"), std::string::npos) << diff;
    EXPECT_NE(diff.find("\n graph watched\n-features: blur=on\n+features: blur=off\n"), std::string::npos)
        << diff;  // a context line, then the change
    const std::string second = slurp(out);
    const fs::path edited = writeGraph("edited.json", blurOff);
    const CliRun direct = run({"compile", edited.string()});
    EXPECT_EQ(second, direct.out);  // -o holds exactly what `compile` prints for the saved file

    // A save that breaks the file: errors on stderr, the last good plan stays in -o.
    saveAtomically(graph, "{\n  \"version\": 1,\n  \"name\": \n}\n");
    EXPECT_EQ(waitExit(pid, 20), 0);  // the second recompilation ends the test hook
    const std::string err = slurp(dir_ / "stderr");
    EXPECT_NE(err.find(graph.string() + ":4:1:"), std::string::npos) << err;
    EXPECT_NE(err.find("keeping the last plan that compiled"), std::string::npos) << err;
    EXPECT_EQ(slurp(out), second);
    EXPECT_EQ(workFiles(), std::vector<std::string>{"plan.txt"});
}

TEST_F(Cli, WatchQuietPrintsNoLogsAndStopsOnSigint) {
    const fs::path graph = writeGraph("watched.json", kWatchedGraph);
    const pid_t pid = spawn({"-q", "compile", graph.string(), "--watch", "--watch-interval-ms", "20"});
    ASSERT_TRUE(waitFor([&] { return slurp(dir_ / "stdout").find("present") != std::string::npos; }, 20));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ::kill(pid, SIGINT);
    EXPECT_EQ(waitExit(pid, 20), 0);
    EXPECT_EQ(slurp(dir_ / "stderr"), "");  // -q: not even "watching ..."
}

}  // namespace
