// The SPIR-V disk cache (framework/executor/spirv_cache.hpp) through ShaderCompiler: reused
// across compiler instances, invalidated by an edited include, and a damaged or foreign
// entry is a miss, never a wrong shader. No device.
#include "spirv_cache.hpp"

#include <skygraph/device.hpp>
#include <skygraph/pipeline_builder.hpp>
#include <skygraph/shader_compiler.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <unistd.h>

namespace skygraph::test {
namespace {

namespace fs = std::filesystem;

class SpirvCacheTest : public ::testing::Test {
protected:
    void SetUp() override {
        root = fs::temp_directory_path() / ("skygraph-spirv-cache-" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root / "include");
        writeInclude("float scale() { return 2.0; }\n");
    }
    void TearDown() override { fs::remove_all(root); }

    void writeInclude(const std::string& text) const { std::ofstream(root / "include" / "lib.glsl") << text; }
    [[nodiscard]] std::vector<fs::path> entries() const {
        std::vector<fs::path> out;
        if (fs::exists(root / "cache"))
            for (const auto& e : fs::directory_iterator(root / "cache")) out.push_back(e.path());
        return out;
    }
    /// Compiles kShader with a fresh compiler (an empty memory cache, as in a new process).
    std::pair<std::vector<uint32_t>, uint32_t> compileFresh() const {
        ShaderCompiler compiler(root / "include", root / "cache");
        auto spirv = compiler.compile(VK_SHADER_STAGE_COMPUTE_BIT, kShader, "cached.comp");
        return {std::move(spirv), compiler.compilations()};
    }

