// `skygraph check` as users call it: the shipped graphs under every feature combination,
// goldens written, edited and compared, a compute-only graph, a combination that cannot
// compile, a device that does not exist, JUnit XML read back by an independent parser; and
// `compile`'s warning for a combination that `check` fails because it presents nothing.
#include "cli_fixture.hpp"
#include "folder_events.hpp"

#include <skygraph/hdr_image.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <csignal>
#include <iterator>
#include <regex>

namespace {

using namespace skygraph::cli_test;
namespace fs = std::filesystem;

/// A frame graph whose one pass, the only user of its presented image, is culled with `lit`
/// off: that combination presents nothing.
const char* kDarkWhenUnlit = R"({"version": 1, "name": "dark", "features": {"lit": true},
  "resources": {"swapchain": {"type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",
                              "external": true, "final": "Present"}},
  "passes": [{"name": "light", "type": "Generic", "if": "lit", "uses": {"swapchain": "Write@ColorAttachment"}}]})";

/// raster.json with its two ForwardPasses both running when geometry and skybox are on: the
/// second, forward_ibl, writes the depth the first wrote (its load op there is not a clear).
std::string rasterWithTwoDepthWrites() {
    std::ifstream in(kSource / "graphs/raster.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto replace = [&](const std::string& from, const std::string& to) {
        const size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) text.replace(at, from.size(), to);
    };
    replace(R"("if": "geometry && !skybox")", R"("if": "geometry")");
    replace(R"("hdr_color": "Write@ColorAttachment",
                "irradiance")", R"("hdr_color": "ReadWrite@ColorAttachment",
                "irradiance")");
    return text;
}

#if SKYGRAPH_CLI_HAS_RENDER

/// Rows of the table whose last column is `result` ("pass" or "FAIL").
size_t rows(const std::string& table, const std::string& result) {
    size_t n = 0;
    std::istringstream in(table);
    for (std::string line; std::getline(in, line);)
        if (line.size() > result.size() && line.ends_with("  " + result)) ++n;
    return n;
}

/// A graph of two compute passes and no image to present: it runs, and nothing is written.
const char* kComputeOnly = R"({
  "version": 1, "name": "compute_only",
  "resources": {
    "field": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [32, 32] },
    "result": { "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [32, 32],
                "external": true, "final": "ShaderRead" }
  },
  "passes": [
    { "name": "fill", "type": "Generic", "uses": { "field": "Write@Compute" } },
    { "name": "blur", "type": "Generic", "uses": { "field": "Read@Compute", "result": "Write@Compute" } }
  ]
})";

/// With `producer` off, `consume` reads what nothing wrote: that combination cannot compile.
const char* kOneBadCombination = R"({
  "version": 1, "name": "one_bad", "features": { "producer": true },
  "resources": {
    "t": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16] },
    "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16],
             "external": true, "final": "ShaderRead" }
  },
  "passes": [
    { "name": "produce", "type": "Generic", "if": "producer", "uses": { "t": "Write@Compute" } },
    { "name": "consume", "type": "Generic", "uses": { "t": "Read@Compute", "out": "Write@Compute" } }
  ]
})";

// 16 + 2 + 2 + 128 combinations, each compiled, verified and run without a message; the
// sanitizer build checks the pairwise covering set it renders (5 + 2 + 2 + 6, as
// SKYGRAPH_PAIRWISE_RENDER_CASES says in tests/CMakeLists.txt).
#ifdef SKYGRAPH_PAIRWISE_RENDER_CASES
constexpr const char* kCoverage = "pairwise";
constexpr size_t kCases = 15;
#else
constexpr const char* kCoverage = "all";
constexpr size_t kCases = 148;
#endif

TEST_F(Cli, CheckPassesEveryShippedGraphAndCombinationWithJUnit) {
    const fs::path junit = dir_ / "work" / "check.xml";
    const CliRun r = run({"check", "graphs/deferred.json", "graphs/ibl.json", "graphs/pathtrace.json",
                          "graphs/raster.json", "--features", kCoverage, "--frames", "2", "--junit", junit.string()});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    const std::string cases = std::to_string(kCases);
    EXPECT_EQ(rows(r.out, "pass"), kCases) << r.out;
    EXPECT_EQ(rows(r.out, "FAIL"), 0u) << r.out;
    EXPECT_NE(r.out.find(cases + " case(s): " + cases + " passed, 0 failed"), std::string::npos) << r.out;
    // Read back by Python's XML parser: a suite per file, a case per combination, none failing.
    const std::string script =
        "import sys, xml.etree.ElementTree as E\n"
        "root = E.parse(sys.argv[1]).getroot()\n"
        "suites = root.findall('testsuite')\n"
        "print(root.get('tests'), root.get('failures'), len(suites), len(root.findall('.//testcase')),"
        " len(root.findall('.//failure')))\n";
    std::ofstream(dir_ / "junit.py") << script;
    const std::string cmd = "python3 " + quote((dir_ / "junit.py").string()) + " " + quote(junit.string()) + " > " +
                            quote((dir_ / "parsed").string());
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_EQ(slurp(dir_ / "parsed"), cases + " 0 4 " + cases + " 0\n");
}

// A --junit file that cannot be written is refused before any case runs (after, a run on
// the device would have been thrown away).
TEST_F(Cli, CheckRefusesAJUnitPathItCannotWriteBeforeRunning) {
    const fs::path junit = dir_ / "no_such_folder" / "j.xml";
    const CliRun r = run({"check", "graphs/pathtrace.json", "--no-run", "--junit", junit.string()});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("cannot write '" + junit.string() + "'"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("case(s)"), std::string::npos) << "no case ran: " << r.out;
}

