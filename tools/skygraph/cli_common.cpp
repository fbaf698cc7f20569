#include "cli_common.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/diagnostics.hpp>

#include "printable_name.hpp"
#include "replace_file.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace skygraph::cli {

std::optional<LayoutPolicy> parseLayoutsFlag(const std::string& text) {
    if (text.empty()) return std::nullopt;
    if (const auto policy = parseLayoutPolicy(text)) return policy;
    throw UsageError("--layouts " + text + ": expected fewest-barriers or optimal");
}

std::array<uint32_t, kQueueKinds> parseQueueFamiliesFlag(const std::string& text) {
    if (text.empty()) return CompileOptions{}.queueFamilies;
    if (text == "one") return {0, 0, 0};
    if (text == "separate") return {0, 1, 2};
    throw UsageError("--queue-families " + text + ": expected separate or one");
}

FeatureValues parseFeatureFlags(const std::vector<std::string>& flags, std::string_view option) {
    FeatureValues out;
    for (const auto& f : flags) {
        const auto eq = f.find('=');
        const std::string value = eq == std::string::npos ? "" : f.substr(eq + 1);
        if (eq == 0 || eq == std::string::npos || (value != "on" && value != "off"))
            throw UsageError(std::string(option) + " expects NAME=on or NAME=off, got '" + printableName(f) + "'");
        if (!out.emplace(f.substr(0, eq), value == "on").second)
            throw UsageError(std::string(option) + " gives feature '" + printableName(f.substr(0, eq)) + "' twice");
    }
    return out;
}

std::string whyNotANumber(std::string& value, bool whole) {
    const bool negative = !value.empty() && value[0] == '-';
    const std::string_view digits = std::string_view(value).substr(negative ? 1 : 0);
    const auto isDigit = [](char c) { return c >= '0' && c <= '9'; };
    const bool decimalWhole = !digits.empty() && std::all_of(digits.begin(), digits.end(), isDigit);
    if (decimalWhole) {
        const size_t zeros = std::min(digits.find_first_not_of('0'), digits.size() - 1);
        value.erase(negative ? 1 : 0, zeros);
        return {};
    }
    // A fraction or an exponent, in decimal: no hexadecimal float, no space, no "inf".
    const bool decimal = !digits.empty() && isDigit(digits.back()) &&
                         digits.find_first_not_of("0123456789.eE+-") == std::string_view::npos &&
                         (isDigit(digits[0]) || digits[0] == '.');
    double number = 0.0;
    if (!decimal || !CLI::detail::lexical_cast(value, number)) return "'" + value + "' is not a number";
    // "1e3" is a thousand, but a count is written in digits alone.
    if (whole) return "'" + value + "' is not a whole number in decimal digits";
    return {};
}

namespace {

/// CLI11's name of the type of an option's value ("UINT", "INT", "FLOAT", "TEXT"; "" for a
/// flag): what get_type_name() gives before the descriptions of its validators.
std::string valueTypeName(const CLI::Option& option) {
    const std::string full = option.get_type_name();
    return full.substr(0, full.find(':'));
}

/// whyNotANumber() as a validator: it describes nothing, so that --help shows the option as before.
CLI::Validator numberCheck(bool whole) {
    return CLI::Validator([whole](std::string& value) { return whyNotANumber(value, whole); }, "");
}

}  // namespace

void refuseValuesThatAreNotNumbers(CLI::App& app) {
    for (CLI::Option* option : app.get_options()) {
        const std::string type = valueTypeName(*option);
        // A transform runs before the checks, the range among them.
        if (type == "UINT" || type == "INT") option->transform(numberCheck(true));
        else if (type == "FLOAT") option->transform(numberCheck(false));
    }
    for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
        refuseValuesThatAreNotNumbers(*command);
}

CLI::Option* addFlagSettingFalse(CLI::App& command, const std::string& name, bool& setting,
                                 const std::string& description) {
    return command.add_flag_callback(name, [&setting] { setting = false; }, description);
}

void refuseToOverwriteInputs(std::string_view option, const std::filesystem::path& output,
                             const std::vector<std::filesystem::path>& inputs) {
    if (const auto input = files::sameFileAmong(output, inputs))
        throw std::runtime_error(std::string(option) + " '" + printableName(output.string()) + "' is the input '" +
                                 printableName(input->string()) + "': it would be overwritten");
}

void requireWritableOutput(const std::string& path) {
    try {
        (void)files::writableOutputTarget(path);
    } catch (const std::filesystem::filesystem_error& e) {
        throw std::runtime_error("cannot write '" + printableName(path) + "': " + files::whyNotWritten(e));
    }
}

void writeOutput(const std::string& path, const std::string& text) {
    if (path.empty()) {
        std::cout << text << std::flush;
        return;
    }
    try {
        files::replaceFileContents(path, text);
    } catch (const std::filesystem::filesystem_error& e) {
        throw std::runtime_error("cannot write '" + printableName(path) + "': " + files::whyNotWritten(e));
    }
}

void configureLogging(bool verbose, bool quiet) {
    auto logger = spdlog::stderr_color_mt("skygraph");
    logger->set_pattern("%^%l%$: %v");
    spdlog::set_default_logger(std::move(logger));
    spdlog::set_level(quiet ? spdlog::level::err : verbose ? spdlog::level::debug : spdlog::level::info);
}

int reportCurrentException() {
    try {
        throw;
    } catch (const GraphError& e) {
        for (const auto& d : e.diagnostics().items()) std::cerr << "error: " << d.format() << "\n";
        return kExitUserError;
    } catch (const UsageError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return kExitUserError;
    }
}

int runGuarded(const std::function<int()>& body) {
    int status = kExitOk;
    try {
        status = body();
    } catch (...) {
        status = reportCurrentException();
    }
    // A plan printed to a full disk or a closed pipe is not a success.
    if (!std::cout.flush() && status == kExitOk) {
        std::cerr << "error: cannot write to standard output\n";
        return kExitUserError;
    }
    return status;
}

}  // namespace skygraph::cli
