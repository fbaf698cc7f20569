// `skygraph sky-sequence`: see sky_sequence_command.hpp.
#include "sky_sequence_command.hpp"

#include "app/procedural_environment.hpp"
#include "printable_name.hpp"
#include "replace_file.hpp"

#include <skygraph/hdr_image.hpp>
#include <skygraph/scene.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <memory>
#include <system_error>

namespace skygraph::cli {
namespace {

struct SkySequenceArgs {
    std::string pattern;
    uint32_t frames = 48;
    uint32_t width = 1024;
};

/// An equirect is twice as wide as it is tall, so its width is even: 3 would make a 3x1 image.
const CLI::Validator kEvenWidth(
    [](const std::string& value) {
        uint32_t width = 0;
        if (!CLI::detail::lexical_cast(value, width) || width % 2 == 0) return std::string();
        return value + " is odd: an equirect is twice as wide as it is tall, so its width must be even";
    },
    "EVEN");

int run(const SkySequenceArgs& args) {
    if (const std::string problem = sequencePatternProblem(std::filesystem::path(args.pattern).filename().string());
        !problem.empty())
        throw UsageError("skygraph sky-sequence: '" + printableName(args.pattern) + "': its file name " + problem);
    // Every other command refuses an output in a folder that does not exist (a typo in it would
    // otherwise make folders), and so does this one, before any frame is drawn: every frame's,
    // since a later one may be a link into another folder.
    const std::filesystem::path firstFrame = sequenceFrameFile(args.pattern, 0);
    for (uint32_t i = 0; i < args.frames; ++i) {
        const std::filesystem::path frame = sequenceFrameFile(args.pattern, i);
        try {
            (void)files::writableOutputTarget(frame);
        } catch (const std::filesystem::filesystem_error& e) {
            throw ImageError(frame, "cannot write: " + files::whyNotWritten(e));
        }
    }
    // A reader plays a sequence up to its first missing frame: an earlier, longer run's frames
    // past this one's would play on after it as if they were its own.
    const std::filesystem::path next = sequenceFrameFile(args.pattern, args.frames);
    std::error_code ec;
    if (std::filesystem::exists(std::filesystem::symlink_status(next, ec)))
        throw ImageError(next, "exists, and a sequence plays on to its first missing frame: frames from " +
                                   std::to_string(args.frames) +
                                   " on, left from an earlier run, would follow these; remove them first");
    app::writeProceduralSkySequence(args.pattern, args.frames, args.width);
    std::cout << "skygraph sky-sequence: " << args.frames << (args.frames == 1 ? " frame" : " frames") << " of "
              << args.width << "x" << args.width / 2 << ", " << printableName(firstFrame.string());
    if (args.frames > 1)
        std::cout << " to " << printableName(sequenceFrameFile(args.pattern, args.frames - 1).string());
    std::cout << "\n";
    return kExitOk;
}

}  // namespace

Command addSkySequenceCommand(CLI::App& parent) {
    auto args = std::make_shared<SkySequenceArgs>();
    CLI::App* cmd = parent.add_subcommand(
        "sky-sequence", "Write a time-lapse of the procedural sky as equirect frames (its sun circles the sky once), "
                        "for an environment sequence: PATTERN holds the frame number as %d or %0Nd, e.g. frames/%04d.exr");
    cmd->add_option("pattern", args->pattern, "Frame files, .hdr or .exr, numbered from 0")->required()->check(kNotEmpty);
    cmd->add_option("--frames", args->frames, "How many frames")->check(CLI::Range(1u, 100000u))->capture_default_str();
    cmd->add_option("--width", args->width, "Equirect width, even; the height is half")
        ->check(CLI::Range(2u, 16384u))->check(kEvenWidth)->capture_default_str();
    return {cmd, [args] { return run(*args); }};
}

}  // namespace skygraph::cli
