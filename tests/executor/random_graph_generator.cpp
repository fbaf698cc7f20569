// The random graph generator: valid by construction, so that every graph it writes must
// compile and run silently; a rejection is a generator or compiler bug, never noise.
#include "random_graph_generator.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <optional>
#include <random>
#include <set>
#include <sstream>

namespace skygraph::test {
namespace {

enum class Kind : uint8_t { Color, Depth, Cube, Array, Buffer };

struct Resource {
    std::string name;
    Kind kind = Kind::Color;
    uint32_t width = 0;  ///< Mip 0, resolved at the shape's output size.
    uint32_t height = 0;
    uint32_t mips = 1;
    uint32_t layers = 1;
    bool storage = true;  ///< The format can be a storage image.
    bool integer = false;  ///< Of an integer format: cleared to integers.
};

struct Range {
    uint32_t baseMip = 0, mipCount = 1, baseLayer = 0, layerCount = 1;
    bool overlaps(const Range& o) const {
        return baseMip < o.baseMip + o.mipCount && o.baseMip < baseMip + mipCount &&
               baseLayer < o.baseLayer + o.layerCount && o.baseLayer < baseLayer + layerCount;
    }
};

/// Access@Stage[@as] with the kinds of resource it applies to.
struct UsageForm {
    const char* access;
    const char* stage;
    const char* as;  ///< "" for the default binding.
    bool attachment;
    bool needsStorage;
};

const std::vector<UsageForm>& imageForms() {
    static const std::vector<UsageForm> f = {
        {"Write", "ColorAttachment", "", true, false},   {"ReadWrite", "ColorAttachment", "", true, false},
        {"Read", "Vertex", "", false, false},            {"Read", "Fragment", "", false, false},
        {"Read", "Compute", "", false, false},           {"Read", "Fragment", "storage", false, true},
        {"Write", "Fragment", "", false, true},          {"ReadWrite", "Fragment", "", false, true},
        {"Read", "Compute", "storage", false, true},     {"Write", "Compute", "", false, true},
        {"ReadWrite", "Compute", "", false, true},       {"Write", "Vertex", "storage", false, true},
        {"Read", "Transfer", "", false, false},          {"Write", "Transfer", "", false, false},
        {"ReadWrite", "Transfer", "", false, false},
    };
    return f;
}

const std::vector<UsageForm>& depthForms() {
    static const std::vector<UsageForm> f = {
        {"Write", "DepthAttachment", "", true, false}, {"Read", "DepthAttachment", "", true, false},
        {"ReadWrite", "DepthAttachment", "", true, false}, {"Read", "Fragment", "", false, false},
        {"Read", "Compute", "sampled", false, false},  {"Read", "Transfer", "", false, false},
    };
    return f;
}

const std::vector<UsageForm>& bufferForms() {
    static const std::vector<UsageForm> f = {
        {"Read", "Vertex", "", false, false},          {"Write", "Vertex", "", false, false},
        {"Read", "Fragment", "", false, false},        {"Write", "Fragment", "", false, false},
        {"ReadWrite", "Fragment", "", false, false},   {"Read", "Compute", "", false, false},
        {"Write", "Compute", "", false, false},        {"ReadWrite", "Compute", "", false, false},
        {"Read", "Vertex", "uniform", false, false},   {"Read", "Fragment", "uniform", false, false},
        {"Read", "Compute", "uniform", false, false},  {"Read", "VertexInput", "", false, false},
        {"Read", "VertexInput", "index", false, false}, {"Read", "Indirect", "", false, false},
        {"Read", "Transfer", "", false, false},        {"Write", "Transfer", "", false, false},
        {"ReadWrite", "Transfer", "", false, false},
    };
    return f;
}

class Generator {
public:
    Generator(uint32_t seed, const RandomGraphShape& shape) : rng_(seed), inputs_(~seed), shape_(shape) {}