TEST_F(Cli, CheckShowsTheDiffOfAGoldenWithOneBarrierEdited) {
    const fs::path golden = dir_ / "golden";
    const CliRun update = run({"check", "graphs/pathtrace.json", "--golden", golden.string(), "--update", "--no-run"});
    ASSERT_EQ(update.status, 0) << update.out << update.err;
    EXPECT_NE(update.out.find("review them"), std::string::npos) << update.out;
    const fs::path file = golden / "pathtrace.environment_file-off.plan.txt";
    ASSERT_TRUE(fs::exists(file));
    EXPECT_EQ(run({"check", "graphs/pathtrace.json", "--golden", golden.string(), "--no-run"}).status, 0);

    // Held back: the golden expects a write the compiled plan's barrier does not wait for.
    std::string text = slurp(file);
    const std::string from = "COMPUTE_SHADER / SHADER_STORAGE_WRITE  ->";
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << text;
    text.replace(at, from.size(), "COMPUTE_SHADER / NONE  ->");
    std::ofstream(file, std::ios::binary) << text;
    const CliRun r = run({"check", "graphs/pathtrace.json", "--golden", golden.string(), "--no-run"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("--- " + file.string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("+++ compiled"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("-      COMPUTE_SHADER / NONE  ->"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("+      COMPUTE_SHADER / SHADER_STORAGE_WRITE  ->"), std::string::npos) << r.out;
    EXPECT_EQ(rows(r.out, "FAIL"), 1u) << r.out;  // the other combination's golden still matches
    EXPECT_EQ(rows(r.out, "pass"), 1u) << r.out;
}

// A golden may hold any bytes: its diff and the first line of a golden of another version were
// printed as they were, a terminal's escape sequence (here, to red) included.
TEST_F(Cli, CheckShowsControlCharactersOfAGoldenEscaped) {
    const fs::path golden = dir_ / "golden";
    const std::vector<std::string> check{"check", "graphs/ibl.json", "--features", "streamed_equirect=off",
                                         "--golden", golden.string(), "--no-run"};
    std::vector<std::string> update = check;
    update.push_back("--update");
    ASSERT_EQ(run(update).status, 0);
    const fs::path file = golden / "ibl.streamed_equirect-off.plan.txt";
    const std::string written = slurp(file);
    std::ofstream(file, std::ios::binary) << written << "\x01\x0c\x1b[31m\xff\n";
    const CliRun diff = run(check);
    EXPECT_EQ(diff.status, 1) << diff.out;
    EXPECT_NE(diff.out.find("\n-\\u0001\\u000c\\u001b[31m\\xff\n"), std::string::npos) << diff.out;
    EXPECT_EQ(diff.out.find_first_of("\x01\x0c\x1b\xff"), std::string::npos) << diff.out;

    std::string other = written;
    other.replace(0, other.find('\n'), "# skygraph golden plan, format \x1b[31m");
    std::ofstream(file, std::ios::binary) << other;
    const CliRun version = run(check);
    EXPECT_EQ(version.status, 1) << version.out;
    EXPECT_NE(version.out.find("its first line is '# skygraph golden plan, format \\u001b[31m'"), std::string::npos)
        << version.out;
    EXPECT_EQ(version.out.find('\x1b'), std::string::npos) << version.out;
}

TEST_F(Cli, CheckReportsGoldensOfAnotherVersionAndMissingDirectories) {
    const fs::path golden = dir_ / "golden";
    ASSERT_EQ(run({"check", "graphs/ibl.json", "--golden", golden.string(), "--update", "--no-run"}).status, 0);
    const fs::path file = golden / "ibl.streamed_equirect-off.plan.txt";
    std::string text = slurp(file);
    text.replace(0, text.find('\n'), "# skygraph golden plan, format 0");
    std::ofstream(file, std::ios::binary) << text;
    const CliRun old = run({"check", "graphs/ibl.json", "--golden", golden.string(), "--no-run"});
    EXPECT_EQ(old.status, 1);
    EXPECT_NE(old.out.find("golden other version: " + file.string() + " was not written by this version"),
              std::string::npos) << old.out;
    const CliRun missing = run({"check", "graphs/ibl.json", "--golden", (dir_ / "nowhere").string(), "--no-run"});
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.out.find("(its directory does not exist)"), std::string::npos) << missing.out;
}

TEST_F(Cli, CheckRunsAComputeOnlyGraphAndRenderExitsZeroOnIt) {
    const fs::path graph = writeGraph("compute_only.json", kComputeOnly);
    const CliRun r = run({"check", graph.string(), "--frames", "2"});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_EQ(rows(r.out, "pass"), 1u) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(compute_only\.json\s+defaults\s+2\s+0\s+\d+\s+0\s+0\s+-\s+ok)"))) << r.out;
    const CliRun render = run({"render", graph.string(), "--frames", "2", "--validate"});
    EXPECT_EQ(render.status, 0) << render.err;
}

TEST_F(Cli, CheckGoesOnPastACombinationThatCannotCompile) {
    const fs::path graph = writeGraph("one_bad.json", kOneBadCombination);
    const CliRun r = run({"check", graph.string(), "--frames", "1"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_EQ(rows(r.out, "FAIL"), 1u) << r.out;
    EXPECT_EQ(rows(r.out, "pass"), 1u) << r.out;
    EXPECT_NE(r.out.find("[producer=off]\n  does not compile: " + graph.string()), std::string::npos) << r.out;
}

// A frame graph whose passes, in some combination, use none of its presented images would
// present nothing: that combination fails, naming them; the others pass.
TEST_F(Cli, CheckFailsACombinationThatPresentsNothing) {
    const fs::path graph = writeGraph("dark.json", kDarkWhenUnlit);
    const CliRun r = run({"check", graph.string(), "--no-run"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_EQ(rows(r.out, "FAIL"), 1u) << r.out;
    EXPECT_EQ(rows(r.out, "pass"), 1u) << r.out;
    EXPECT_NE(r.out.find("[lit=off]\n  presents nothing: no pass that runs in this combination uses a presented "
                         "image ('swapchain'): the frame presents nothing"),
              std::string::npos)
        << r.out;
}

TEST_F(Cli, CheckNamesADeviceThatCannotRunTheGraphAndStillVerifies) {
    const CliRun r = run({"check", "graphs/pathtrace.json", "--device", "no-such-device"});
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(rows(r.out, "FAIL"), 2u) << r.out;
    EXPECT_NE(r.out.find("cannot run: no device: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("no-such-device"), std::string::npos) << r.out;
    // Compiled and verified all the same: each row has its barriers and the verifier's "ok".
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(environment_file=off\s+2\s+1\s+4\s+0\s+0\s+-\s+ok)"))) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(environment_file=on\s+2\s+1\s+4\s+0\s+0\s+-\s+ok)"))) << r.out;
}

TEST_F(Cli, CheckJUnitOfFailuresIsValidXmlWithTheDiff) {
    const fs::path golden = dir_ / "golden";
    ASSERT_EQ(run({"check", "graphs/pathtrace.json", "--golden", golden.string(), "--update", "--no-run"}).status, 0);
    // A golden line with markup and text that is not ASCII: the diff quotes it into the XML.
    const fs::path file = golden / "pathtrace.environment_file-on.plan.txt";
    std::string text = slurp(file);
    text.insert(text.find('\n') + 1, "<b> & \"caf\xc3\xa9\" \xff\n");
    std::ofstream(file, std::ios::binary) << text;
    const fs::path junit = dir_ / "work" / "failing.xml";
    const CliRun r = run({"check", "graphs/pathtrace.json", "--golden", golden.string(), "--no-run", "--junit",
                          junit.string()});
    EXPECT_EQ(r.status, 1);
    const std::string script =
        "import sys, xml.etree.ElementTree as E\n"
        "root = E.parse(sys.argv[1]).getroot()\n"
        "f = root.findall('.//failure')\n"
        "print(root.get('failures'), len(f), f[0].get('message').startswith('golden differs'),"
        " '-<b> & \"caf\u00e9\" ?' in f[0].text)\n";
    std::ofstream(dir_ / "junit.py") << script;
    const std::string cmd = "python3 " + quote((dir_ / "junit.py").string()) + " " + quote(junit.string()) + " > " +
                            quote((dir_ / "parsed").string()) + " 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir_ / "parsed");
    EXPECT_EQ(slurp(dir_ / "parsed"), "1 1 True True\n") << slurp(junit);
}

TEST_F(Cli, CheckGivesTheSameTableOnSeveralThreads) {
    const auto withoutTimes = [](std::string table) {
        return std::regex_replace(table, std::regex(R"(\s+\d+\.\d\d\s+(pass|FAIL))"), " $1");
    };
    const CliRun one = run({"check", "graphs/raster.json", "graphs/deferred.json", "--no-run", "--jobs", "1"});
    const CliRun four = run({"check", "graphs/raster.json", "graphs/deferred.json", "--no-run", "--jobs", "4"});
    EXPECT_EQ(one.status, 0);
    EXPECT_EQ(four.status, 0);
    EXPECT_EQ(rows(four.out, "pass"), 144u);  // 128 + 16
    EXPECT_EQ(withoutTimes(one.out), withoutTimes(four.out));
}

TEST_F(Cli, CheckRefusesTwoCasesWithOneGoldenAndNamesTheLayoutsItForces) {
    const fs::path golden = dir_ / "golden";
    const CliRun twice = run({"check", "graphs/ibl.json", "graphs/ibl.json", "--golden", golden.string(), "--update",
                              "--no-run"});
    EXPECT_EQ(twice.status, 1);
    EXPECT_EQ(rows(twice.out, "pass"), 2u) << twice.out;  // the first file's two combinations
    EXPECT_EQ(rows(twice.out, "FAIL"), 2u) << twice.out;
    // Its plan compiles: the row says it was not checked, not that it does not compile.
    EXPECT_NE(twice.out.find("  not checked: its golden " + (golden / "ibl.streamed_equirect-off.plan.txt").string() +
                             " is also graphs/ibl.json's"),
              std::string::npos) << twice.out;
    EXPECT_EQ(twice.out.find("does not compile"), std::string::npos) << twice.out;
    const CliRun optimal = run({"check", "graphs/ibl.json", "--golden", golden.string(), "--update", "--no-run",
                                "--layouts", "optimal"});
    EXPECT_EQ(optimal.status, 0);
    EXPECT_TRUE(fs::exists(golden / "ibl.streamed_equirect-off.layouts-optimal.plan.txt"));
}

// a.json with its feature b on and a.b-on.json have one golden name: the message said to check
// graphs of one file name apart, though their names differ.
TEST_F(Cli, CheckNamesBothGraphsWhoseGoldenNamesCollide) {
    const std::string graph = R"({"version": 1, "name": "NAME", "features": FEATURES,
      "resources": {"img": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64]},
                    "out": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true,
                            "final": "TransferSrc"}},
      "passes": [{"name": "a", "type": "Generic", "uses": {"img": "Write@Compute"}},
                 {"name": "b", "type": "Generic", "uses": {"img": "Read@Fragment", "out": "Write@ColorAttachment"}}]})";
    const auto withFeatures = [&](const std::string& name, const std::string& features) {
        std::string text = std::regex_replace(graph, std::regex("NAME"), name);
        return std::regex_replace(text, std::regex("FEATURES"), features);
    };
    const fs::path first = writeGraph("a.json", withFeatures("first", R"({"b": true, "f": true})"));
    const fs::path second = writeGraph("a.b-on.json", withFeatures("second", R"({"f": true})"));
    const fs::path golden = dir_ / "golden";
    const CliRun r = run({"check", first.string(), second.string(), "--golden", golden.string(), "--update", "--no-run"});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("not checked: its golden " + (golden / "a.b-on.f-on.plan.txt").string() + " is also " +
                         first.string() + "'s: the golden names of " + first.string() + " and " + second.string() +
                         " collide"),
              std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("one file name"), std::string::npos) << r.out;
}

