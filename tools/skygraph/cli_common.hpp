// Pieces every skygraph subcommand shares: how a subcommand plugs into main(), feature
// flags, safe output, logging and error reporting with the command line's exit statuses
// (docs/graph-format.md, "Command line").
//
// Adding a subcommand: write x_command.{hpp,cpp} with `Command addXCommand(CLI::App& parent)`
// that adds a CLI11 subcommand (its own --help comes with it), keeps its parsed arguments
// alive in the returned `run` closure, and returns both; then add one line to main.cpp's
// list of commands. Long work shows a ProgressBar (progress_bar.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include <skygraph/condition.hpp>
#include <skygraph/graph.hpp>

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace CLI {
class App;
}

namespace skygraph::cli {

/// Exit statuses of the command line (docs/graph-format.md, "Command line").
enum ExitStatus : int { kExitOk = 0, kExitUserError = 1, kExitUsage = 2 };

/// A command-line mistake: exit status 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// One subcommand: `app` is owned by the parent CLI::App; main() calls `run` when `app` was
/// parsed, through runGuarded. `run` returns an ExitStatus.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

/// --queue-families: "separate" (or not given): graphics, compute and transfer queues of three
/// families; "one": every queue kind in one family (a device of one queue family).
[[nodiscard]] std::array<uint32_t, kQueueKinds> parseQueueFamiliesFlag(const std::string& text);
/// --layouts: "fewest-barriers" or "optimal" -> the policy, "" (not given) -> unset (the graph
/// file's setting). Throws UsageError for anything else.
[[nodiscard]] std::optional<LayoutPolicy> parseLayoutsFlag(const std::string& text);

/// "NAME=on|off" strings -> values. Throws UsageError on bad syntax, naming `option`.
[[nodiscard]] FeatureValues parseFeatureFlags(const std::vector<std::string>& flags,
                                              std::string_view option = "--feature");

/// For options that name a file or a device: given empty (`-o ""`), they would silently mean
/// their default; CLI11 then refuses them as misuse (exit 2).
inline const CLI::Validator kNotEmpty(
    [](const std::string& value) { return value.empty() ? std::string("must not be empty") : std::string(); },
    "NOT EMPTY");

/// Why `value` is not a number as the command line takes one, or "" when it is: written in
/// decimal ("0x20" and " 64" are not numbers), and with `whole` in decimal digits alone, after
/// a '-' ("1.5" and "1e3" are not whole numbers in decimal digits). Strips a whole number's
/// leading zeros, which CLI11 would read as octal ("010" is ten, not 8), as it reads "0x" as
/// hexadecimal. The message quotes `value` as it is: printableName() it for a terminal.
[[nodiscard]] std::string whyNotANumber(std::string& value, bool whole);

/// Makes every numeric option of `app` and of its subcommands say that a value such as "abc" is
/// not a number ("--width: 'abc' is not a number"), and that "1.5" given for a count is not a
/// whole number, before any range check: CLI11's Range calls such a value out of range, and an
/// option without one fails with "Could not convert". Call once, after every option is added.
void refuseValuesThatAreNotNumbers(CLI::App& app);

/// Adds a flag that sets `setting` to false when given (--no-alias for aliasing). `setting`
/// must outlive parsing. CLI11's own form of it, "!--no-alias", would show in --help as
/// "--no-alias{false}".
CLI::Option* addFlagSettingFalse(CLI::App& command, const std::string& name, bool& setting,
                                 const std::string& description);

/// Throws std::runtime_error (exit 1) when `output`, given as `option`, is the same file as one
/// of `inputs`: writing it would destroy what the command reads. Empty names are skipped.
void refuseToOverwriteInputs(std::string_view option, const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs);

/// Throws std::runtime_error naming `path` unless writeOutput() could write it (a file in an
/// existing folder, not a folder): checked before the work, so that a mistyped path costs none.
void requireWritableOutput(const std::string& path);

/// Writes `text` to `path` (stdout when empty) with files::replaceFileContents: a failure never
/// leaves half a file behind, a link's target gets the text, and a FIFO or device is written.
void writeOutput(const std::string& path, const std::string& text);

/// Logs to stderr (stdout carries plans) at debug (-v), error (-q) or info level.
void configureLogging(bool verbose, bool quiet);

/// Prints the exception in flight (call from a catch block) to stderr, every diagnostic of a
/// GraphError on its own line, and returns its exit status: 2 for UsageError, else 1.
[[nodiscard]] int reportCurrentException();

/// Runs a subcommand, turning exceptions into those exit statuses and messages.
[[nodiscard]] int runGuarded(const std::function<int()>& body);

}  // namespace skygraph::cli