    RandomGraph run(uint32_t seed) {
        RandomGraph g;
        g.seed = seed;
        std::vector<std::string> declared;
        const uint32_t count = 1 + pick(shape_.maxResources);
        for (uint32_t i = 0; i < count; ++i) declared.push_back(resource(i));
        features_ = {chance(2), chance(2)};
        for (size_t f = 0; f < features_.size(); ++f)
            if (chance(3)) g.features["f" + std::to_string(f)] = chance(2);
        const uint32_t passes = shape_.minPasses + pick(shape_.maxPasses - shape_.minPasses + 1);
        for (uint32_t p = 0; p < passes; ++p) {
            std::string pass = this->pass(p);
            if (!pass.empty()) g.passes.push_back(std::move(pass));
        }
        std::string last;  // the image the present pass reads; empty: any
        std::string chainResources;
        for (uint32_t c = 0; c < shape_.chains; ++c) last = chain(c, last, chainResources, g.passes);
        g.resources = chainResources;
        g.present = present(last);
        // An output no pass uses is refused: such a resource keeps its declaration, not `final`.
        std::ostringstream res;
        for (size_t i = 0; i < declared.size(); ++i)
            res << (usedByAny(resources_[i].name, g) ? declared[i] : withoutFinal(declared[i])) << ",\n";
        res << R"("swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output",)"
            << R"( "external": true, "final": "Present" })";
        g.resources = res.str() + g.resources;
        featureDecl_ = R"("features": { "f0": )" + std::string(features_[0] ? "true" : "false") +
                       R"(, "f1": )" + (features_[1] ? "true" : "false") + " }";
        g.resources = featureDecl_ + ",\n\"resources\": {\n" + g.resources + "}";
        return g;
    }

private:
    static bool usedByAny(const std::string& resource, const RandomGraph& g) {
        const std::string use = R"("resource": ")" + resource + "\"";
        return g.present.find(use) != std::string::npos ||
               std::any_of(g.passes.begin(), g.passes.end(),
                           [&](const std::string& p) { return p.find(use) != std::string::npos; });
    }
    static std::string withoutFinal(std::string declaration) {
        const size_t at = declaration.find(R"(, "final": ")");
        if (at != std::string::npos) declaration.erase(at, declaration.find('"', at + 12) + 1 - at);
        return declaration;
    }

    uint32_t pick(uint32_t n) { return n == 0 ? 0 : static_cast<uint32_t>(rng_() % n); }
    bool chance(uint32_t oneIn) { return pick(oneIn) == 0; }
    template <class T>
    const T& any(const std::vector<T>& v) { return v[pick(static_cast<uint32_t>(v.size()))]; }

    /// Extent JSON and its size at the output size.
    std::string extent(uint32_t& w, uint32_t& h, bool fixedOnly) {
        const uint32_t out = shape_.outputSize;
        switch (fixedOnly ? 2 + pick(2) : pick(4)) {
            case 0: w = h = out; return R"("output")";
            case 1: w = h = std::max(1u, out / 2); return R"("output/2")";
            case 2: w = h = 8; return "[8, 8]";
            default: w = 16; h = 8; return "[16, 8]";
        }
    }

