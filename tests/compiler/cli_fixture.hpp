// The fixture of the command-line tests: runs the built `skygraph` from the source directory
// in a scratch folder of its own, capturing stdout, stderr and the exit status.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <spawn.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace skygraph::cli_test {

namespace fs = std::filesystem;

const fs::path kSource = SKYGRAPH_SOURCE_DIR;
const fs::path kCli = SKYGRAPH_CLI;

struct CliRun {
    int status = -1;
    std::string out;
    std::string err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline std::string quote(const std::string& s) {
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

    /// Runs the CLI with `args`, from the source directory, capturing stdout and stderr;
    /// `shell` runs in the same shell first (`ulimit -f 4;`, `export TMPDIR=...;`).
    CliRun run(const std::vector<std::string>& args, const std::string& shell = "") {
        std::string cmd = "cd " + quote(kSource.string()) + " && " + shell + quote(kCli.string());
        for (const auto& a : args) cmd += " " + quote(a);
        cmd += " >" + quote((dir_ / "stdout").string()) + " 2>" + quote((dir_ / "stderr").string());
        const int raw = std::system(cmd.c_str());
        CliRun r;
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.out = slurp(dir_ / "stdout");
        r.err = slurp(dir_ / "stderr");
        return r;
    }

    /// Starts the CLI in the background from the source directory; stdout and stderr go to
    /// files in the scratch folder. Returns the child's pid.
    pid_t spawn(const std::vector<std::string>& args) {
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, 1, (dir_ / "stdout").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&actions, 2, (dir_ / "stderr").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addchdir_np(&actions, kSource.c_str());
        std::vector<std::string> argv{kCli.string()};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> cargv;
        for (auto& a : argv) cargv.push_back(a.data());
        cargv.push_back(nullptr);
        pid_t pid = -1;
        const int rc = posix_spawn(&pid, kCli.c_str(), &actions, nullptr, cargv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        EXPECT_EQ(rc, 0);
        return pid;
    }

    /// Waits for the child to exit (killing it after `seconds`); its exit status, or -1.
    static int waitExit(pid_t pid, double seconds) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        int raw = 0;
        while (::waitpid(pid, &raw, WNOHANG) == 0) {
            if (std::chrono::steady_clock::now() > deadline) {
                ::kill(pid, SIGKILL);
                ::waitpid(pid, &raw, 0);
                return -1;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    }

    /// Polls `done` until it holds or `seconds` pass.
    static bool waitFor(const std::function<bool()>& done, double seconds) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (!done()) {
            if (std::chrono::steady_clock::now() > deadline) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return true;
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

}  // namespace skygraph::cli_test
