// gpu_frame_bench: what a frame costs on a real GPU, and how close each pass is to the
// memory-bandwidth bound. Prints tables and optionally writes one CSV of every figure.
//
//   gpu_frame_bench --device nvidia --run graphs/raster.json:scenes/default.json
//       --size 1920x1080 --size 3840x2160 --frames 200 --csv gpu.csv
//
// 1. DRAM bandwidth: vkCmdCopyBuffer and a compute copy of a --bandwidth-mib buffer, median
//    of --bandwidth-reps; the faster median is the bandwidth used for the bounds.
// 2. Each --run GRAPH[:SCENE][@VARIANT] at each --size (variants: gpu_frames.hpp): per-pass
//    GPU medians over --frames frames (Renderer::lastTimings) beside bytes / bandwidth.
// 3. Probes at each size (gpu_probes.hpp): the TonemappingPass's operation as compute shaders,
//    and a fragment pass that only writes a constant (the fragment path's own cost).
// Validation is off unless --validate; any validation message then fails the run (exit 1).
#include "gpu_frames.hpp"
#include "gpu_probes.hpp"

#include <skygraph/compiler.hpp>
#include <skygraph/device.hpp>
#include <skygraph/renderer.hpp>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using namespace skygraph;
using namespace skygraph::gpubench;

struct Args {
    std::string device;
    std::vector<std::string> runs;
    std::vector<std::string> procedural;
    std::vector<std::string> sizes;
    uint32_t frames = 200;
    uint32_t warmup = 20;
    uint32_t bandwidthMib = 1024;
    uint32_t bandwidthReps = 50;
    uint32_t probeReps = 200;
    uint32_t evictMib = 256;
    bool noProbes = false;
    bool validate = false;
    std::string csv;
    std::string pngDir;
};

/// One CSV row: section, graph/probe, size, name, type, bytes, median, p10, p90, bound, ratio.
struct Row {
    std::string section, source, size, name, type;
    double bytes = 0, medianMs = 0, p10Ms = 0, p90Ms = 0, boundMs = 0;
};

VkExtent2D parseSize(const std::string& s) {
    unsigned w = 0, h = 0;
    char x = 0;
    std::istringstream in(s);
    if (!(in >> w >> x >> h) || x != 'x' || w == 0 || h == 0 || !in.eof())
        throw std::invalid_argument("--size '" + s + "': expected WIDTHxHEIGHT, e.g. 3840x2160");
    return {w, h};
}

std::string fmt(double v, int decimals = 3) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

void printRow(const Row& r) {
    const double ratio = r.boundMs > 0 ? r.medianMs / r.boundMs : 0;
    std::printf("  %-38s %-16s %10s %10s %10s %9s %10s %8s\n", r.name.c_str(), r.type.c_str(),
                fmt(r.medianMs, 4).c_str(), fmt(r.p10Ms, 4).c_str(), fmt(r.p90Ms, 4).c_str(),
                fmt(r.bytes / 1e6, 1).c_str(), r.boundMs > 0 ? fmt(r.boundMs, 4).c_str() : "-",
                r.boundMs > 0 ? (fmt(ratio, 2) + "x").c_str() : "-");
}

void printHeader(const std::string& title) {
    std::printf("\n%s\n  %-38s %-16s %10s %10s %10s %9s %10s %8s\n", title.c_str(), "pass/probe", "type",
                "median ms", "p10 ms", "p90 ms", "MB moved", "bound ms", "/bound");
}

void writeCsv(const std::string& path, const std::string& deviceName, double bandwidth, const std::vector<Row>& rows) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp);
        out << "# device: " << deviceName << "; bandwidth used for bounds: " << fmt(bandwidth, 1) << " GB/s\n";
        out << "section,source,size,name,type,bytes,median_ms,p10_ms,p90_ms,bound_ms,ratio\n";
        for (const Row& r : rows) {
            out << r.section << ',' << r.source << ',' << r.size << ',' << r.name << ',' << r.type << ','
                << fmt(r.bytes, 0) << ',' << fmt(r.medianMs, 5) << ',' << fmt(r.p10Ms, 5) << ','
                << fmt(r.p90Ms, 5) << ',' << fmt(r.boundMs, 5) << ','
                << fmt(r.boundMs > 0 ? r.medianMs / r.boundMs : 0, 3) << '\n';
        }
        if (!out) throw std::runtime_error("cannot write " + tmp);
    }
    std::rename(tmp.c_str(), path.c_str());  // never a half-written CSV
}