TEST_F(Cli, CheckCountsPerformanceWarningsAndCanFailOnThem) {
    // The deferred frame's history copy reads an image kept in GENERAL, which the layer
    // reports as a performance warning (it suggests TRANSFER_SRC_OPTIMAL).
    const std::vector<std::string> args{"check", "graphs/deferred.json", "--features",
                                        "bloom=off,dof=off,ssao=off,ssr=off", "--frames", "2"};
    const CliRun lenient = run(args);
    EXPECT_EQ(lenient.status, 0) << lenient.out;
    EXPECT_TRUE(std::regex_search(lenient.out, std::regex(R"(performance warning\(s\))"))) << lenient.out;
    EXPECT_NE(lenient.out.find("WARN graphs/deferred.json"), std::string::npos) << lenient.out;
    std::vector<std::string> strict = args;
    strict.push_back("--warnings-as-errors");
    const CliRun r = run(strict);
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find("errors by --warnings-as-errors"), std::string::npos) << r.out;
    // Each reader in its optimal layout: the copy finds TRANSFER_SRC_OPTIMAL, and the layer is
    // satisfied even with warnings as errors.
    strict.push_back("--layouts");
    strict.push_back("optimal");
    const CliRun optimal = run(strict);
    EXPECT_EQ(optimal.status, 0) << optimal.out;
    EXPECT_EQ(optimal.out.find("performance warning"), std::string::npos) << optimal.out;
    const CliRun plan = run({"compile", "graphs/deferred.json", "--layouts", "optimal"});
    EXPECT_EQ(plan.status, 0);
    EXPECT_NE(plan.out.find("layouts: optimal"), std::string::npos);
    EXPECT_NE(plan.out.find("uses taa_resolved Read@Transfer in TRANSFER_SRC_OPTIMAL"), std::string::npos) << plan.out;
    EXPECT_EQ(run({"compile", "graphs/deferred.json", "--layouts", "fast"}).status, 2);
}