    static constexpr const char* kShader =
        "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"lib.glsl\"\n"
        "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer B { float v; };\n"
        "void main() { v = scale(); }\n";
    fs::path root;
};

TEST_F(SpirvCacheTest, ASecondProcessReusesTheEntry) {
    const auto [first, firstRuns] = compileFresh();
    EXPECT_EQ(firstRuns, 1u);
    ASSERT_EQ(entries().size(), 1u) << "one whole entry, no temporary left behind";
    const auto [second, secondRuns] = compileFresh();
    EXPECT_EQ(secondRuns, 0u) << "glslang did not run";
    EXPECT_EQ(second, first);
}

TEST_F(SpirvCacheTest, AnEditedIncludeIsCompiledAgain) {
    const auto [before, runs] = compileFresh();
    writeInclude("float scale() { return 3.0; }\n");
    const auto [after, againRuns] = compileFresh();
    EXPECT_EQ(againRuns, 1u) << "the include changed, so the entry is stale";
    EXPECT_NE(after, before);
    writeInclude("float scale() { return oops; }\n");
    EXPECT_THROW((void)compileFresh(), ExecutorError) << "a broken include is an error, not the old shader";
}

// An include cycle without a guard was expanded until memory ran out (a hot reload of such an
// edit froze the application): it is an error, naming the file, as any broken include is.
TEST_F(SpirvCacheTest, AnIncludeCycleIsAnError) {
    writeInclude("#include \"lib.glsl\"\n");
    try {
        (void)compileFresh();
        FAIL() << "a file including itself compiled";
    } catch (const ExecutorError& e) {
        EXPECT_NE(std::string(e.what()).find("#include nested deeper than 64 levels at 'lib.glsl'"), std::string::npos)
            << e.what();
    }
    // A guarded one is the usual way to include a file twice, and compiles.
    writeInclude("#ifndef LIB\n#define LIB\n#include \"lib.glsl\"\nfloat scale() { return 1.0; }\n#endif\n");
    EXPECT_NO_THROW((void)compileFresh());
}

// A compiler includes each file as it first read it, like its top-level sources, until clear():
// a new variant compiled while an include is edited (or broken) on disk uses the kept text,
// and a disk cache entry made from the edited include is not taken for it.
TEST_F(SpirvCacheTest, IncludedFilesAreKeptUntilClear) {
    ShaderCompiler kept(root / "include", root / "cache");
    (void)kept.compile(VK_SHADER_STAGE_COMPUTE_BIT, kShader, "cached.comp");
    const std::string variant = std::string(kShader) + "// another variant\n";
    writeInclude("float scale() { return 3.0; }\n");
    const std::vector<uint32_t> edited =
        ShaderCompiler(root / "include", root / "cache").compile(VK_SHADER_STAGE_COMPUTE_BIT, variant, "v.comp");
    writeInclude("float scale() { return oops; }\n");
    const std::vector<uint32_t> fromKept = kept.compile(VK_SHADER_STAGE_COMPUTE_BIT, variant, "v.comp");
    EXPECT_NE(fromKept, edited) << "the disk cache's entry for the edited include was taken";
    writeInclude("float scale() { return 2.0; }\n");
    EXPECT_EQ(fromKept, ShaderCompiler(root / "include").compile(VK_SHADER_STAGE_COMPUTE_BIT, variant, "v.comp"))
        << "not compiled from the include as first read";
    writeInclude("float scale() { return oops; }\n");
    kept.clear();
    EXPECT_THROW((void)kept.compile(VK_SHADER_STAGE_COMPUTE_BIT, variant, "v.comp"), ExecutorError)
        << "clear() reads the include again";
}

// keptFilesChanged() answers for the files this compiler read, sources and includes, and for
// no other file of the folder.
TEST_F(SpirvCacheTest, KeptFilesChangedSeesEditsToWhatWasReadOnly) {
    std::ofstream(root / "include" / "main.comp") << kShader;
    std::ofstream(root / "include" / "other.comp") << kShader;
    ShaderCompiler compiler(root / "include");
    EXPECT_FALSE(compiler.keptFilesChanged()) << "nothing read yet";
    (void)compiler.compileFile(VK_SHADER_STAGE_COMPUTE_BIT, "main.comp");
    EXPECT_FALSE(compiler.keptFilesChanged());
    std::ofstream(root / "include" / "other.comp", std::ios::app) << "// an edit elsewhere\n";
    EXPECT_FALSE(compiler.keptFilesChanged()) << "a file it never read";
    writeInclude("float scale() { return 2.5; }\n");
    EXPECT_TRUE(compiler.keptFilesChanged()) << "an include it read";
    writeInclude("float scale() { return 2.0; }\n");
    EXPECT_FALSE(compiler.keptFilesChanged()) << "the include as first read again";
    std::ofstream(root / "include" / "main.comp", std::ios::app) << "// an edit\n";
    EXPECT_TRUE(compiler.keptFilesChanged()) << "the source it read";
    compiler.clear();
    EXPECT_FALSE(compiler.keptFilesChanged()) << "clear() keeps nothing";
    (void)compiler.compileFile(VK_SHADER_STAGE_COMPUTE_BIT, "main.comp");
    fs::remove(root / "include" / "lib.glsl");
    EXPECT_FALSE(compiler.keptFilesChanged()) << "renamed away mid-save";
    writeInclude("");
    EXPECT_FALSE(compiler.keptFilesChanged()) << "truncated mid-save";
    writeInclude("float scale() { return 2.5; }\n");
    EXPECT_TRUE(compiler.keptFilesChanged()) << "saved";
}

TEST_F(SpirvCacheTest, DamagedEntriesAreMisses) {
    const auto [good, runs] = compileFresh();
    ASSERT_EQ(entries().size(), 1u);
    const fs::path entry = entries().front();
    for (const auto size : {uintmax_t(0), uintmax_t(10), fs::file_size(entry) - 4, fs::file_size(entry) - 1}) {
        SCOPED_TRACE(size);
        (void)compileFresh();  // rewrite a whole entry
        fs::resize_file(entry, size);
        const auto [again, compiled] = compileFresh();
        EXPECT_EQ(compiled, 1u) << "a truncated entry is recompiled";
        EXPECT_EQ(again, good);
    }
    // An entry for another key stored under this key's name (a hash collision) is a miss.
    const SpirvDiskCache cache(root / "cache");
    fs::remove(entry);
    cache.store("another key", {}, good);
    fs::rename(entries().front(), entry);
    EXPECT_EQ(compileFresh().second, 1u);
}

TEST_F(SpirvCacheTest, AnEmptyDirectoryDisablesIt) {
    const SpirvDiskCache disabled{fs::path{}};
    disabled.store("key", {}, {0x07230203u, 1u});
    EXPECT_FALSE(disabled.find("key", {}));
    ShaderCompiler memoryOnly(root / "include");
    (void)memoryOnly.compile(VK_SHADER_STAGE_COMPUTE_BIT, kShader, "memory.comp");
    EXPECT_TRUE(entries().empty());
}

// compileShader's defines go right after #version, which a licence comment may precede (above
// it they would be an error: #version must come first), and they take effect.
TEST_F(SpirvCacheTest, CompileShaderDefinesFollowTheVersionAfterAComment) {
    std::ofstream(root / "include" / "licensed.comp")
        << "// SPDX-License-Identifier: MIT\n\n  #version 450\n"
           "#extension GL_GOOGLE_include_directive : require\n"
           "layout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer B { float v; };\n"
           "void main() { v = VALUE; }\n";
    ShaderCompiler compiler(root / "include", {});
    std::vector<uint32_t> one, two;
    ASSERT_NO_THROW(one = compileShader(compiler, VK_SHADER_STAGE_COMPUTE_BIT, "licensed.comp", {{"VALUE", "1.0"}}));
    ASSERT_NO_THROW(two = compileShader(compiler, VK_SHADER_STAGE_COMPUTE_BIT, "licensed.comp", {{"VALUE", "2.0"}}));
    EXPECT_NE(one, two);
    EXPECT_THROW((void)compileShader(compiler, VK_SHADER_STAGE_COMPUTE_BIT, "licensed.comp"), ExecutorError)
        << "VALUE is defined only by the caller";
}

TEST(SpirvCacheHash, IsFnv1a) {
    EXPECT_EQ(SpirvDiskCache::hash(""), 0xcbf29ce484222325ull);
    EXPECT_EQ(SpirvDiskCache::hash("a"), 0xaf63dc4c8601ec8cull);  // published FNV-1a 64 test vector
}

}  // namespace
}  // namespace skygraph::test
