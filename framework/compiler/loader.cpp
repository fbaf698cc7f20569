// Graph file -> GraphDesc. Collects every problem in the file before giving up, so a user
// fixing a hand-edited graph sees all of them in one run.
#include "json_positions.hpp"
#include "validation.hpp"
#include "vulkan_state.hpp"

#include <skygraph/compiler.hpp>

#include <algorithm>
#include <bit>
#include <map>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_map>

namespace skygraph {
namespace {

using nlohmann::json;

constexpr uint32_t kMaxExtent = 16384;  // the common maxImageDimension2D; devices may allow less
constexpr uint32_t kMaxLayers = 2048;
constexpr uint32_t kMaxDivisor = 4096;
constexpr uint64_t kMaxBufferBytes = 1ull << 31;

std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

class GraphLoader {
public:
    GraphLoader(std::string file, const PassRegistry& registry)
        : registry_(registry) {
        graph_.file = std::move(file);
    }

    GraphDesc load(std::string_view text) {
        JsonParseResult parsed = parseJsonWithPositions(text);
        if (!parsed.error.empty()) {
            Diagnostic d{graph_.file, parsed.errorPath, "", "", parsed.error};
            d.line = parsed.line;
            d.column = parsed.column;
            diags_.add(std::move(d));
            throw GraphError(std::move(diags_));
        }
        loadRoot(parsed.value);
        for (const auto& dup : parsed.duplicateKeys) reportDuplicate(dup);
        if (diags_.empty()) checkReadsHaveSourcesAtLoad(graph_, diags_);
        if (!diags_.empty()) throw GraphError(std::move(diags_));
        return std::move(graph_);
    }

private:
    void error(const std::string& path, const std::string& pass, const std::string& resource,
               const std::string& message) {
        diags_.add(Diagnostic{graph_.file, path, pass, resource, message});
    }

    static std::string join(const std::string& path, const std::string& key) {
        return path.empty() ? key : path + "." + key;
    }

    /// A repeated JSON key, with the pass and resource it concerns: "resources.<r>..." names
    /// resource r, "passes[i]..." pass i, and "passes[i].uses.<r>" both.
    void reportDuplicate(const DuplicateKey& dup) {
        std::string pass, resource;
        const std::string& path = dup.path;
        auto segment = [&](size_t from) { return path.substr(from, path.find('.', from) - from); };
        if (path.starts_with("resources.")) resource = segment(10);
        if (path.starts_with("passes[")) {
            const size_t close = path.find(']');
            const std::string index = path.substr(7, close - 7);
            if (close != std::string::npos && !index.empty() &&
                index.find_first_not_of("0123456789") == std::string::npos && index.size() < 10) {
                if (auto it = passNames_.find(std::stoul(index)); it != passNames_.end()) pass = it->second;
                if (path.compare(close + 1, 6, ".uses.") == 0) resource = segment(close + 7);
            }
        }
        const bool isResource = path.starts_with("resources.") && path.find('.', 10) == std::string::npos;
        error(path, pass, resource,
              (isResource ? "duplicate resource name '" : "duplicate key '") + dup.key +
                  "'; JSON keeps only the last one");
    }

    void checkKeys(const json& object, const std::string& path,
                   std::initializer_list<std::string_view> allowed, const std::string& pass = "",
                   const std::string& resource = "") {
        for (const auto& [key, _] : object.items()) {
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string list;
            for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            error(join(path, key), pass, resource, "unknown key '" + key + "'; expected one of: " + list);
        }
    }