int run(const Args& args) {
    std::vector<VkExtent2D> sizes;
    for (const auto& s : args.sizes.empty() ? std::vector<std::string>{"1920x1080", "3840x2160"} : args.sizes)
        sizes.push_back(parseSize(s));

    DeviceOptions dopts;
    dopts.device = args.device;
    dopts.validation = args.validate;
    if (!args.pngDir.empty()) std::filesystem::create_directories(args.pngDir);
    auto device = Device::create(dopts);
    std::printf("device: %s (timestamp period %.3f ns)%s\n", device->name().c_str(), device->timestampPeriodNs(),
                args.validate ? ", validation on" : "");
    std::vector<Row> rows;

    double bandwidth = 0;  // GB/s
    if (args.bandwidthMib > 0) {
        printHeader("DRAM bandwidth (" + std::to_string(args.bandwidthMib) + " MiB buffers, " +
                    std::to_string(args.bandwidthReps) + " repetitions; bytes = read + written)");
        for (const ProbeResult& p : measureBandwidth(*device, uint64_t(args.bandwidthMib) << 20, args.bandwidthReps)) {
            Row r{"bandwidth", "buffer", std::to_string(args.bandwidthMib) + "MiB", p.name, "copy",
                  p.bytes, p.medianMs, p.p10Ms, p.p90Ms, 0};
            printRow(r);
            std::printf("  %-38s %.1f GB/s\n", "", p.gigabytesPerSecond());
            bandwidth = std::max(bandwidth, p.gigabytesPerSecond());
            rows.push_back(r);
        }
        std::printf("  bandwidth used for the bounds: %.1f GB/s (the faster median)\n", bandwidth);
    }
    const auto boundMs = [&](double bytes) { return bandwidth > 0 ? bytes / (bandwidth * 1e6) : 0.0; };

    for (const std::string& spec : args.runs) {
        FrameCase c;
        std::string rest = spec;
        if (const auto at = rest.find('@'); at != std::string::npos) {
            c.variant = rest.substr(at + 1);
            rest = rest.substr(0, at);
        }
        const auto colon = rest.find(':');
        c.graph = rest.substr(0, colon);
        if (colon != std::string::npos) c.scene = rest.substr(colon + 1);
        c.frames = args.frames;
        c.warmupFrames = args.warmup;
        c.proceduralExternals = args.procedural;
        for (const VkExtent2D size : sizes) {
            c.width = size.width;
            c.height = size.height;
            if (!args.pngDir.empty()) {
                std::string name = c.graph.stem().string() + (c.scene.empty() ? "" : "-" + c.scene.stem().string()) +
                                   (c.variant.empty() ? "" : "-" + c.variant) + "-" + std::to_string(size.width) + "x" +
                                   std::to_string(size.height) + ".png";
                c.png = std::filesystem::path(args.pngDir) / name;
            }
            const FrameResult f = measureFrames(*device, c);
            const std::string sizeText = std::to_string(size.width) + "x" + std::to_string(size.height);
            printHeader(spec + " at " + sizeText + ", median of " + std::to_string(f.frames) + " frames");
            double sum = 0;
            for (const PassResult& p : f.passes) {
                Row r{"pass", spec, sizeText, p.pass, p.type, p.bytes, p.medianMs, p.p10Ms, p.p90Ms, boundMs(p.bytes)};
                printRow(r);
                if (!p.attachments.empty()) std::printf("  %-38s attachments: %s\n", "", p.attachments.c_str());
                rows.push_back(r);
                sum += p.medianMs;
            }
            Row frame{"frame", spec, sizeText, "(whole frame)", f.hostTimed ? "host, queues" : "recordInto", 0,
                      f.frameMedianMs, 0, 0, 0};
            printRow(frame);
            rows.push_back(frame);
            std::printf("  sum of pass medians: %.4f ms\n", sum);
            for (const auto& culled : f.culled) std::printf("  culled %s\n", culled.c_str());
            for (const auto& name : f.proceduralExternals) std::printf("  %s: procedural HDR sky\n", name.c_str());
        }
    }

    if (!args.noProbes) {
        for (const VkExtent2D size : sizes) {
            const std::string sizeText = std::to_string(size.width) + "x" + std::to_string(size.height);
            printHeader("probes at " + sizeText + ": compute tonemap (RGBA16F in, RGBA8 out, L2 evicted before "
                        "each), fragment constant fill (RGBA8); median of " + std::to_string(args.probeReps));
            std::vector<ProbeResult> probes = measureComputeTonemap(*device, size.width, size.height, args.probeReps,
                                                                   uint64_t(args.evictMib) << 20);
            probes.push_back(measureFragmentFill(*device, size.width, size.height, args.probeReps));
            for (const ProbeResult& p : probes) {
                const std::string kind = p.name.rfind("fragment", 0) == 0 ? "fragment" : "compute";
                Row r{"probe", kind, sizeText, p.name, kind, p.bytes, p.medianMs, p.p10Ms, p.p90Ms,
                      boundMs(p.bytes)};
                printRow(r);
                rows.push_back(r);
            }
        }
    }

    if (!args.csv.empty()) writeCsv(args.csv, device->name(), bandwidth, rows);
    if (device->validationEnabled() && device->messageCount() > 0) {
        std::cerr << "gpu_frame_bench: validation reported " << device->messageCount() << " message(s)\n";
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"gpu_frame_bench: per-pass GPU times against the memory-bandwidth bound"};
    Args args;
    app.add_option("--device", args.device, "Physical device: index or name substring (e.g. nvidia, llvmpipe)");
    app.add_option("--run", args.runs,
                   "GRAPH[:SCENE][@VARIANT] to render (repeatable); VARIANT: unorm-swapchain, compute-tonemap");
    app.add_option("--png-dir", args.pngDir,
                   "Also write each run's last frame as PNG here (adds a read-back copy to every frame)");
    app.add_option("--procedural", args.procedural,
                   "External image to fill with a procedural HDR sky before the first frame, where a "
                   "run's graph has it (repeatable; e.g. equirect for graphs/ibl.json)");
    app.add_option("--size", args.sizes, "Output WIDTHxHEIGHT (repeatable; default 1920x1080 and 3840x2160)");
    app.add_option("--frames", args.frames, "Measured frames per run and size")->check(CLI::PositiveNumber);
    app.add_option("--warmup", args.warmup, "Frames rendered before measuring");
    app.add_option("--bandwidth-mib", args.bandwidthMib, "Size of each bandwidth buffer in MiB (0: skip)");
    app.add_option("--bandwidth-reps", args.bandwidthReps, "Repetitions of each bandwidth copy")->check(CLI::PositiveNumber);
    app.add_option("--probe-reps", args.probeReps, "Repetitions of each tonemap probe")->check(CLI::PositiveNumber);
    app.add_option("--evict-mib", args.evictMib, "Buffer read before each tonemap probe to empty the L2 (MiB)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--no-probes", args.noProbes, "Skip the compute tonemap and fragment fill probes");
    app.add_flag("--validate", args.validate, "Validation + synchronization validation; fail on any message");
    app.add_option("--csv", args.csv, "Write every figure to this CSV file");
    CLI11_PARSE(app, argc, argv);
    spdlog::set_level(spdlog::level::warn);
    try {
        return run(args);
    } catch (const GraphError& e) {
        std::cerr << e.diagnostics().format() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "gpu_frame_bench: " << e.what() << "\n";
        return 1;
    }
}