    std::string lifecycle(const Resource& r) {
        // Cleared or external, so that every read has a source in any pass order.
        std::string s;
        const bool external = r.kind == Kind::Buffer || chance(3);
        if (external) {
            s += R"(, "external": true)";
            // An exported one starts each frame in the state the last frame left it; one that
            // is not (no `final`) in its `initial` state, ShaderRead, where the compiler moves
            // it back. Buffers have no layout: TransferSrc is for images only.
            static const std::vector<std::string> finals = {"ShaderRead", "General", "TransferSrc"};
            const auto choices = static_cast<uint32_t>(r.kind == Kind::Buffer ? 2 : 3);
            const std::string& final = finals[pick(choices)];
            // Drawn from a stream of its own, so that no other choice of a seed depends on it.
            if (inputs_() % 4 != 0) s += R"(, "final": ")" + final + "\"";
        } else if (r.kind == Kind::Depth) {
            s += R"(, "clear": { "depth": 1.0 })";
        } else {
            s += r.integer ? R"(, "clear": { "color": [1, 2, 3, 1] })" : R"(, "clear": { "color": [0.25, 0.5, 0.75, 1] })";
            if (chance(4)) s += R"(, "final": ")" + std::string(chance(2) ? "ShaderRead" : "TransferSrc") + "\"";
        }
        return s;
    }

    std::string resource(uint32_t index) {
        Resource r;
        r.kind = static_cast<Kind>(pick(5));
        std::ostringstream j;
        static const std::vector<std::pair<const char*, bool>> colorFormats = {
            {"R8G8B8A8_UNORM", true}, {"R16G16B16A16_SFLOAT", true}, {"R32_UINT", true},
            {"R8G8B8A8_SRGB", false}, {"A2B10G10R10_UNORM_PACK32", false}, {"R32_SFLOAT", true}};
        static const std::vector<const char*> depthFormats = {"D32_SFLOAT", "D24_UNORM_S8_UINT", "D16_UNORM"};
        switch (r.kind) {
            case Kind::Buffer:
                r.name = "buf" + std::to_string(index);
                j << R"({ "type": "buffer", "size": )" << (chance(2) ? 256 : 1024);
                break;
            case Kind::Depth: {
                r.name = "depth" + std::to_string(index);
                const std::string e = extent(r.width, r.height, false);
                r.storage = false;
                j << R"({ "type": "image2d", "format": ")" << any(depthFormats) << R"(", "extent": )" << e;
                break;
            }
            default: {
                const auto& [format, storage] = any(colorFormats);
                r.storage = storage;
                r.integer = std::string_view(format).ends_with("_UINT");
                const bool fixed = r.kind == Kind::Cube;
                const std::string e = extent(r.width, r.height, fixed);
                if (r.kind == Kind::Cube) {
                    r.name = "cube" + std::to_string(index);
                    r.width = r.height;  // cubes are square
                    r.layers = 6;
                    j << R"({ "type": "cube", "format": ")" << format << R"(", "extent": [)" << r.width
                      << ", " << r.height << "]";
                } else {
                    const bool array = r.kind == Kind::Array;
                    r.name = (array ? "arr" : "img") + std::to_string(index);
                    r.layers = array ? 2 + pick(3) : 1;
                    j << R"({ "type": ")" << (array ? "image2d_array" : "image2d") << R"(", "format": ")"
                      << format << R"(", "extent": )" << e;
                    if (array) j << R"(, "layers": )" << r.layers;
                }
                r.mips = 1 + pick(3);
                if (r.mips > 1) j << R"(, "mips": )" << r.mips;
            }
        }
        j << lifecycle(r) << " }";
        resources_.push_back(r);
        return "\"" + r.name + "\": " + j.str();
    }

    Range randomRange(const Resource& r, bool attachment) {
        Range g;
        g.baseMip = pick(r.mips);
        g.mipCount = attachment ? 1 : 1 + pick(r.mips - g.baseMip);
        g.baseLayer = pick(r.layers);
        g.layerCount = 1 + pick(r.layers - g.baseLayer);
        return g;
    }

    std::string condition() {
        static const std::vector<std::string> conditions = {"f0", "!f0", "f1", "f0 && f1", "f0 || !f1",
                                                            "!(f0 && !f1)"};
        return chance(3) ? any(conditions) : "";
    }

    /// One pass: 1..maxUsagesPerPass usages; attachments share one size and layer count.
    std::string pass(uint32_t index) {
        struct Taken { size_t resource; Range range; };
        std::vector<Taken> taken;
        std::optional<std::array<uint32_t, 3>> attachmentShape;  // width, height, layers
        bool depth = false;
        std::set<std::string> drawInputs;
        std::string uses;
        const uint32_t wanted = 1 + pick(shape_.maxUsagesPerPass);
        for (uint32_t attempt = 0; attempt < wanted * 4 && taken.size() < wanted; ++attempt) {
            const size_t ri = pick(static_cast<uint32_t>(resources_.size()));
            const Resource& r = resources_[ri];
            const auto& forms = r.kind == Kind::Buffer  ? bufferForms()
                                : r.kind == Kind::Depth ? depthForms()
                                                        : imageForms();
            const UsageForm& f = any(forms);
            if (f.needsStorage && !r.storage) continue;
            const bool isDepthAttachment = std::string(f.stage) == "DepthAttachment";
            if (isDepthAttachment && depth) continue;
            // One draw: at most one indirect and one index buffer a pass (the executor refuses more).
            const std::string drawInput = std::string(f.stage) == "Indirect" ? "indirect"
                                          : std::string(f.as) == "index"     ? "index"
                                                                             : "";
            if (!drawInput.empty() && drawInputs.count(drawInput)) continue;
            if (!drawInput.empty()) drawInputs.insert(drawInput);
            const bool image = r.kind != Kind::Buffer;
            const bool whole = !image || (!f.attachment && chance(3)) ||
                               (f.attachment && r.mips == 1 && r.layers == 1);
            Range range = whole ? Range{0, r.mips, 0, r.layers} : randomRange(r, f.attachment);
            if (f.attachment) {
                const std::array<uint32_t, 3> s = {std::max(1u, r.width >> range.baseMip),
                                                   std::max(1u, r.height >> range.baseMip), range.layerCount};
                if (attachmentShape && *attachmentShape != s) continue;
                attachmentShape = s;
            }
            const bool clash = std::any_of(taken.begin(), taken.end(), [&](const Taken& t) {
                return t.resource == ri && (r.kind == Kind::Buffer || t.range.overlaps(range));
            });
            if (clash) continue;
            depth = depth || isDepthAttachment;
            taken.push_back({ri, range});
            std::ostringstream u;
            u << R"({ "resource": ")" << r.name << R"(", "access": ")" << f.access << R"(", "stage": ")"
              << f.stage << "\"";
            if (*f.as) u << R"(, "as": ")" << f.as << "\"";
            if (!whole) {
                u << R"(, "mips": [)" << range.baseMip << ", " << range.mipCount << "]";
                if (r.layers > 1)
                    u << R"(, "layers": [)" << range.baseLayer << ", " << range.layerCount << "]";
            }
            u << " }";
            uses += (uses.empty() ? "" : ", ") + u.str();
        }
        if (uses.empty()) return {};
        std::string p = R"({ "name": "p)" + std::to_string(index) + R"(", "type": "Generic")";
        if (chance(2)) p += R"(, "never_cull": true)";
        if (const std::string c = condition(); !c.empty()) p += R"(, "if": ")" + c + "\"";
        return p + R"(, "uses": [ )" + uses + " ] }";
    }

    /// An image of the graph before the chains (cleared or external, so always written), or
    /// empty when it has none.
    std::string anyImage() {
        std::vector<const Resource*> images;
        for (const auto& r : resources_)
            if (r.kind != Kind::Buffer) images.push_back(&r);
        return images.empty() ? std::string() : any(images)->name;
    }

    /// A read of `resource` in the fragment shader (of mip 0 alone when `firstMip`).
    static std::string fragmentRead(const std::string& resource, bool firstMip = false) {
        return R"({ "resource": ")" + resource + R"(", "access": "Read", "stage": "Fragment")" +
               (firstMip ? R"(, "mips": [0, 1])" : "") + " }, ";
    }

    /// Chain `index`: two to four links, each a pass that reads the link before (the first:
    /// `from`, or nothing) and writes a new transient, without `clear`, whole: images of mixed
    /// formats and sizes, as attachments or storage, some with a second mip that nothing
    /// writes or reads (it keeps its poison), and with `chainBuffers` now and then a buffer.
    /// Those sharing memory are then described differently. Adds the transients' JSON to
    /// `resources` and the passes to `passes`; returns the last link, an image of one mip.
    std::string chain(uint32_t index, const std::string& from, std::string& resources,
                      std::vector<std::string>& passes) {
        static const std::vector<const char*> formats = {"R8G8B8A8_UNORM", "R16G16B16A16_SFLOAT", "R32_SFLOAT"};
        std::string read = from;
        bool readFirstMip = false;
        const uint32_t links = 2 + pick(3);
        for (uint32_t l = 0; l < links; ++l) {
            const std::string name = "c" + std::to_string(index) + "_" + std::to_string(l);
            std::string uses = read.empty() ? "" : fragmentRead(read, readFirstMip);
            const bool last = l + 1 == links;
            if (shape_.chainBuffers && !last && chance(4)) {
                // A buffer link, written by compute, which the next link reads in its shader.
                resources += ",\n\"" + name + R"(": { "type": "buffer", "size": )" + (chance(2) ? "256" : "4096") +
                             " }";
                passes.push_back(R"({ "name": ")" + name + R"(", "type": "Generic", "uses": [ )" + uses +
                                 R"({ "resource": ")" + name + R"(", "access": "Write", "stage": "Compute" } ] })");
                read = name;
                readFirstMip = false;
                continue;
            }
            // One draw from the generator per statement: the order of a graph's choices must not
            // depend on how a compiler orders the operands of one expression.
            const bool mips = !last && chance(4);
            const std::string format = any(formats);
            const bool half = !last && chance(3);
            const bool attachment = chance(2);
            resources += ",\n\"" + name + R"(": { "type": "image2d", "format": ")" + format + R"(", "extent": )" +
                         (half ? R"("output/2")" : R"("output")") + (mips ? R"(, "mips": 2)" : "") + " }";
            uses += R"({ "resource": ")" + name + R"(", "access": "Write", "stage": ")" +
                    (attachment ? "ColorAttachment" : "Compute") + "\"" + (mips ? R"(, "mips": [0, 1])" : "") + " }";
            passes.push_back(R"({ "name": ")" + name + R"(", "type": "Generic", "uses": [ )" + uses + " ] }");
            read = name;
            readFirstMip = mips;
        }
        return read;
    }

    /// Reads one image (sampled, whole; `image` when given) and writes the swapchain, as an
    /// attachment or a copy.
    std::string present(const std::string& image) {
        std::string uses;
        const std::string read = image.empty() ? anyImage() : image;
        if (!read.empty())
            uses = R"({ "resource": ")" + read + R"(", "access": "Read", "stage": "Fragment" }, )";
        uses += std::string(R"({ "resource": "swapchain", "access": "Write", "stage": ")") +
                (chance(3) ? "Transfer" : "ColorAttachment") + R"(" })";
        return R"({ "name": "present", "type": "Generic", "uses": [ )" + uses + " ] }";
    }

    std::mt19937 rng_;
    std::mt19937 inputs_;  // whether an external is an input, not exported
    RandomGraphShape shape_;
    std::vector<Resource> resources_;
    std::array<bool, 2> features_{};
    std::string featureDecl_;
};

}  // namespace