    void loadRoot(const json& root) {
        if (!root.is_object()) {
            error("", "", "", "a graph file must be a JSON object");
            return;
        }
        checkKeys(root, "", {"$schema", "version", "name", "description", "features",
                             "resources", "passes"});
        if (!root.contains("version")) {
            error("version", "", "", "missing; this reader understands version 1");
        } else if (root["version"] != 1) {
            error("version", "", "", "unsupported version " + root["version"].dump() +
                                         "; this reader understands version 1");
        }
        if (auto it = root.find("name"); it != root.end() && it->is_string())
            graph_.name = it->get<std::string>();
        else
            error("name", "", "", "missing or not a string");
        if (auto it = root.find("features"); it != root.end()) loadFeatures(*it);
        if (auto it = root.find("resources"); it != root.end() && it->is_object()) {
            for (const auto& [name, value] : it->items()) loadResource(name, value);
            for (size_t i = 0; i < graph_.resources.size(); ++i)
                resourceIndex_.emplace(graph_.resources[i].name, static_cast<uint32_t>(i));
        } else
            error("resources", "", "", "missing or not an object of named resources");
        if (auto it = root.find("passes"); it != root.end() && it->is_array()) {
            for (size_t i = 0; i < it->size(); ++i) loadPass(i, (*it)[i]);
        } else {
            error("passes", "", "", "missing or not an array");
        }
    }

    void loadFeatures(const json& features) {
        if (!features.is_object()) {
            error("features", "", "", "must be an object of feature name -> true/false");
            return;
        }
        for (const auto& [name, value] : features.items()) {
            std::string err;
            if (!Condition::parse(name, err) || name == "true" || name == "false" ||
                name.find_first_of("!&|() ") != std::string::npos)
                error("features." + name, "", "", "'" + name + "' is not a valid feature name");
            if (!value.is_boolean())
                error("features." + name, "", "", "default must be true or false");
            graph_.features.push_back({name, value.is_boolean() && value.get<bool>()});
        }
    }

    // ---- resources -------------------------------------------------------------------
    void loadResource(const std::string& name, const json& v) {
        std::string path = "resources." + name;
        ResourceDesc r;
        r.name = name;
        auto fail = [&](const std::string& sub, const std::string& msg) {
            error(sub.empty() ? path : path + "." + sub, "", name, msg);
        };
        if (!v.is_object()) {
            fail("", "must be an object");
            graph_.resources.push_back(std::move(r));
            return;
        }
        checkKeys(v, path, {"type", "format", "extent", "mips", "layers", "size", "clear",
                            "external", "initial", "final", "description"}, "", name);
        static const std::map<std::string, ResourceType> types{
            {"image2d", ResourceType::Image2D}, {"cube", ResourceType::Cube},
            {"image2d_array", ResourceType::Image2DArray}, {"buffer", ResourceType::Buffer}};
        auto type = v.find("type");
        if (type == v.end() || !type->is_string() || !types.count(type->get<std::string>())) {
            fail("type", "expected one of image2d, cube, image2d_array, buffer" +
                             (type == v.end() ? std::string(" (missing)") : ", got " + type->dump()));
            graph_.resources.push_back(std::move(r));
            return;
        }
        r.type = types.at(type->get<std::string>());
        if (r.isImage()) {
            loadImageShape(r, v, fail);
        } else {
            for (const char* k : {"format", "extent", "mips", "layers"})
                if (v.contains(k)) fail(k, std::string("buffers have no ") + k);
            auto size = v.find("size");
            if (size == v.end() || !size->is_number_unsigned() || size->get<uint64_t>() == 0 ||
                size->get<uint64_t>() > kMaxBufferBytes)
                fail("size", "buffers need a size in bytes between 1 and 2 GiB");
            else
                r.sizeBytes = size->get<uint64_t>();
        }
        loadClear(r, v, fail);
        loadExternal(r, v, fail);
        graph_.resources.push_back(std::move(r));
    }