TEST_F(Cli, CheckFeatureSelection) {
    const CliRun one = run({"check", "graphs/raster.json", "--features", "skybox=off,ui=on", "--no-run"});
    EXPECT_EQ(one.status, 0) << one.out;
    EXPECT_EQ(rows(one.out, "pass"), 1u) << one.out;
    EXPECT_NE(one.out.find("skybox=off ui=on"), std::string::npos) << one.out;
    const CliRun pairwise = run({"check", "graphs/raster.json", "--features", "pairwise", "--no-run"});
    EXPECT_EQ(pairwise.status, 0);
    EXPECT_GE(rows(pairwise.out, "pass"), 4u);
    EXPECT_LT(rows(pairwise.out, "pass"), 16u) << pairwise.out;
    // The row of a feature the graph does not declare shows what was asked for.
    const CliRun unknown = run({"check", "graphs/raster.json", "--features", "nosuch=on,ui=on", "--no-run"});
    EXPECT_EQ(unknown.status, 1);
    EXPECT_TRUE(std::regex_search(unknown.out, std::regex(R"(graphs/raster\.json +[a-z_= ]* ui=on nosuch=on +-)")))
        << unknown.out;
    EXPECT_NE(unknown.out.find("ui=on nosuch=on]\n  does not compile: graphs/raster.json: features: unknown feature 'nosuch'"),
              std::string::npos) << unknown.out;
    // An empty element is a feature lost to a stray comma, wherever it is.
    for (const std::string features : {"skybox=off,", ",skybox=off", "skybox=off,,ui=on", ","}) {
        const CliRun empty = run({"check", "graphs/raster.json", "--features", features, "--no-run"});
        EXPECT_EQ(empty.status, 2) << features;
        EXPECT_NE(empty.err.find("--features '" + features + "' has an empty element"), std::string::npos)
            << features << ": " << empty.err;
        EXPECT_EQ(empty.out, "") << features;
    }
    const CliRun badValue = run({"check", "graphs/raster.json", "--features", "skybox=maybe", "--no-run"});
    EXPECT_EQ(badValue.status, 2);
    EXPECT_NE(badValue.err.find("--features expects NAME=on or NAME=off, got 'skybox=maybe'"), std::string::npos)
        << badValue.err;
    EXPECT_EQ(run({"check", "graphs/raster.json", "--size", "64by64", "--no-run"}).status, 2);
    EXPECT_EQ(run({"check", "graphs/raster.json", "--update", "--no-run"}).status, 2);  // needs --golden
}