std::string RandomGraph::json() const {
    std::vector<size_t> order(passes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    return json(order);
}

std::string RandomGraph::json(const std::vector<size_t>& order) const {
    std::string s = R"({ "version": 1, "name": "random)" + std::to_string(seed) + "\",\n" + resources +
                    ",\n\"passes\": [\n";
    for (size_t i : order) s += passes.at(i) + ",\n";
    return s + present + "\n] }\n";
}

std::vector<size_t> RandomGraph::shuffledOrder(uint32_t salt) const {
    std::vector<size_t> order(passes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::mt19937 rng(seed * 2654435761u + salt);
    std::shuffle(order.begin(), order.end(), rng);
    return order;
}

RandomGraph generateRandomGraph(uint32_t seed, const RandomGraphShape& shape) {
    return Generator(seed, shape).run(seed);
}

RandomGraph withRandomQueues(const RandomGraph& graph, uint32_t salt) {
    RandomGraph out = graph;
    const nlohmann::json resources = nlohmann::json::parse("{" + graph.resources + "}").at("resources");
    auto depthImage = [&](const std::string& name) {
        const auto& r = resources.at(name);
        const std::string format = r.value("format", "");
        return format.rfind("D", 0) == 0 || format.rfind("S8", 0) == 0;
    };
    std::mt19937 rng(graph.seed * 2246822519u + salt * 3266489917u + 1u);
    for (std::string& text : out.passes) {
        nlohmann::ordered_json pass = nlohmann::ordered_json::parse(text);
        bool compute = true, transfer = true;
        auto consider = [&](const std::string& resource, const std::string& stage) {
            compute &= stage == "Compute" || stage == "Transfer" || stage == "Indirect";
            transfer &= stage == "Transfer";
            // Copies of depth or stencil need a graphics queue (vkCmdCopy*Image* on other queues).
            if (stage == "Transfer" && depthImage(resource)) compute = transfer = false;
        };
        const auto& uses = pass.at("uses");
        if (uses.is_object()) {
            for (const auto& [resource, usage] : uses.items()) {
                const std::string u = usage.get<std::string>();
                consider(resource, u.substr(u.find('@') + 1));
            }
        } else {
            for (const auto& u : uses) consider(u.at("resource").get<std::string>(), u.at("stage").get<std::string>());
        }
        std::vector<const char*> choices;
        if (compute) choices.push_back("compute");
        if (transfer) choices.push_back("transfer");
        if (choices.empty() || rng() % 2 == 0) continue;
        pass["queue"] = choices[rng() % choices.size()];
        text = pass.dump();
    }
    return out;
}

}  // namespace skygraph::test