    template <typename Fail>
    void loadImageShape(ResourceDesc& r, const json& v, Fail& fail) {
        if (v.contains("size")) fail("size", "images have an extent, not a size");
        auto format = v.find("format");
        if (format == v.end() || !format->is_string()) {
            fail("format", "missing; a VkFormat name without VK_FORMAT_, e.g. R16G16B16A16_SFLOAT");
        } else if (auto f = findFormat(format->get<std::string>())) {
            r.format = *f;
        } else {
            std::string known;
            for (const auto& k : knownFormats()) known += (known.empty() ? "" : ", ") + std::string(k.name);
            fail("format", "unknown format '" + format->get<std::string>() + "'; known: " + known);
        }
        auto extent = v.find("extent");
        if (extent == v.end()) {
            fail("extent", "missing; \"output\", \"output/N\" or [width, height]");
        } else if (extent->is_string()) {
            std::string s = extent->get<std::string>();
            if (s == "output") {
                r.extent.divisor = 1;
            } else if (s.starts_with("output/") && s.size() > 7 &&
                       s.find_first_not_of("0123456789", 7) == std::string::npos && s.size() < 13) {
                r.extent.divisor = static_cast<uint32_t>(std::stoul(s.substr(7)));
                if (r.extent.divisor == 0 || r.extent.divisor > kMaxDivisor)
                    fail("extent", "divisor must be between 1 and " + std::to_string(kMaxDivisor));
            } else {
                fail("extent", "expected \"output\", \"output/N\" or [width, height], got \"" + s + "\"");
            }
            if (r.type == ResourceType::Cube)
                fail("extent", "cube faces must be square, which an output-relative extent is not "
                               "in general; give a fixed [n, n]");
        } else if (extent->is_array() && extent->size() == 2 && (*extent)[0].is_number_integer() &&
                   (*extent)[1].is_number_integer()) {
            int64_t w = (*extent)[0].get<int64_t>(), h = (*extent)[1].get<int64_t>();
            if (w < 1 || h < 1 || w > kMaxExtent || h > kMaxExtent)
                fail("extent", "[" + std::to_string(w) + ", " + std::to_string(h) +
                                   "] is outside 1.." + std::to_string(kMaxExtent));
            r.extent.relativeToOutput = false;
            r.extent.width = static_cast<uint32_t>(std::clamp<int64_t>(w, 1, kMaxExtent));
            r.extent.height = static_cast<uint32_t>(std::clamp<int64_t>(h, 1, kMaxExtent));
            if (r.type == ResourceType::Cube && w != h) fail("extent", "cube faces must be square");
        } else {
            fail("extent", "expected \"output\", \"output/N\" or [width, height]");
        }
        if (auto mips = v.find("mips"); mips != v.end()) {
            uint32_t maxMips = static_cast<uint32_t>(std::bit_width(kMaxExtent));
            if (*mips == "full") {
                r.mips = 0;
            } else if (!mips->is_number_integer() || mips->get<int64_t>() < 1 ||
                       mips->get<int64_t>() > maxMips) {
                fail("mips", "expected \"full\" or a count between 1 and " + std::to_string(maxMips) +
                                 ", got " + mips->dump());
            } else {
                r.mips = mips->get<uint32_t>();
                if (!r.extent.relativeToOutput &&
                    r.mips > static_cast<uint32_t>(std::bit_width(std::max(r.extent.width, r.extent.height))))
                    fail("mips", std::to_string(r.mips) + " levels is more than a " +
                                     std::to_string(r.extent.width) + "x" +
                                     std::to_string(r.extent.height) + " image has");
            }
        }
        r.layers = r.type == ResourceType::Cube ? 6 : 1;
        if (auto layers = v.find("layers"); layers != v.end()) {
            if (!layers->is_number_integer() || layers->get<int64_t>() < 1 ||
                layers->get<int64_t>() > kMaxLayers) {
                fail("layers", "expected a count between 1 and " + std::to_string(kMaxLayers) +
                                   ", got " + layers->dump());
            } else {
                r.layers = layers->get<uint32_t>();
                if (r.type == ResourceType::Cube && r.layers != 6)
                    fail("layers", "a cube has 6 layers");
                if (r.type == ResourceType::Image2D && r.layers != 1)
                    fail("layers", "an image2d has 1 layer; use image2d_array");
            }
        }
    }