// --size was read by sscanf, which takes a sign and white space before a number: "+64x64",
// "64x 64" and a leading tab passed, though --width calls " 64" no number.
TEST_F(Cli, CheckSizeTakesEachSideAsWidthTakesANumber) {
    const std::vector<std::pair<std::string, std::string>> refused{
        {"+64x64", "'+64' is not a number"},
        {"64x+64", "'+64' is not a number"},
        {"64x 64", "' 64' is not a number"},
        {"\t64x64", "'\\u000964' is not a number"},
        {"64 x64", "'64 ' is not a number"},
        {"64x64 ", "'64 ' is not a number"},
        {"64x1e2", "'1e2' is not a whole number in decimal digits"},
        {"64x64x64", "'64x64' is not a number"},
        {"x64", "'' is not a number"},
        {"-64x64", "expected WIDTHxHEIGHT, each 1 to 16384"},
        {"64x16385", "expected WIDTHxHEIGHT, each 1 to 16384"},
        {"64x99999999999", "expected WIDTHxHEIGHT, each 1 to 16384"},
    };
    for (const auto& [size, why] : refused) {
        const CliRun r = run({"check", "graphs/raster.json", "--features", "skybox=off,ui=on", "--size", size, "--no-run"});
        EXPECT_EQ(r.status, 2) << size << ": " << r.out << r.err;
        EXPECT_NE(r.err.find("error: --size '"), std::string::npos) << size << ": " << r.err;
        EXPECT_NE(r.err.find(why), std::string::npos) << size << ": " << r.err;
    }
    // Leading zeros are decimal there too.
    const CliRun padded = run({"check", "graphs/raster.json", "--features", "skybox=off,ui=on", "--size", "064x010",
                               "--no-run"});
    EXPECT_EQ(padded.status, 0) << padded.err;
}

// A graph of 17 features: every combination, 2^17, is more than check tries. The graph loads
// and would compile: its row says it was not checked, and why.
TEST_F(Cli, CheckSaysAGraphWithTooManyFeaturesForAllIsNotChecked) {
    std::string features;
    for (int i = 0; i < 17; ++i) features += (i ? ", " : "") + std::string("\"f") + std::to_string(i) + "\": false";
    const fs::path graph = writeGraph("many.json", std::string(R"({
  "version": 1, "name": "many", "features": {)") + features + R"(},
  "resources": { "out": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [16, 16],
                          "external": true, "final": "ShaderRead" } },
  "passes": [ { "name": "fill", "type": "Generic", "uses": { "out": "Write@Compute" } } ]
})");
    const CliRun all = run({"check", graph.string(), "--features", "all", "--no-run"});
    EXPECT_EQ(all.status, 1) << all.out << all.err;
    EXPECT_NE(all.out.find("  not checked: graph 'many' has 17 features: all 2^17 combinations are too many"),
              std::string::npos) << all.out;
    EXPECT_EQ(all.out.find("does not compile"), std::string::npos) << all.out;
    const CliRun pairwise = run({"check", graph.string(), "--features", "pairwise", "--no-run"});
    EXPECT_EQ(pairwise.status, 0) << pairwise.out;
}

// --golden naming a file is said once, not as a golden missing under it in every case.
TEST_F(Cli, CheckRefusesAGoldenThatIsNotAFolder) {
    const fs::path junit = dir_ / "work" / "check.xml";
    const CliRun r = run({"check", "graphs/pathtrace.json", "--golden", "graphs/raster.json", "--no-run", "--junit",
                          junit.string()});
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.err.find("error: --golden 'graphs/raster.json' is not a folder"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(workFiles().empty());
}

// The goldens' folder holds golden plans only: a --junit there, under another spelling of the
// folder too, is refused before any case runs, so that --update cannot write a golden and then
// replace it with the report (and a check cannot replace one of the same name).
TEST_F(Cli, CheckRefusesAJUnitInTheGoldenFolder) {
    const fs::path golden = dir_ / "work" / "golden";
    fs::create_directories(golden);
    const fs::path report = golden / "pathtrace.environment_file-off.plan.txt";
    for (const fs::path& junit : {report, golden / ".." / "golden" / "check.xml"}) {
        const CliRun r = run({"check", "graphs/pathtrace.json", "--no-run", "--golden", golden.string(), "--update",
                              "--junit", junit.string()});
        EXPECT_EQ(r.status, 2) << r.out << r.err;
        EXPECT_NE(r.err.find("--junit '" + junit.string() + "' is in the --golden folder"), std::string::npos) << r.err;
        EXPECT_TRUE(fs::is_empty(golden)) << "a golden was written";
    }
}

// Two files whose graphs have one name: the table and the JUnit XML tell them apart by file.
TEST_F(Cli, CheckNamesEachCaseByItsFile) {
    fs::create_directories(dir_ / "a");
    fs::create_directories(dir_ / "b");
    const fs::path first = dir_ / "a" / "compute_only.json", second = dir_ / "b" / "compute_only.json";
    std::ofstream(first) << kComputeOnly;
    std::ofstream(second) << kComputeOnly;
    const fs::path junit = dir_ / "work" / "check.xml";
    const CliRun r = run({"check", first.string(), second.string(), "--no-run", "--junit", junit.string()});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_TRUE(r.out.starts_with("file ")) << r.out;
    for (const fs::path& file : {first, second})
        EXPECT_TRUE(std::regex_search(r.out, std::regex("\n" + file.string() + R"( +defaults +2 )"))) << r.out;
    const std::string script =
        "import sys, xml.etree.ElementTree as E\n"
        "root = E.parse(sys.argv[1]).getroot()\n"
        "print(sorted((s.get('name'), c.get('classname')) for s in root.findall('testsuite') for c in s))\n";
    std::ofstream(dir_ / "junit.py") << script;
    const std::string cmd = "python3 " + quote((dir_ / "junit.py").string()) + " " + quote(junit.string()) + " > " +
                            quote((dir_ / "parsed").string()) + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir_ / "parsed");
    EXPECT_EQ(slurp(dir_ / "parsed"), "[('" + first.string() + "', '" + first.string() + "'), ('" + second.string() +
                                          "', '" + second.string() + "')]\n");
}

