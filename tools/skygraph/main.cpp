// The skygraph command line (docs/graph-format.md, "Command line"). Exit status: 0 success,
// 1 user error (message on stderr, nothing half-written), 2 misuse of the command line. Each
// subcommand lives in its own x_command.{hpp,cpp} and is listed once below (see cli_common.hpp).
#include "cli_common.hpp"
#include "compile_command.hpp"
#include "pending_temporaries.hpp"
#include "printable_name.hpp"
#include "progress_bar.hpp"
#if SKYGRAPH_HAS_EXECUTOR
#include "render_command.hpp"
#include "check_command.hpp"
#include "cubemap_command.hpp"
#include "sky_sequence_command.hpp"
#include "view_command.hpp"
#endif

#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <csignal>
#include <iostream>
#include <string>
#include <vector>

using namespace skygraph::cli;

namespace {

/// A signal that ends the process ends it as it would have, without the hidden temporary of a
/// write in progress (`view` and `compile --watch` stop on SIGINT and SIGTERM on their own).
extern "C" void removeTemporariesAndEnd(int signal) {
    skygraph::files::removePendingTemporaries();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

/// A standard descriptor the parent closed (`>&-`) is the number the next file opened takes:
/// a plan for standard output went into the temporary of another output, and log lines into a
/// shader cache's file. Each is held by /dev/null, opened the other way round, so that using
/// it fails as using a closed one does (files:: refuses its /dev/stdout and /dev/fd/N names).
void holdClosedStandardDescriptors() {
    for (const int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) {
        if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
        const int held = ::open("/dev/null", fd == STDIN_FILENO ? O_WRONLY : O_RDONLY);
        if (held < 0 || held == fd) continue;
        ::dup2(held, fd);
        ::close(held);
    }
}

}  // namespace

int main(int argc, char** argv) {
    holdClosedStandardDescriptors();
    // A signal the parent had ignored (nohup's SIGHUP, a background job's SIGINT) stays ignored.
    for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
        struct sigaction previous {};
        if (::sigaction(signal, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
        struct sigaction ending {};
        ending.sa_handler = removeTemporariesAndEnd;
        sigemptyset(&ending.sa_mask);
        ::sigaction(signal, &ending, nullptr);
    }
    CLI::App app{"skygraph: a data-driven Vulkan render graph"};
    app.require_subcommand(1);
    app.fallthrough();  // -v, -q and --progress also after the subcommand's name
    app.set_version_flag("--version", "skygraph 0.1.0");
    bool verbose = false, quiet = false;
    std::string progress = "auto";
    CLI::Option* verboseFlag = app.add_flag("-v,--verbose", verbose, "Log debug messages");
    app.add_flag("-q,--quiet", quiet, "Log errors only (and draw no progress bars)")->excludes(verboseFlag);
    app.add_option("--progress", progress, "Progress bars on stderr: auto (when it is a terminal), always, never")
        ->check(CLI::IsMember({"auto", "always", "never"}));

    const std::vector<Command> commands{
        addCompileCommand(app),
#if SKYGRAPH_HAS_EXECUTOR
        addRenderCommand(app),
        addCheckCommand(app),
        addCubemapCommand(app),
        addViewCommand(app),
        addSkySequenceCommand(app),
#endif
    };
    refuseValuesThatAreNotNumbers(app);

    // CLI11 would answer an unknown command with "A subcommand is required": name it instead.
    if (argc > 1 && argv[1][0] != '-') {
        std::string known;
        bool found = false;
        for (const Command& command : commands) {
            found = found || command.app->get_name() == argv[1];
            known += (known.empty() ? "" : ", ") + command.app->get_name();
        }
        if (!found) {
            std::cerr << "error: unknown command '" << skygraph::printableName(argv[1]) << "'; commands: " << known << "\n";
            return kExitUsage;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Help and the version are CLI11's to print; a mistake is shown as every other error is,
        // the words the command line gave escaped.
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e) == 0 ? kExitOk : kExitUsage;
        std::cerr << "error: " << skygraph::printableName(e.what()) << "\nRun with --help for more information.\n";
        return kExitUsage;
    }
    configureLogging(verbose, quiet);
    const ProgressMode mode = progress == "always" ? ProgressMode::Always
                              : progress == "never" ? ProgressMode::Never
                                                    : ProgressMode::Auto;
    ProgressBar::setMode(quiet ? ProgressMode::Never : mode);

    for (const Command& command : commands)
        if (command.app->parsed()) return runGuarded(command.run);
    return kExitUsage;
}