    template <typename Fail>
    void loadClear(ResourceDesc& r, const json& v, Fail& fail) {
        auto clear = v.find("clear");
        if (clear == v.end()) return;
        ClearValue c;
        if (!clear->is_object()) {
            fail("clear", "expected {\"color\": [r, g, b, a]} or {\"depth\": d}");
            return;
        }
        checkKeys(*clear, r.jsonPath() + ".clear", {"color", "depth", "stencil"}, "", r.name);
        if (!r.isImage()) fail("clear", "buffers cannot be cleared by the graph");
        if (auto color = clear->find("color"); color != clear->end()) {
            if (!color->is_array() || color->size() != 4 ||
                !std::all_of(color->begin(), color->end(), [](const json& x) { return x.is_number(); }))
                fail("clear.color", "expected four numbers");
            else
                for (size_t i = 0; i < 4; ++i) c.color[i] = (*color)[i].get<float>();
            if (r.format.isDepthStencil()) fail("clear.color", "a depth format needs {\"depth\": d}");
        } else if (clear->contains("depth") || clear->contains("stencil")) {
            c.isDepth = true;
            if (auto depth = clear->find("depth"); depth != clear->end()) {
                if (!depth->is_number() || depth->get<double>() < 0.0 || depth->get<double>() > 1.0)
                    fail("clear.depth", "expected a number in [0, 1]");
                else
                    c.depth = depth->get<float>();
            }
            if (auto st = clear->find("stencil"); st != clear->end()) {
                if (!st->is_number_unsigned() || st->get<uint64_t>() > 255)
                    fail("clear.stencil", "expected an integer in [0, 255]");
                else
                    c.stencil = st->get<uint32_t>();
            }
            if (r.isImage() && r.format.format != VK_FORMAT_UNDEFINED && !r.format.isDepthStencil())
                fail("clear", "a color format needs {\"color\": [r, g, b, a]}");
        } else {
            fail("clear", "expected {\"color\": [r, g, b, a]} or {\"depth\": d}");
        }
        r.clear = c;
    }

    template <typename Fail>
    void loadExternal(ResourceDesc& r, const json& v, Fail& fail) {
        static const std::map<std::string, ExternalState> states{
            {"Present", ExternalState::Present}, {"TransferSrc", ExternalState::TransferSrc},
            {"ShaderRead", ExternalState::ShaderRead}, {"General", ExternalState::General}};
        auto state = [&](const char* key) {
            auto it = v.find(key);
            if (it == v.end()) return ExternalState::None;
            if (!it->is_string() || !states.count(it->get<std::string>())) {
                fail(key, "expected one of Present, TransferSrc, ShaderRead, General");
                return ExternalState::None;
            }
            ExternalState s = states.at(it->get<std::string>());
            if (!r.isImage() && (s == ExternalState::Present || s == ExternalState::TransferSrc))
                fail(key, "a buffer cannot be in state " + it->get<std::string>());
            return s;
        };
        if (auto ext = v.find("external"); ext != v.end()) {
            if (!ext->is_boolean()) fail("external", "expected true or false");
            else r.external = ext->get<bool>();
        }
        r.final = state("final");
        r.initial = state("initial");
        if (r.initial != ExternalState::None && !r.external)
            fail("initial", "only external resources arrive in a state");
        // An external resource that persists comes back in the state it was left in.
        if (r.external && r.initial == ExternalState::None)
            r.initial = r.final != ExternalState::None ? r.final : ExternalState::ShaderRead;
        if (r.external && r.clear) fail("clear", "an external resource arrives with contents; it is not cleared");
    }

    // ---- passes ----------------------------------------------------------------------
    void loadPass(size_t index, const json& v) {
        std::string path = "passes[" + std::to_string(index) + "]";
        PassDesc p;
        p.jsonPath = path;
        usePaths_.clear();
        if (!v.is_object()) {
            error(path, "", "", "a pass must be an object");
            return;
        }
        if (auto it = v.find("name"); it != v.end() && it->is_string() && !it->get<std::string>().empty())
            p.name = it->get<std::string>();
        else
            error(path + ".name", "", "", "missing or not a non-empty string");
        checkKeys(v, path, {"name", "type", "if", "uses", "params", "never_cull", "description"}, p.name);
        if (!p.name.empty()) {
            passNames_.emplace(index, p.name);
            auto [first, fresh] = passPaths_.emplace(p.name, path);
            if (!fresh)
                error(path + ".name", p.name, "", "duplicate pass name; the first is " + first->second);
        }

        const PassTypeInfo* type = nullptr;
        if (auto it = v.find("type"); it != v.end() && it->is_string()) {
            p.type = it->get<std::string>();
            type = registry_.find(p.type);
            if (!type)
                error(path + ".type", p.name, "", "unknown pass type '" + p.type +
                                                      "'; registered: " + joinNames(registry_.names()));
        } else {
            error(path + ".type", p.name, "", "missing or not a string");
        }
        if (auto it = v.find("if"); it != v.end()) loadCondition(p, *it);
        if (auto it = v.find("never_cull"); it != v.end()) {
            if (it->is_boolean()) p.neverCull = it->get<bool>();
            else error(path + ".never_cull", p.name, "", "expected true or false");
        }
        if (auto it = v.find("params"); it != v.end()) {
            if (!it->is_object()) error(path + ".params", p.name, "", "expected an object");
            else p.params = PassParams(*it);
        }
        if (type && type->validateParams)
            for (const auto& e : type->validateParams(p.params))
                error(path + ".params" + (e.path.empty() ? "" : "." + e.path), p.name, "", e.message);
        if (auto it = v.find("uses"); it != v.end()) loadUses(p, *it);
        else error(path + ".uses", p.name, "", "missing; a pass that uses nothing does nothing");
        if (type) bindSlots(p, *type);
        checkOverlaps(p);
        graph_.passes.push_back(std::move(p));
    }