TEST_F(Cli, SkySequenceWritesEveryFrameAndRefusesAPatternWithoutANumber) {
    fs::create_directories(dir_ / "work" / "frames");
    const fs::path pattern = dir_ / "work" / "frames" / "sky_%03d.exr";
    const CliRun ok = run({"sky-sequence", pattern.string(), "--frames", "3", "--width", "32"});
    EXPECT_EQ(ok.status, 0) << ok.err;
    for (const char* name : {"sky_000.exr", "sky_001.exr", "sky_002.exr"}) {
        const skygraph::HdrImage frame = skygraph::loadHdrImage(dir_ / "work" / "frames" / name);
        EXPECT_EQ(frame.width, 32u) << name;
        EXPECT_EQ(frame.height, 16u) << name;
    }
    EXPECT_FALSE(fs::exists(dir_ / "work" / "frames" / "sky_003.exr"));
    const CliRun bad = run({"sky-sequence", (dir_ / "work" / "sky.exr").string()});
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("sky.exr': its file name must hold the frame number as %d or %0Nd"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir_ / "work" / "sky.exr"));
}

// An equirect is twice as wide as it is tall: an odd width is misuse, named with its value,
// and nothing is written. One frame is counted as one.
TEST_F(Cli, SkySequenceRefusesAnOddWidthAndCountsOneFrameInTheSingular) {
    const fs::path pattern = dir_ / "work" / "sky_%d.exr";
    for (const char* odd : {"3", "33"}) {
        const CliRun r = run({"sky-sequence", pattern.string(), "--frames", "1", "--width", odd});
        EXPECT_EQ(r.status, 2) << odd << ": " << r.err;
        EXPECT_NE(r.err.find(std::string("error: --width: ") + odd + " is odd: an equirect is twice as wide as it is "
                             "tall, so its width must be even"),
                  std::string::npos)
            << r.err;
        EXPECT_TRUE(workFiles().empty()) << odd;
    }
    const CliRun one = run({"sky-sequence", pattern.string(), "--frames", "1", "--width", "8"});
    ASSERT_EQ(one.status, 0) << one.err;
    EXPECT_EQ(one.out, "skygraph sky-sequence: 1 frame of 8x4, " + (dir_ / "work" / "sky_0.exr").string() + "\n");
    const CliRun two = run({"sky-sequence", pattern.string(), "--frames", "2", "--width", "8"});
    ASSERT_EQ(two.status, 0) << two.err;
    EXPECT_EQ(two.out, "skygraph sky-sequence: 2 frames of 8x4, " + (dir_ / "work" / "sky_0.exr").string() + " to " +
                           (dir_ / "work" / "sky_1.exr").string() + "\n");
}

