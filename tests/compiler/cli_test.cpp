// `skygraph compile` as users call it (contract §3): exit status 0 on success, 1 on a user
// error with the message on stderr and nothing half-written, 2 on misuse of the command line.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;
const fs::path kCli = SKYGRAPH_CLI;

struct CliRun {
    int status = -1;
    std::string out;
    std::string err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("skygraph_cli_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "work");
    }
    void TearDown() override { fs::remove_all(dir_); }

    /// Runs the CLI with `args`, from the source directory, capturing stdout and stderr.
    CliRun run(const std::vector<std::string>& args) {
        std::string cmd = "cd " + quote(kSource.string()) + " && " + quote(kCli.string());
        for (const auto& a : args) cmd += " " + quote(a);
        cmd += " >" + quote((dir_ / "stdout").string()) + " 2>" + quote((dir_ / "stderr").string());
        const int raw = std::system(cmd.c_str());
        CliRun r;
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.out = slurp(dir_ / "stdout");
        r.err = slurp(dir_ / "stderr");
        return r;
    }

    fs::path writeGraph(const std::string& name, const std::string& text) {
        const fs::path p = dir_ / name;
        std::ofstream(p) << text;
        return p;
    }

    /// Files in the scratch output folder (to prove nothing was left behind).
    std::vector<std::string> workFiles() const {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(dir_ / "work")) out.push_back(e.path().filename().string());
        return out;
    }

    fs::path dir_;
};

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

TEST_F(Cli, CompileRasterAsJson) {
    const CliRun r = run({"compile", "graphs/raster.json", "--format", "json"});
    ASSERT_EQ(r.status, 0) << r.err;
    nlohmann::json plan;
    ASSERT_NO_THROW(plan = nlohmann::json::parse(r.out)) << r.out;
    ASSERT_TRUE(plan.is_object());
    for (const char* key : {"graph", "features", "passes", "final", "culled"})
        EXPECT_TRUE(plan.contains(key)) << key << " missing in " << r.out;
    EXPECT_EQ(plan["graph"], "raster");
    EXPECT_EQ(plan["features"], (nlohmann::json{{"geometry", true}, {"skybox", true}}));
    std::vector<std::string> names;
    for (const auto& p : plan["passes"]) {
        names.push_back(p["name"].get<std::string>());
        EXPECT_TRUE(p["type"].is_string());
        EXPECT_TRUE(p["barriers"].is_array());
    }
    EXPECT_EQ(names, (std::vector<std::string>{"forward", "skybox", "tonemap"}));
    EXPECT_TRUE(plan["culled"].is_array());
    EXPECT_TRUE(plan["culled"].empty());
    // The swapchain ends in PRESENT_SRC.
    bool present = false;
    for (const auto& b : plan["final"])
        present |= b["resource"] == "swapchain" && b["newLayout"] == "VK_IMAGE_LAYOUT_PRESENT_SRC_KHR";
    EXPECT_TRUE(present) << plan["final"].dump(2);
}

TEST_F(Cli, FeatureOffCullsWithAReason) {
    const CliRun r = run({"compile", "graphs/raster.json", "--format", "json", "--feature", "skybox=off"});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto plan = nlohmann::json::parse(r.out);
    EXPECT_EQ(plan["features"]["skybox"], false);
    ASSERT_EQ(plan["culled"].size(), 1u) << plan["culled"].dump();
    EXPECT_EQ(plan["culled"][0]["pass"], "skybox");
    EXPECT_EQ(plan["culled"][0]["reason"], "feature 'skybox' is off");
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

TEST_F(Cli, TextAndDotFormats) {
    const CliRun text = run({"compile", "graphs/raster.json"});
    ASSERT_EQ(text.status, 0) << text.err;
    EXPECT_NE(text.out.find("tonemap"), std::string::npos) << text.out;
    const CliRun dot = run({"compile", "graphs/raster.json", "--format", "dot", "--feature", "skybox=off"});
    ASSERT_EQ(dot.status, 0) << dot.err;
    EXPECT_EQ(dot.out.rfind("digraph", 0), 0u) << dot.out;
    EXPECT_NE(dot.out.find("skybox"), std::string::npos);
    EXPECT_NE(dot.out.find("feature 'skybox' is off"), std::string::npos) << dot.out;
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

TEST_F(Cli, UnwritableOutputExitsOne) {
    const fs::path out = dir_ / "work" / "no_such_dir" / "plan.json";
    const CliRun r = run({"compile", "graphs/raster.json", "-o", out.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("plan.json"), std::string::npos) << r.err;
    EXPECT_TRUE(workFiles().empty());
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

}  // namespace