    void loadCondition(PassDesc& p, const json& v) {
        std::string path = p.jsonPath + ".if";
        if (!v.is_string()) {
            error(path, p.name, "", "expected a string expression such as \"skybox && !debug\"");
            return;
        }
        std::string err;
        auto cond = Condition::parse(v.get<std::string>(), err);
        if (!cond) {
            error(path, p.name, "", "bad expression \"" + v.get<std::string>() + "\": " + err);
            return;
        }
        for (const auto& f : cond->features()) {
            bool known = std::any_of(graph_.features.begin(), graph_.features.end(),
                                     [&](const FeatureDecl& d) { return d.name == f; });
            if (!known) {
                std::vector<std::string> names;
                for (const auto& d : graph_.features) names.push_back(d.name);
                error(path, p.name, "", "unknown feature '" + f + "'; the file declares: " +
                                            (names.empty() ? "none" : joinNames(names)));
            }
        }
        p.condition = *cond;
    }

    void loadUses(PassDesc& p, const json& uses) {
        std::string path = p.jsonPath + ".uses";
        p.usesByName = uses.is_object();
        if (uses.is_object()) {
            for (const auto& [name, value] : uses.items()) {
                std::string upath = path + "." + name;
                if (!value.is_string()) {
                    error(upath, p.name, name, "expected \"Access@Stage\", e.g. \"Read@Fragment\"");
                    continue;
                }
                json entry = {{"resource", name}};
                auto at = value.get<std::string>().find('@');
                if (at == std::string::npos) {
                    error(upath, p.name, name, "expected \"Access@Stage\", got \"" + value.get<std::string>() + "\"");
                    continue;
                }
                entry["access"] = value.get<std::string>().substr(0, at);
                entry["stage"] = value.get<std::string>().substr(at + 1);
                loadUsage(p, entry, upath);
            }
        } else if (uses.is_array()) {
            for (size_t i = 0; i < uses.size(); ++i) {
                std::string upath = path + "[" + std::to_string(i) + "]";
                if (!uses[i].is_object()) {
                    error(upath, p.name, "", "expected {\"resource\", \"access\", \"stage\", ...}");
                    continue;
                }
                auto res = uses[i].find("resource");
                checkKeys(uses[i], upath, {"resource", "access", "stage", "as", "mips", "layers", "slot"},
                          p.name, res != uses[i].end() && res->is_string() ? res->get<std::string>() : "");
                loadUsage(p, uses[i], upath);
            }
        } else {
            error(path, p.name, "", "expected an object (resource -> \"Access@Stage\") or an array of usage objects");
        }
    }

