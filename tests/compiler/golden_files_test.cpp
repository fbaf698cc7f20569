// Golden plan files (<skygraph/golden.hpp>): their names, their header, each status of a
// comparison, and writing them whole.
#include <skygraph/compiler.hpp>
#include <skygraph/golden.hpp>
#include <skygraph/plan_format.hpp>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <unistd.h>

namespace skygraph {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;

class GoldenFile : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("skygraph_golden_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        graph_ = loadGraphFile(kSource / "graphs" / "pathtrace.json", PassRegistry::withBuiltins());
        plan_ = compile(graph_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
    GraphDesc graph_;
    Plan plan_;
};

TEST_F(GoldenFile, NamesFollowTheDeclaredFeatures) {
    EXPECT_EQ(goldenFileName(graph_, {{"environment_file", true}}), "pathtrace.environment_file-on.plan.txt");
    EXPECT_EQ(goldenFileName(graph_, {}), "pathtrace.environment_file-off.plan.txt");  // the default
    GraphDesc inMemory;
    inMemory.name = "mine";
    inMemory.file = "<memory>";
    EXPECT_EQ(goldenFileName(inMemory, {}), "mine.plan.txt");
    // A name is any text: it stays one file in the goldens' folder.
    inMemory.name = "../up/and out";
    EXPECT_EQ(goldenFileName(inMemory, {}), "_.._up_and_out.plan.txt");
    inMemory.name = "";
    EXPECT_EQ(goldenFileName(inMemory, {}), "_.plan.txt");
    inMemory.features.push_back({"../f", false});
    EXPECT_EQ(goldenFileName(inMemory, {}), "_._.._f-off.plan.txt");
}

TEST_F(GoldenFile, EveryStatus) {
    const fs::path file = dir_ / "sub" / "p.plan.txt";
    EXPECT_EQ(compareWithGolden(plan_, file).status, GoldenStatus::Missing);
    writeGolden(plan_, file);
    EXPECT_EQ(std::distance(fs::directory_iterator(file.parent_path()), fs::directory_iterator()), 1)
        << "a temporary file was left beside the golden";
    const GoldenComparison same = compareWithGolden(plan_, file);
    EXPECT_TRUE(same.ok()) << same.message;
    EXPECT_TRUE(same.diff.empty());
    EXPECT_EQ(goldenText(plan_).substr(0, goldenText(plan_).find('\n')), "# skygraph golden plan, format 2");

    CompileOptions other;
    other.outputWidth = 64;
    const GoldenComparison differs = compareWithGolden(compile(graph_, other), file);
    EXPECT_EQ(differs.status, GoldenStatus::Differs);
    EXPECT_NE(differs.diff.find("-output: 1920x1080"), std::string::npos) << differs.diff;
    EXPECT_NE(differs.diff.find("+output: 64x1080"), std::string::npos) << differs.diff;

    // A golden whose last newline an editor dropped differs, and the diff shows where.
    std::string cut = goldenText(plan_);
    cut.pop_back();
    std::ofstream(file, std::ios::binary | std::ios::trunc) << cut;
    const GoldenComparison noNewline = compareWithGolden(plan_, file);
    EXPECT_EQ(noNewline.status, GoldenStatus::Differs);
    EXPECT_NE(noNewline.diff.find("\\ No newline at end of file\n+"), std::string::npos) << noNewline.diff;
    EXPECT_NE(noNewline.diff.find("@@"), std::string::npos) << noNewline.diff;
    writeGolden(plan_, file);

    // A checkout that turned the line ends into CRLF still matches.
    std::string crlf;
    for (const char ch : goldenText(plan_)) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
    std::ofstream(file, std::ios::binary) << crlf;
    EXPECT_TRUE(compareWithGolden(plan_, file).ok());

    std::ofstream(file, std::ios::binary | std::ios::trunc).flush();  // empty
    EXPECT_EQ(compareWithGolden(plan_, file).status, GoldenStatus::OtherVersion);

    std::ofstream(file, std::ios::binary) << planToText(plan_);  // no header: an older writer
    const GoldenComparison old = compareWithGolden(plan_, file);
    EXPECT_EQ(old.status, GoldenStatus::OtherVersion);
    EXPECT_NE(old.message.find("--update"), std::string::npos) << old.message;

    fs::remove(file);
    fs::create_directories(file);  // a directory where the file should be
    EXPECT_EQ(compareWithGolden(plan_, file).status, GoldenStatus::Unreadable);

    // A FIFO that no one writes: refused at once, where reading it would wait for ever.
    fs::remove(file);
    ASSERT_EQ(::mkfifo(file.c_str(), 0600), 0);
    const GoldenComparison fifo = compareWithGolden(plan_, file);
    EXPECT_EQ(fifo.status, GoldenStatus::Unreadable);
    EXPECT_NE(fifo.message.find("it is not a regular file"), std::string::npos) << fifo.message;
}

TEST_F(GoldenFile, AFailedWriteNamesTheFileAndLeavesNothingBehind) {
    const fs::path file = dir_ / "p.plan.txt";
    fs::create_directories(file / "kept");  // the rename over a directory that is not empty fails
    try {
        writeGolden(plan_, file);
        FAIL() << "wrote over a directory";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    EXPECT_TRUE(fs::is_directory(file / "kept"));
    std::ofstream(dir_ / "plain") << "a file";
    EXPECT_THROW(writeGolden(plan_, dir_ / "plain" / "x.plan.txt"), std::runtime_error);
}

}  // namespace
}  // namespace skygraph