// As every command does, sky-sequence refuses a folder that does not exist, making none.
TEST_F(Cli, SkySequenceRefusesAFolderThatDoesNotExist) {
    const fs::path missing = dir_ / "work" / "no such folder" / "deeper";
    const CliRun r = run({"sky-sequence", (missing / "sky_%d.exr").string(), "--frames", "2", "--width", "16"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("error: '" + (missing / "sky_0.exr").string() + "': cannot write: the folder '" +
                         missing.string() + "' does not exist"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(workFiles().empty());
    // A later frame that is a link into a missing folder: refused before the frames ahead of
    // it were replaced (they were, and then the run failed).
    const fs::path work = dir_ / "work";
    std::ofstream(work / "sky_0.exr") << "old 0";
    fs::create_symlink(missing / "sky.exr", work / "sky_1.exr");
    const CliRun linked = run({"sky-sequence", (work / "sky_%d.exr").string(), "--frames", "2", "--width", "16"});
    EXPECT_EQ(linked.status, 1) << linked.err;
    EXPECT_NE(linked.err.find("error: '" + (work / "sky_1.exr").string() + "': cannot write: the folder '" +
                              missing.string() + "' does not exist"),
              std::string::npos)
        << linked.err;
    std::ifstream first(work / "sky_0.exr");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(first), {}), "old 0") << "nothing written";
}

// A sequence plays on to its first missing frame: a shorter run over an earlier one's frames
// would leave the rest playing after it. It is refused, writing nothing; the same length
// replaces the frames.
TEST_F(Cli, SkySequenceRefusesToEndBeforeAnEarlierRunsFrames) {
    const std::string pattern = (dir_ / "work" / "sky_%d.exr").string();
    ASSERT_EQ(run({"sky-sequence", pattern, "--frames", "3", "--width", "8"}).status, 0);
    const auto before = fs::last_write_time(dir_ / "work" / "sky_0.exr");
    const CliRun shorter = run({"sky-sequence", pattern, "--frames", "2", "--width", "16"});
    EXPECT_EQ(shorter.status, 1) << shorter.err;
    EXPECT_NE(shorter.err.find("error: '" + (dir_ / "work" / "sky_2.exr").string() +
                               "': exists, and a sequence plays on to its first missing frame: frames from 2 on, "
                               "left from an earlier run, would follow these; remove them first"),
              std::string::npos)
        << shorter.err;
    EXPECT_EQ(fs::last_write_time(dir_ / "work" / "sky_0.exr"), before) << "nothing written";
    EXPECT_EQ(workFiles().size(), 3u);
    EXPECT_EQ(run({"sky-sequence", pattern, "--frames", "3", "--width", "16"}).status, 0);
}

// A run that fails part way writes none of its outputs: a frame path that is a folder, a
// cross in a folder that does not exist, a product where a folder is.
TEST_F(Cli, SkySequenceAndCubemapWriteAllTheirOutputsOrNone) {
    fs::create_directories(dir_ / "work" / "frames" / "sky_1.exr");
    const CliRun frames = run({"sky-sequence", (dir_ / "work" / "frames" / "sky_%d.exr").string(), "--frames", "3",
                               "--width", "8"});
    EXPECT_EQ(frames.status, 1) << frames.err;
    EXPECT_NE(frames.err.find("sky_1.exr': cannot write: it is a folder"), std::string::npos) << frames.err;
    EXPECT_FALSE(fs::exists(dir_ / "work" / "frames" / "sky_0.exr"));
    fs::remove_all(dir_ / "work" / "frames");

    const fs::path sky = dir_ / "sky.exr";
    ASSERT_EQ(run({"sky-sequence", (dir_ / "sky%d.exr").string(), "--frames", "1", "--width", "32"}).status, 0);
    fs::rename(dir_ / "sky0.exr", sky);
    const fs::path cube = dir_ / "work" / "cube.ktx2";
    const CliRun cross = run({"cubemap", sky.string(), "-o", cube.string(), "--size", "32", "--cross",
                              (dir_ / "work" / "nodir" / "x.exr").string()});
    EXPECT_EQ(cross.status, 1) << cross.err;
    EXPECT_NE(cross.err.find("the folder '" + (dir_ / "work" / "nodir").string() + "' does not exist"),
              std::string::npos)
        << cross.err;
    EXPECT_TRUE(workFiles().empty());
    fs::create_directories(dir_ / "work" / "cube.brdf.ktx2");
    const CliRun product = run({"cubemap", sky.string(), "-o", cube.string(), "--size", "32"});
    EXPECT_EQ(product.status, 1) << product.err;
    EXPECT_NE(product.err.find("cube.brdf.ktx2': cannot write: it is a folder"), std::string::npos) << product.err;
    EXPECT_EQ(workFiles(), std::vector<std::string>{"cube.brdf.ktx2"});
    fs::remove(dir_ / "work" / "cube.brdf.ktx2");
    // A product named twice is written once.
    const CliRun twice = run({"cubemap", sky.string(), "-o", cube.string(), "--size", "32", "--products",
                              "irradiance,irradiance"});
    EXPECT_EQ(twice.status, 0) << twice.err;
    std::vector<std::string> written = workFiles();
    std::sort(written.begin(), written.end());
    EXPECT_EQ(written, (std::vector<std::string>{"cube.irradiance.ktx2", "cube.ktx2"}));
}

// Each of cubemap's outputs is written once, into one temporary beside it, and renamed into
// place once (the folder's events say so): not a temporary written through a temporary of its
// own and renamed twice.
TEST_F(Cli, CubemapWritesEachOutputOnceAndRenamesItOnce) {
    const fs::path sky = dir_ / "sky.exr";
    ASSERT_EQ(run({"sky-sequence", (dir_ / "sky%d.exr").string(), "--frames", "1", "--width", "32"}).status, 0);
    fs::rename(dir_ / "sky0.exr", sky);
    const fs::path work = dir_ / "work";
    skygraph::test::FolderEvents events(work);
    const CliRun r = run({"cubemap", sky.string(), "-o", (work / "cube.ktx2").string(), "--size", "32", "--cross",
                          (work / "cross.exr").string()});
    ASSERT_EQ(r.status, 0) << r.err;
    const skygraph::test::FolderEvents::Counts counts = events.take();
    const std::vector<std::string> outputs{"cross.exr", "cube.brdf.ktx2", "cube.irradiance.ktx2", "cube.ktx2",
                                           "cube.prefiltered.ktx2"};
    std::map<std::string, int> once;
    for (const std::string& name : outputs) once[name] = 1;
    EXPECT_EQ(counts.renamedTo, once) << "each output is renamed into place once, and nothing else is renamed";
    EXPECT_EQ(counts.written.size(), outputs.size()) << "one temporary each";
    EXPECT_EQ(counts.created.size(), outputs.size()) << "one temporary each";
    for (const auto& [name, times] : counts.written) {
        EXPECT_EQ(name.front(), '.') << name << " was written under its own name";
        EXPECT_EQ(times, 1) << name;
        EXPECT_EQ(counts.created.count(name), 1u) << name;
    }
    std::vector<std::string> left = workFiles();
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, outputs);
}