    void loadUsage(PassDesc& p, const json& e, const std::string& path) {
        auto resIt = e.find("resource");
        if (resIt == e.end() || !resIt->is_string())
            return error(resIt == e.end() ? path : path + ".resource", p.name, "",
                         "expected \"resource\": the name of a declared resource");
        const std::string resName = resIt->get<std::string>();
        auto fail = [&](const std::string& msg) { error(path, p.name, resName, msg); };
        auto found = resourceIndex_.find(resName);
        const ResourceDesc* res = found == resourceIndex_.end() ? nullptr : &graph_.resources[found->second];
        if (!res) {
            std::vector<std::string> names;
            for (const auto& r : graph_.resources) names.push_back(r.name);
            return fail("unknown resource; declared: " + joinNames(names));
        }
        UsageDecl u;
        u.resource = static_cast<uint32_t>(res - graph_.resources.data());
        auto access = e.contains("access") && e["access"].is_string()
                          ? parseAccess(e["access"].get<std::string>()) : std::nullopt;
        auto stage = e.contains("stage") && e["stage"].is_string()
                         ? parseStage(e["stage"].get<std::string>()) : std::nullopt;
        if (!access) fail("unknown access " + (e.contains("access") ? e["access"].dump() : "(missing)") +
                          "; expected Read, Write or ReadWrite");
        if (!stage) fail("unknown stage " + (e.contains("stage") ? e["stage"].dump() : "(missing)") +
                         "; expected ColorAttachment, DepthAttachment, Vertex, Fragment, Compute, "
                         "Transfer, VertexInput or Indirect");
        if (!access || !stage) return;
        u.usage.access = *access;
        u.usage.stage = *stage;
        if (auto as = e.find("as"); as != e.end()) {
            auto parsed = as->is_string() ? parseBindAs(as->get<std::string>()) : std::nullopt;
            if (!parsed) return fail("unknown `as` " + as->dump() + "; expected sampled, storage, uniform or index");
            u.usage.as = *parsed;
        }
        if (e.contains("slot")) {
            if (!e["slot"].is_string()) return fail("`slot` must be a string");
            u.slot = graph_.internSlot(e["slot"].get<std::string>());
        }
        if (e.contains("mips") || e.contains("layers")) {
            // A full chain's length is known here for fixed extents only; for output-relative
            // ones the compiler clips the range to the chain it resolves.
            const uint32_t levels = res->mips != 0 ? res->mips
                                    : res->extent.relativeToOutput
                                        ? static_cast<uint32_t>(std::bit_width(kMaxExtent))
                                        : res->mipCount(0, 0);
            SubresourceRange range{0, levels, 0, res->layers};
            auto pair = [&](const char* key, uint32_t& first, uint32_t& count) {
                auto it = e.find(key);
                if (it == e.end()) return true;
                if (!res->isImage()) return fail(std::string("buffers have no ") + key), false;
                if (!it->is_array() || it->size() != 2 || !(*it)[0].is_number_unsigned() ||
                    !(*it)[1].is_number_unsigned() || (*it)[1].get<uint64_t>() == 0 ||
                    (*it)[0].get<uint64_t>() > kMaxLayers || (*it)[1].get<uint64_t>() > kMaxLayers)
                    return fail(std::string("`") + key + "` must be [first, count] with count >= 1"), false;
                first = (*it)[0].get<uint32_t>();
                count = (*it)[1].get<uint32_t>();
                return true;
            };
            if (!pair("mips", range.baseMip, range.mipCount) ||
                !pair("layers", range.baseLayer, range.layerCount))
                return;
            if (res->mips == 0 && range.baseMip + range.mipCount > levels)
                return fail("mips [" + std::to_string(range.baseMip) + ", " + std::to_string(range.mipCount) +
                            "] exceed the resource's " + std::to_string(levels) + " mip levels (" +
                            (res->extent.relativeToOutput
                                 ? std::string("the most any image can have")
                                 : "the full chain of " + std::to_string(res->extent.width) + "x" +
                                       std::to_string(res->extent.height)) +
                            ")");
            u.usage.range = range;
        }
        std::string problem = usageProblem(*res, u.usage);
        if (!problem.empty()) return fail(problem);
        u.usage.as = resolvedBinding(u.usage.mode(), res->isImage());
        p.uses.push_back(std::move(u));
        usePaths_.push_back(path);
    }

    void bindSlots(PassDesc& p, const PassTypeInfo& type) {
        if (type.acceptsAnyUsage) return;
        std::map<std::string, int> filled;
        auto matches = [&](const SlotDecl& s, const UsageDecl& u) {
            return s.stage == u.usage.stage &&
                   std::find(s.accesses.begin(), s.accesses.end(), u.usage.access) != s.accesses.end() &&
                   (s.as == BindAs::Default || s.as == u.usage.as);
        };
        std::string expected;
        for (const auto& s : type.slots)
            expected += (expected.empty() ? "" : "; ") + s.name + " (" + s.describeUsage() + ")";
        for (size_t i = 0; i < p.uses.size(); ++i) {
            UsageDecl& u = p.uses[i];
            const std::string& path = usePaths_[i];
            const std::string& resName = graph_.resources[u.resource].name;
            const SlotDecl* slot = nullptr;
            const std::string named(graph_.slotName(u.slot));  // as the file names it, or empty
            const std::string& wanted = named.empty() ? resName : named;
            for (const auto& s : type.slots)
                if (s.name == wanted) slot = &s;
            if (!slot && !named.empty()) {
                error(path, p.name, resName, type.name + " has no slot '" + named +
                                                       "'; its slots: " + expected);
                continue;
            }
            if (!slot) {
                std::vector<const SlotDecl*> candidates;
                for (const auto& s : type.slots)
                    if (matches(s, u) && (s.repeated || !filled.count(s.name))) candidates.push_back(&s);
                if (candidates.size() > 1) {
                    error(path, p.name, resName, "usage " + toString(u.usage) + " fits several slots of " +
                                                           type.name + "; name one with \"slot\"");
                    continue;
                }
                if (candidates.empty()) {
                    error(path, p.name, resName, "usage " + toString(u.usage) + " contradicts " +
                                                           type.name + "; expected " + expected);
                    continue;
                }
                slot = candidates.front();
            }
            if (!matches(*slot, u)) {
                error(path, p.name, resName, "usage " + toString(u.usage) + " contradicts slot '" +
                                                       slot->name + "' of " + type.name + "; expected " +
                                                       slot->describeUsage());
                continue;
            }
            if (filled.count(slot->name) && !slot->repeated) {
                error(path, p.name, resName, "slot '" + slot->name + "' of " + type.name +
                                                       " is already filled");
                continue;
            }
            filled[slot->name]++;
            u.slot = graph_.internSlot(slot->name);
        }
        for (const auto& s : type.slots)
            if (!s.optional && !filled.count(s.name))
                error(p.jsonPath + ".uses", p.name, "", type.name + " needs slot '" + s.name + "' (" +
                                                            s.describeUsage() + "); no usage fills it");
    }

    void checkOverlaps(const PassDesc& p) {
        for (size_t i = 0; i < p.uses.size(); ++i)
            for (size_t j = 0; j < i; ++j) {
                const auto& a = p.uses[i];
                const auto& b = p.uses[j];
                if (a.resource != b.resource) continue;
                const auto& res = graph_.resources[a.resource];
                SubresourceRange whole{0, std::max(1u, res.mips), 0, res.layers};
                if (a.usage.range.value_or(whole).overlaps(b.usage.range.value_or(whole)) ||
                    (res.mips == 0 && (!a.usage.range || !b.usage.range)))
                    error(usePaths_[i], p.name, res.name, "overlaps " + usePaths_[j] +
                                                            "; one pass may use each subresource once");
            }
    }

    const PassRegistry& registry_;
    GraphDesc graph_;
    Diagnostics diags_;
    std::unordered_map<std::string, uint32_t> resourceIndex_;  ///< name -> graph_.resources
    std::unordered_map<std::string, std::string> passPaths_;   ///< name -> first JSON path
    std::unordered_map<size_t, std::string> passNames_;        ///< JSON index -> name
    /// The JSON paths of the pass being loaded's usages, beside PassDesc::uses (a usage that
    /// fails to load leaves a gap in the file's numbering, so they cannot be derived yet).
    std::vector<std::string> usePaths_;
};

}  // namespace

GraphDesc parseGraph(std::string_view text, const std::string& fileName, const PassRegistry& registry) {
    return GraphLoader(fileName, registry).load(text);
}

GraphDesc loadGraphFile(const std::filesystem::path& path, const PassRegistry& registry) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        Diagnostics d;
        d.add({path.string(), "", "", "", "cannot open the file"});
        throw GraphError(std::move(d));
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseGraph(text.str(), path.string(), registry);
}

}  // namespace skygraph