// A frame that cannot be written part way through: the frames this run made are removed, and a
// file of the user's that the run had not reached yet is as it was. The third frame is a link
// into a folder that does not exist.
TEST_F(Cli, SkySequenceThatFailsPartWayRemovesTheFramesItMade) {
    const fs::path frames = dir_ / "work" / "frames";
    fs::create_directories(frames);
    std::ofstream(frames / "sky_3.exr") << "the user's";
    fs::create_symlink(dir_ / "no such folder" / "sky.exr", frames / "sky_2.exr");
    const CliRun r = run({"sky-sequence", (frames / "sky_%d.exr").string(), "--frames", "4", "--width", "8"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("sky_2.exr': cannot write"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(frames / "sky_0.exr"));
    EXPECT_FALSE(fs::exists(frames / "sky_1.exr"));
    EXPECT_TRUE(fs::is_symlink(fs::symlink_status(frames / "sky_2.exr")));
    EXPECT_EQ(slurp(frames / "sky_3.exr"), "the user's");
}

// A run stopped by a signal while it writes leaves no temporary: not the hidden one beside an
// output, nor the system's one of an output written in place. The cross is a FIFO that no one
// reads, so the run waits to open it with every temporary made; then it gets SIGTERM (and SIGINT).
TEST_F(Cli, AStoppedRunLeavesNoTemporaries) {
    const fs::path sky = dir_ / "sky.exr";
    ASSERT_EQ(run({"sky-sequence", (dir_ / "sky%d.exr").string(), "--frames", "1", "--width", "32"}).status, 0);
    fs::rename(dir_ / "sky0.exr", sky);
    const fs::path fifo = dir_ / "work" / "cross.hdr", temporaries = dir_ / "tmp";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_directories(temporaries);
    ASSERT_EQ(::setenv("TMPDIR", temporaries.c_str(), 1), 0);
    const auto hidden = [&] {
        std::vector<std::string> names;
        for (const fs::path& folder : {dir_ / "work", temporaries})
            for (const auto& e : fs::directory_iterator(folder))
                if (e.path().filename().string()[0] == '.') names.push_back(e.path().string());
        return names;
    };
    const auto startWaitingOnTheFifo = [&] {
        const pid_t pid = spawn({"cubemap", sky.string(), "-o", (dir_ / "work" / "cube.ktx2").string(), "--size", "32",
                                 "--products", "irradiance", "--cross", fifo.string()});
        // cube.ktx2 and cube.irradiance.ktx2 beside their targets, and the cross's in the system's folder.
        EXPECT_TRUE(waitFor([&] { return hidden().size() == 3; }, 120)) << ::testing::PrintToString(hidden());
        return pid;
    };
    const auto expectEndedBy = [&](pid_t pid, int signal) {
        int raw = 0;
        ASSERT_EQ(::waitpid(pid, &raw, 0), pid);
        EXPECT_TRUE(WIFSIGNALED(raw) && WTERMSIG(raw) == signal) << raw << " " << slurp(dir_ / "stderr");
        EXPECT_EQ(hidden(), std::vector<std::string>{});
        EXPECT_EQ(workFiles(), std::vector<std::string>{"cross.hdr"});
    };
    for (const int signal : {SIGTERM, SIGINT, SIGHUP}) {
        SCOPED_TRACE(signal);
        const pid_t pid = startWaitingOnTheFifo();
        ::kill(pid, signal);
        expectEndedBy(pid, signal);
    }
    // A signal ignored when the run started (nohup's SIGHUP) stays ignored.
    const auto previous = std::signal(SIGHUP, SIG_IGN);
    const pid_t pid = startWaitingOnTheFifo();
    std::signal(SIGHUP, previous);
    ::kill(pid, SIGHUP);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    int raw = 0;
    EXPECT_EQ(::waitpid(pid, &raw, WNOHANG), 0) << "the run ended on an ignored SIGHUP";
    ::kill(pid, SIGTERM);
    expectEndedBy(pid, SIGTERM);
    ::unsetenv("TMPDIR");
}

TEST_F(Cli, CheckDrawsAProgressBarOnlyWhenAskedOrOnATerminal) {
    const CliRun bar = run({"--progress", "always", "check", "graphs/pathtrace.json", "--frames", "1"});
    EXPECT_EQ(bar.status, 0) << bar.out << bar.err;
    EXPECT_NE(bar.err.find("check [##############################] 2/2 cases"), std::string::npos) << bar.err;
    const CliRun plain = run({"check", "graphs/pathtrace.json", "--frames", "1"});
    EXPECT_EQ(plain.err.find("check ["), std::string::npos) << plain.err;  // stderr is a file here
}

// `check --no-run` fails each combination where both of raster.json's ForwardPasses run, with
// ForwardPass's own refusal of the second's depth Write, and passes the others.
TEST_F(Cli, CheckFailsTheCombinationsWhereAPassTypeRefusesThePlan) {
    const fs::path graph = writeGraph("two_depth_writes.json", rasterWithTwoDepthWrites());
    const CliRun check = run({"check", graph.string(), "--no-run"});
    EXPECT_EQ(check.status, 1) << check.out;
    // Of its 7 features' 128 combinations, those with geometry and skybox on.
    EXPECT_EQ(rows(check.out, "FAIL"), 32u) << check.out;
    EXPECT_EQ(rows(check.out, "pass"), 96u) << check.out;
    EXPECT_NE(check.out.find("does not compile: " + graph.string() + ": passes[1].uses.depth: pass 'forward_ibl'"),
              std::string::npos)
        << check.out;
}

#endif

// A pass type's check of the plan (ForwardPass: a depth Write must be the depth's first use)
// runs where the plan is made, without a device: `compile` refuses the combination where both
// of raster.json's ForwardPasses run, naming the usage, and compiles the others.
TEST_F(Cli, CompileRefusesWhatAPassTypeRefusesInThePlan) {
    const fs::path graph = writeGraph("two_depth_writes.json", rasterWithTwoDepthWrites());
    const CliRun both = run({"compile", graph.string()});
    EXPECT_EQ(both.status, 1) << both.out;
    EXPECT_EQ(both.out, "");
    EXPECT_NE(both.err.find(graph.string() + ": passes[1].uses.depth: pass 'forward_ibl', resource 'depth': "
                                             "ForwardPass tests depth against what slot 'depth' starts with, and "
                                             "this Write is not the first use of the resource in the plan"),
              std::string::npos)
        << both.err;
    EXPECT_EQ(run({"compile", graph.string(), "--feature", "skybox=off"}).status, 0);
}

// The same combination compiled is only a warning (the plan is printed, exit status 0), naming
// the file and the presented image; a combination that presents, and a shipped frame, compile
// without one. Outside the render-only section: `compile` needs no device.
TEST_F(Cli, CompileWarnsOfACombinationThatPresentsNothing) {
    const fs::path graph = writeGraph("dark.json", kDarkWhenUnlit);
    const CliRun dark = run({"compile", graph.string(), "--feature", "lit=off"});
    EXPECT_EQ(dark.status, 0) << dark.err;
    EXPECT_NE(dark.out.find("features: lit=off"), std::string::npos) << dark.out;
    EXPECT_EQ(dark.err, "warning: " + graph.string() +
                            ": no pass that runs in this combination uses a presented image ('swapchain'): "
                            "the frame presents nothing\n");
    const CliRun lit = run({"compile", graph.string()});
    EXPECT_EQ(lit.status, 0) << lit.err;
    EXPECT_EQ(lit.err, "");
    const CliRun raster = run({"compile", "graphs/raster.json"});
    EXPECT_EQ(raster.status, 0) << raster.err;
    EXPECT_EQ(raster.err, "");
}

}  // namespace
