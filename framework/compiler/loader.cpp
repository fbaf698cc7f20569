// Graph file -> GraphDesc. Collects every problem in the file before giving up, so a user
// fixing a hand-edited graph sees all of them in one run.
//
// Loading costs in proportion to the file: the text is read once into a JsonDocument (no
// allocation per value), and everything only a message needs (JSON paths, lists of names) is
// worked out when there is a problem to report.
#include "graph_file.hpp"
#include "graph_limits.hpp"
#include "json_document.hpp"
#include "json_path.hpp"
#include "name_index.hpp"
#include "printable_name.hpp"
#include "resource_loader.hpp"
#include "validation.hpp"
#include "usage_fit.hpp"

#include <skygraph/compiler.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>

namespace skygraph {
namespace {

/// A value as nlohmann prints it, for messages: strings quoted and escaped.
std::string dumpString(std::string_view s) { return nlohmann::json(std::string(s)).dump(); }

constexpr Keys<8> kRootKeys{"$schema", "version", "name", "description", "features", "layouts", "resources", "passes"};
constexpr Keys<8> kPassKeys{"name", "type", "if", "uses", "params", "never_cull", "queue", "description"};
constexpr Keys<7> kUsageKeys{"resource", "access", "stage", "as", "mips", "layers", "slot"};

// Each entry's keys by name, for JsonFields.
namespace rootKey {
constexpr size_t version = keyIndex(kRootKeys, "version"), name = keyIndex(kRootKeys, "name"),
                 features = keyIndex(kRootKeys, "features"), layouts = keyIndex(kRootKeys, "layouts"),
                 resources = keyIndex(kRootKeys, "resources"), passes = keyIndex(kRootKeys, "passes"),
                 schema = keyIndex(kRootKeys, "$schema"), description = keyIndex(kRootKeys, "description");
}
namespace passKey {
constexpr size_t name = keyIndex(kPassKeys, "name"), type = keyIndex(kPassKeys, "type"),
                 condition = keyIndex(kPassKeys, "if"), uses = keyIndex(kPassKeys, "uses"),
                 params = keyIndex(kPassKeys, "params"), neverCull = keyIndex(kPassKeys, "never_cull"),
                 queue = keyIndex(kPassKeys, "queue"), description = keyIndex(kPassKeys, "description");
}
namespace usageKey {
constexpr size_t resource = keyIndex(kUsageKeys, "resource"), access = keyIndex(kUsageKeys, "access"),
                 stage = keyIndex(kUsageKeys, "stage"), as = keyIndex(kUsageKeys, "as"),
                 mips = keyIndex(kUsageKeys, "mips"), layers = keyIndex(kUsageKeys, "layers"),
                 slot = keyIndex(kUsageKeys, "slot");
}

/// One entry of a pass's `uses` in either form: an object in an array (its fields), or a
/// "resource": "Access@Stage" member split at the '@'.
struct UsageEntry {
    JsonFields<kUsageKeys.size()> fields;  ///< The array form's entry; none for the object form.
    bool split = false;  ///< The object form: `access` and `stage` are its halves.
    std::string_view access, stage;
};

/// Loads a graph file's document. As a JsonListener it loads `features` and `resources` as
/// they are read and then each pass as it is, so that a large file's passes never sit in the
/// document all at once; the file's other parts, and everything of a file it was not told
/// of, are loaded by finish(). Problems are kept per part and reported in the file format's
/// order (the root's own keys, features, resources, passes), whatever the file's order.
class GraphLoader final : public JsonListener {
public:
    /// `textSize`: the file's, to guess from.
    GraphLoader(std::string file, const PassRegistry& registry, size_t textSize)
        : registry_(registry), textSize_(textSize), report_(file) {
        graph_.file = std::move(file);
        into(rootDiags_);
    }

    /// The malformed text's one diagnostic.
    [[noreturn]] void refuse(const JsonRead& read) {
        Diagnostic d{graph_.file, read.errorPath, "", "", read.error};
        d.line = read.line;
        d.column = read.column;
        Diagnostics diags;
        diags.add(std::move(d));
        throw GraphError(std::move(diags));
    }

    /// Whether what the listener was told can stand: false when the file repeats `features`,
    /// `resources` or `passes`, or gives the first two after passes it streamed (which then
    /// were loaded against the wrong ones).
    [[nodiscard]] bool toldSoundly() const noexcept { return !unsound_; }

    /// Loads what the listener was not told of (all of `root`, without one) and returns the
    /// graph, or throws GraphError listing every problem.
    GraphDesc finish(JsonValue root, const std::vector<DuplicateKey>& duplicateKeys) {
        if (!root.isObject()) {
            into(rootDiags_);
            error("", "", "", "a graph file must be a JSON object");
        } else {
            loadRoot(root);
        }
        checkPassNames();
        checkOutputsAreUsed();
        FileProblems::Part repeatedKeys;
        into(repeatedKeys);
        for (const auto& dup : duplicateKeys) reportDuplicate(dup);
        Diagnostics diags;
        for (FileProblems::Part* part : {&rootDiags_, &featureDiags_, &resourceDiags_, &passDiags_, &repeatedKeys})
            for (Diagnostic& d : *part) diags.add(std::move(d));
        if (diags.empty()) checkReadsHaveSourcesAtLoad(graph_, diags);
        if (!diags.empty()) throw GraphError(std::move(diags));
        return std::move(graph_);
    }

    // ---- JsonListener ----------------------------------------------------------------
    void rootMember(std::string_view key, JsonValue value) override {
        if (key == "features" || key == "resources") {
            bool& seen = key == "features" ? featuresSeen_ : resourcesSeen_;
            if (seen || passesStreamed_) unsound_ = true;
            seen = true;
            if (unsound_) return;
            if (key == "features") loadFeatures(value);
            else loadResources(value);
        } else if (key == "passes") {
            if (passesSeen_) unsound_ = true;
            passesSeen_ = true;
        }
    }
    bool streamArray(std::string_view key, size_t offset) override {
        if (key != "passes" || passesSeen_ || !resourcesSeen_ || unsound_) return false;
        passesStreamed_ = true;
        passesStart_ = offset;
        return true;
    }
    void element(size_t index, JsonValue value, size_t end) override {
        if (unsound_) return;
        // The passes' number is not known yet: guessed from the bytes of the first ones, it
        // spares the copies of growing the array one doubling at a time.
        if (index == kPassesSampled) {
            const size_t bytesPerPass = std::max<size_t>(1, (end - passesStart_) / index);
            const size_t guess = index + (textSize_ - end) / bytesPerPass;
            graph_.passes.reserve(guess + guess / 8);
            passNames_.reserve(guess + guess / 8);
            passIndex_.reserve(guess + guess / 8);
        }
        loadPass(index, value);
    }

private:
    void into(FileProblems::Part& part) { report_.into(part); }
    void error(const std::string& path, std::string_view pass, std::string_view resource,
               const std::string& message) {
        report_(path, pass, resource, message);
    }

    /// An output no pass of the file uses would silently be missing from every plan. Culling
    /// and features may still drop its passes; that the plan reports.
    void checkOutputsAreUsed() {
        if (!rootDiags_.empty() || !passDiags_.empty()) return;  // the uses may be incomplete
        into(resourceDiags_);
        std::vector<bool> used(graph_.resources.size());
        for (const PassDesc& p : graph_.passes)
            for (const UsageDecl& u : p.uses) used[u.resource] = true;
        for (size_t r = 0; r < graph_.resources.size(); ++r) {
            const ResourceDesc& d = graph_.resources[r];
            if (!used[r] && d.final != ExternalState::None && !faultyResources_[r])
                error(d.jsonPath() + ".final", "", d.name,
                      "'" + printableName(d.name) + "' is an output of the graph (`final`), but no pass uses it");
        }
    }

    /// A repeated JSON key, with the pass and resource it concerns: a path under
    /// "resources.<r>" (or `resources["<r>"]`) names resource r, one under "passes[i]" pass i,
    /// and one under "passes[i].uses.<r>" both.
    void reportDuplicate(const DuplicateKey& dup) {
        std::string pass, resource;
        const std::string& path = dup.path;
        if (size_t at = 9; path.starts_with("resources"))
            if (auto name = readPathMember(path, at)) resource = std::move(*name);
        if (path.starts_with("passes[")) {
            const size_t close = path.find(']');
            const std::string index = path.substr(7, close - 7);
            if (close != std::string::npos && !index.empty() &&
                index.find_first_not_of("0123456789") == std::string::npos && index.size() < 10) {
                if (const size_t i = std::stoul(index); i < passNames_.size()) pass = passNames_[i];
                if (size_t at = close + 6; path.compare(close + 1, 5, ".uses") == 0)
                    if (auto name = readPathMember(path, at)) resource = std::move(*name);
            }
        }
        const bool isResource = path == jsonPathMember("resources", dup.key);
        error(path, pass, resource,
              (isResource ? "duplicate resource name '" : "duplicate key '") + dup.key +
                  "'; JSON keeps only the last one");
    }

    /// The root object's own keys, and the parts the listener was not told of.
    void loadRoot(JsonValue root) {
        into(rootDiags_);
        const auto f = fieldsOf(root, kRootKeys);
        report_.unknownKeys(root, f, [] { return std::string(); }, kRootKeys);
        if (const JsonValue version = f[rootKey::version]; !version) {
            error("version", "", "", "missing; this reader understands version 1");
        } else if (!version.isInteger() || !version.equals(1)) {
            error("version", "", "", "unsupported version " + version.dump() + version.integerHint(1, 1) +
                                         "; this reader understands version 1");
        }
        if (const JsonValue name = f[rootKey::name]; name && name.isString()) {
            graph_.name = name.string();
            if (const std::string why = unprintableNameProblem(graph_.name); !why.empty())
                error("name", "", "", "'" + printableName(graph_.name) + "' " + why);
        } else {
            error("name", "", "", "missing or not a string");
        }
        for (const size_t k : {rootKey::schema, rootKey::description})
            if (const JsonValue text = f[k]; text && !text.isString())
                error(std::string(kRootKeys[k]), "", "", "expected a string, got " + text.dump());
        if (const JsonValue layouts = f[rootKey::layouts]) {
            const auto policy = layouts.isString() ? parseLayoutPolicy(layouts.string()) : std::nullopt;
            if (policy) graph_.layouts = *policy;
            else error("layouts", "", "", "expected \"fewest-barriers\" or \"optimal\", got " + layouts.dump());
        }
        if (!featuresSeen_)
            if (const JsonValue features = f[rootKey::features]) loadFeatures(features);
        if (!resourcesSeen_) loadResources(f[rootKey::resources]);
        if (passesStreamed_) return;
        into(passDiags_);
        if (const JsonValue passes = f[rootKey::passes]; passes && passes.isArray()) {
            graph_.passes.reserve(passes.size());
            passIndex_.reserve(passes.size());
            for (size_t i = 0; i < passes.size(); ++i) loadPass(i, passes[i]);
        } else {
            error("passes", "", "", "missing or not an array");
        }
    }

    void loadResources(JsonValue resources) {
        into(resourceDiags_);
        if (!resources || !resources.isObject()) {
            error("resources", "", "", "missing or not an object of named resources");
            return;
        }
        graph_.resources.reserve(resources.size());
        for (const auto& [name, value] : resources.members()) {  // in place: a ResourceDesc is large
            const size_t before = resourceDiags_.size();
            loadResource(name, value, report_, graph_.resources.emplace_back());
            faultyResources_.push_back(resourceDiags_.size() > before);
        }
        // Keys are unique: every name is new.
        resourceIndex_.reserve(graph_.resources.size());
        for (size_t i = 0; i < graph_.resources.size(); ++i)
            resourceIndex_.insert(graph_.resources[i].name, static_cast<uint32_t>(i));
    }

    void loadFeatures(JsonValue features) {
        into(featureDiags_);
        if (!features.isObject()) {
            error("features", "", "", "must be an object of feature name -> true/false");
            return;
        }
        for (const auto& [key, value] : features.members()) {
            const std::string name(key);
            if (!Condition::isFeatureName(name))
                error(jsonPathMember("features", name), "", "", "'" + printableName(name) + "' is not a valid feature name");
            if (!value.isBoolean())
                error(jsonPathMember("features", name), "", "", "default must be true or false");
            graph_.features.push_back({name, value.isBoolean() && value.boolean()});
        }
    }

    // ---- passes ----------------------------------------------------------------------
    static std::string passPath(size_t index) { return "passes[" + std::to_string(index) + "]"; }

    void loadPass(size_t index, JsonValue v) {
        into(passDiags_);
        if (index >= passNames_.size()) passNames_.resize(index + 1);
        if (!v.isObject()) {
            error(passPath(index), "", "", "a pass must be an object");
            return;
        }
        const size_t problemsBeforePass = passDiags_.size();
        PassDesc& p = graph_.passes.emplace_back();  // built in place: a PassDesc is large
        p.jsonPath = passPath(index);
        const std::string& path = p.jsonPath;
        useIndices_.clear();
        const auto f = fieldsOf(v, kPassKeys);
        const JsonValue name = f[passKey::name];
        if (name && name.isString() && !name.string().empty())
            p.name = name.string();
        else
            error(path + ".name", "", "", "missing or not a non-empty string");
        if (const std::string why = unprintableNameProblem(p.name); !why.empty()) {
            error(path + ".name", "", "", "'" + printableName(p.name) + "' " + why);
            p.name.clear();
        }
        if (p.name.find(' ') != std::string::npos) refuseInsertedStepName(path, p.name);
        report_.unknownKeys(v, f, [&] { return path; }, kPassKeys, p.name);
        if (!p.name.empty()) {
            passNames_[index] = name.string();
            const PassIndex::Key key = PassIndex::keyOf(name.string());
            passIndex_.prefetch(key);
            namesToCheck_.push_back({static_cast<uint32_t>(index), passDiags_.size(), key});
            if (namesToCheck_.size() == kNamesCheckedTogether) checkPassNames();
        }

        const PassTypeInfo* type = nullptr;
        if (const JsonValue t = f[passKey::type]; t && t.isString()) {
            p.type = t.string();
            type = findType(p.type);
            if (!type)
                error(path + ".type", p.name, "", "unknown pass type '" + p.type +
                                                      "'; registered: " + joinNames(registry_.names()));
        } else {
            error(path + ".type", p.name, "", "missing or not a string");
        }
        if (const JsonValue cond = f[passKey::condition]) loadCondition(p, cond);
        if (const JsonValue nc = f[passKey::neverCull]) {
            if (nc.isBoolean()) p.neverCull = nc.boolean();
            else error(path + ".never_cull", p.name, "", "expected true or false");
        }
        if (const JsonValue q = f[passKey::queue]) {
            const auto queue = q.isString() ? parseQueueKind(q.string()) : std::nullopt;
            if (queue) p.queue = *queue;
            else error(path + ".queue", p.name, "", "expected \"graphics\", \"compute\" or \"transfer\", got " + q.dump());
        }
        if (const JsonValue text = f[passKey::description]; text && !text.isString())
            error(path + ".description", p.name, "", "expected a string, got " + text.dump());
        if (const JsonValue params = f[passKey::params]) {
            if (!params.isObject()) error(path + ".params", p.name, "", "expected an object");
            else if (params.size() != 0) p.params = PassParams(params.toJson());
        }
        if (type && type->validateParams) {
            // The application's code: an exception from it (nlohmann's at() and get<T>() throw)
            // is a problem with these params, not with the file's JSON.
            std::vector<ParamError> problems;
            try {
                problems = type->validateParams(p.params);
            } catch (const std::exception& e) {
                error(path + ".params", p.name, "", "the params validator of type '" + type->name + "' threw: " + e.what());
            } catch (...) {
                error(path + ".params", p.name, "", "the params validator of type '" + type->name +
                                                        "' threw something other than a std::exception");
            }
            for (const auto& e : problems)
                error(e.pathUnder(path + ".params"), p.name, "", e.message);
        }
        if (const JsonValue uses = f[passKey::uses]) {
            loadUses(p, uses);
            if ((uses.isObject() || uses.isArray()) && uses.size() == 0)
                error(path + ".uses", p.name, "", "empty; a pass that uses nothing does nothing");
        } else {
            error(path + ".uses", p.name, "", "missing; a pass that uses nothing does nothing");
        }
        if (type) bindSlots(p, *type);
        if (type && type->validateUsages && passDiags_.size() == problemsBeforePass) checkUsagesWithType(p, *type);
        if (type) checkQueue(p, *type);
        checkOverlaps(p);
        checkAttachments(p);
    }

    /// Enters the names of the passes loaded since the last call, in file order, reporting
    /// each name an earlier pass has. In batches: on a large graph the table of names is far
    /// larger than the cache, and the misses of lookups started together overlap. A repeated
    /// name's diagnostic goes where the pass's problems were at its name.
    void checkPassNames() {
        size_t inserted = 0;
        for (const PendingName& n : namesToCheck_) {
            const auto [first, fresh] = passIndex_.insert(passNames_[n.pass], n.pass, n.key);
            if (fresh) continue;
            const std::string path = passPath(n.pass);
            passDiags_.insert(passDiags_.begin() + static_cast<std::ptrdiff_t>(n.problemsBefore + inserted++),
                              report_.diagnostic(path + ".name", passNames_[n.pass], "",
                                                 "duplicate pass name; the first is " + passPath(first)));
        }
        namesToCheck_.clear();
    }

    /// The compiler names the steps it inserts into a frame "<verb> <resource>"
    /// (docs/graph-format.md, "Compiled plan"): a pass of such a name would make two steps of
    /// one name in a plan, in its timings and in its DOT graph. (The setup plan's steps are in
    /// a plan of their own.)
    void refuseInsertedStepName(const std::string& path, const std::string& name) {
        static constexpr std::string_view kVerbs[] = {"clear ", "clobber ", "read back "};
        for (const std::string_view verb : kVerbs) {
            if (!name.starts_with(verb)) continue;
            const std::string_view resource = std::string_view(name).substr(verb.size());
            if (!resourceIndex_.find(resource)) continue;
            error(path + ".name", name, resource,
                  "'" + name + "' is the name the compiler gives the step it inserts to " +
                      std::string(verb.substr(0, verb.size() - 1)) + " '" + std::string(resource) +
                      "'; choose another");
            return;
        }
    }

    /// Passes of one type usually come in runs: the last type found is asked first.
    const PassTypeInfo* findType(const std::string& name) {
        if (!lastType_ || lastType_->name != name) lastType_ = registry_.find(name);
        return lastType_;
    }

    void loadCondition(PassDesc& p, JsonValue v) {
        const std::string path = p.jsonPath + ".if";
        if (!v.isString()) {
            error(path, p.name, "", "expected a string expression such as \"skybox && !debug\"");
            return;
        }
        const std::string text(v.string());
        std::string err;
        auto cond = Condition::parse(text, err);
        if (!cond) {
            error(path, p.name, "", "bad expression \"" + text + "\": " + err);
            return;
        }
        for (const auto& f : cond->features()) {
            bool known = std::any_of(graph_.features.begin(), graph_.features.end(),
                                     [&](const FeatureDecl& d) { return d.name == f; });
            if (!known) {
                std::vector<std::string> names;
                // A declaration refused for its name has its own error; it is no suggestion.
                for (const auto& d : graph_.features)
                    if (Condition::isFeatureName(d.name)) names.push_back(d.name);
                error(path, p.name, "", "unknown feature '" + f + "'; the file declares: " + joinNames(names));
            }
        }
        p.condition = *cond;
    }

    /// Looks up the resources of a pass's usages all at once, before loading them: on a large
    /// graph the name table and the resources are far larger than the cache, and misses that
    /// are started together overlap instead of waiting one for the other. ahead_[i].found is
    /// entry i's resource, if it names a declared one.
    void lookUpAhead(JsonValue uses) {
        ahead_.clear();
        for (const auto& [key, value] : uses.members()) {
            Ahead& a = ahead_.emplace_back();
            a.name = key;  // the object form
            if (uses.isArray()) {
                const JsonValue res = value.isObject() ? value.find("resource") : JsonValue();
                a.named = res && res.isString();
                a.name = a.named ? res.string() : std::string_view();
            }
            a.key = ResourceIndex::keyOf(a.name);
            resourceIndex_.prefetch(a.key);
        }
        for (Ahead& a : ahead_) {
            if (!a.named || !(a.found = resourceIndex_.find(a.name, a.key))) continue;
            const auto* record = reinterpret_cast<const char*>(&graph_.resources[*a.found]);
            __builtin_prefetch(record);
            __builtin_prefetch(record + 64);
        }
    }

    void loadUses(PassDesc& p, JsonValue uses) {
        auto path = [&] { return p.jsonPath + ".uses"; };
        p.usesByName = uses.isObject();
        p.uses.reserve(uses.isObject() || uses.isArray() ? uses.size() : 0);
        if (uses.isObject() || uses.isArray()) lookUpAhead(uses);
        if (uses.isObject()) {
            size_t i = 0;
            for (const auto& [name, value] : uses.members()) {
                const std::optional<uint32_t> found = ahead_[i++].found;
                auto upath = [&, name = name] { return jsonPathMember(path(), name); };
                if (!value.isString()) {
                    error(upath(), p.name, name, "expected \"Access@Stage\", e.g. \"Read@Fragment\"");
                    continue;
                }
                const std::string_view text = value.string();
                const size_t at = text.find('@');
                if (at == std::string_view::npos) {
                    error(upath(), p.name, name, "expected \"Access@Stage\", got \"" + std::string(text) + "\"");
                    continue;
                }
                loadUsage(p, name, found, UsageEntry{{}, true, text.substr(0, at), text.substr(at + 1)}, 0, upath);
            }
        } else if (uses.isArray()) {
            for (size_t i = 0; i < uses.size(); ++i) {
                auto upath = [&] { return path() + "[" + std::to_string(i) + "]"; };
                const JsonValue entry = uses[i];
                if (!entry.isObject()) {
                    error(upath(), p.name, "", "expected {\"resource\", \"access\", \"stage\", ...}");
                    continue;
                }
                UsageEntry e{fieldsOf(entry, kUsageKeys), false, {}, {}};
                const JsonValue res = e.fields[usageKey::resource];
                const std::string_view resName = res && res.isString() ? res.string() : std::string_view();
                report_.unknownKeys(entry, e.fields, upath, kUsageKeys, p.name, resName);
                if (!res || !res.isString()) {
                    error(!res ? upath() : upath() + ".resource", p.name, "",
                          "expected \"resource\": the name of a declared resource");
                    continue;
                }
                loadUsage(p, resName, ahead_[i].found, e, static_cast<uint32_t>(i), upath);
            }
        } else {
            error(path(), p.name, "", "expected an object (resource -> \"Access@Stage\") or an array of usage objects");
        }
    }

    /// One usage of `resName` (`found`: its index, if declared); `fileIndex` is its place in
    /// an array of uses (for its path).
    template <typename Path>
    void loadUsage(PassDesc& p, std::string_view resName, std::optional<uint32_t> found, const UsageEntry& e,
                   uint32_t fileIndex, Path&& path) {
        auto fail = [&](const std::string& msg) { error(path(), p.name, resName, msg); };
        // In a usage object, an error about a key it has points at that key; one about a
        // missing key, at the object. The short form's "Access@Stage" string has no keys inside.
        auto failAt = [&](const char* key, const std::string& msg) {
            const bool present = !e.split && e.fields[keyIndex(kUsageKeys, key)];
            error(present ? path() + "." + key : path(), p.name, resName, msg);
        };
        if (!found) {
            std::vector<std::string> names;
            for (const auto& r : graph_.resources) names.push_back(r.name);
            return failAt("resource", "unknown resource; declared: " + joinNames(names));
        }
        const ResourceDesc* res = &graph_.resources[*found];
        UsageDecl u;
        u.resource = *found;
        const JsonValue accessValue = e.fields[usageKey::access], stageValue = e.fields[usageKey::stage];
        const auto access = e.split ? parseAccess(e.access)
                            : accessValue && accessValue.isString() ? parseAccess(accessValue.string())
                                                                    : std::nullopt;
        const auto stage = e.split ? parseStage(e.stage)
                           : stageValue && stageValue.isString() ? parseStage(stageValue.string())
                                                                 : std::nullopt;
        if (!access)
            failAt("access", "unknown access " +
                 (e.split ? dumpString(e.access) : accessValue ? accessValue.dump() : "(missing)") +
                 "; expected Read, Write or ReadWrite");
        if (!stage)
            failAt("stage", "unknown stage " + (e.split ? dumpString(e.stage) : stageValue ? stageValue.dump() : "(missing)") +
                 "; expected ColorAttachment, DepthAttachment, Vertex, Fragment, Compute, "
                 "Transfer, VertexInput or Indirect");
        if (!access || !stage) return;
        u.usage.access = *access;
        u.usage.stage = *stage;
        if (const JsonValue as = e.fields[usageKey::as]) {
            auto parsed = as.isString() ? parseBindAs(as.string()) : std::nullopt;
            if (!parsed) return failAt("as", "unknown `as` " + as.dump() + "; expected sampled, storage, uniform or index");
            u.usage.as = *parsed;
        }
        if (const JsonValue slot = e.fields[usageKey::slot]) {
            if (!slot.isString() || slot.string().empty())
                return failAt("slot", "`slot` must name a slot of the pass type");
            u.slot = graph_.internSlot(slot.string());
        }
        // A resource whose declaration was refused has no description to check a usage against:
        // its own error says what to mend, and follow-on errors would only mislead.
        const bool described = !faultyResources_[static_cast<size_t>(res - graph_.resources.data())];
        const JsonValue mips = e.fields[usageKey::mips], layers = e.fields[usageKey::layers];
        if (mips || layers) {
            // A full chain's length is known here for fixed extents only; for output-relative
            // ones the compiler clips the range to the chain it resolves.
            const uint32_t levels = res->mips != 0 ? res->mips
                                    : res->extent.relativeToOutput
                                        ? static_cast<uint32_t>(std::bit_width(kMaxImageExtent))
                                        : res->mipCount(0, 0);
            SubresourceRange range{0, levels, 0, res->layers};
            auto pair = [&](const char* key, JsonValue it, uint32_t& first, uint32_t& count) {
                if (!it) return true;
                if (!res->isImage()) return failAt(key, std::string("buffers have no ") + key), false;
                if (!it.isArray() || it.size() != 2 || !it[0].isUnsigned() || !it[1].isUnsigned() ||
                    it[1].number<uint64_t>() == 0)
                    return failAt(key, std::string("`") + key + "` must be [first, count] with count >= 1, got " +
                                           it.dump() + it.integersHint(0, kMaxLayers)),
                           false;
                // Past any image's levels or layers: said here, before the numbers are narrowed.
                if (it[0].number<uint64_t>() > kMaxLayers || it[1].number<uint64_t>() > kMaxLayers)
                    return failAt(key, std::string("`") + key + "` " + it.dump() + " is past any image's " +
                                (key == std::string_view("mips")
                                     ? "mip levels (at most " + std::to_string(std::bit_width(kMaxImageExtent)) + ")"
                                     : "layers (at most " + std::to_string(kMaxLayers) + ")")),
                           false;
                first = it[0].number<uint32_t>();
                count = it[1].number<uint32_t>();
                return true;
            };
            if (!pair("mips", mips, range.baseMip, range.mipCount) ||
                !pair("layers", layers, range.baseLayer, range.layerCount))
                return;
            // A resource whose declaration was refused has no bounds to check against.
            if (described && range.baseMip + range.mipCount > levels)
                return failAt("mips", "mips [" + std::to_string(range.baseMip) + ", " +
                                          std::to_string(range.mipCount) + "] exceed the resource's " +
                                          std::to_string(levels) + " mip levels" + chainNote(*res));
            if (described && range.baseLayer + range.layerCount > res->layers)
                return failAt("layers", "layers [" + std::to_string(range.baseLayer) + ", " +
                                            std::to_string(range.layerCount) + "] exceed the resource's " +
                                            std::to_string(res->layers) + " layers");
            u.usage.range = range;
        }
        std::string problem = described ? usageProblem(*res, u.usage) : std::string();
        if (!problem.empty()) return fail(problem);
        u.usage.as = resolvedBinding(u.usage.mode(), res->isImage());
        p.uses.push_back(u);
        useIndices_.push_back(fileIndex);
    }

    /// Where a mip count that the file leaves to the compiler comes from, for a range past it.
    static std::string chainNote(const ResourceDesc& r) {
        if (r.mips != 0) return {};
        if (r.extent.relativeToOutput) return " (the most any image can have)";
        return " (the full chain of " + std::to_string(r.extent.width) + "x" + std::to_string(r.extent.height) + ")";
    }

    /// The JSON path of usage `i` of the pass being loaded: a usage that failed to load
    /// leaves a gap in an array's numbering, so it is not always GraphDesc::usageJsonPath.
    std::string usePath(const PassDesc& p, size_t i) const {
        if (p.usesByName) return jsonPathMember(p.jsonPath + ".uses", graph_.resources[p.uses[i].resource].name);
        return p.jsonPath + ".uses[" + std::to_string(useIndices_[i]) + "]";
    }

    /// A pass runs only on a queue that its type allows and whose kind supports every stage it
    /// uses: one error per usage that its queue cannot perform.
    void checkQueue(const PassDesc& p, const PassTypeInfo& type) {
        const std::string where = p.jsonPath + ".queue";
        const std::string on = "runs on the " + std::string(toString(p.queue)) + " queue";
        if (!type.queues.empty() && std::find(type.queues.begin(), type.queues.end(), p.queue) == type.queues.end()) {
            std::string allowed;
            for (QueueKind q : type.queues) allowed += (allowed.empty() ? "" : ", ") + std::string(toString(q));
            error(where, p.name, "", on + ", but pass type " + p.type + " records only on: " + allowed);
            return;
        }
        for (size_t i = 0; i < p.uses.size(); ++i) {
            const ResourceDesc& r = graph_.resources[p.uses[i].resource];
            if (std::string problem = queueProblem(p.queue, r, p.uses[i].usage); !problem.empty())
                error(where, p.name, r.name, std::move(problem));
        }
    }

    /// The type's own checks, on a pass whose usages all bound to declared resources.
    void checkUsagesWithType(const PassDesc& p, const PassTypeInfo& type) {
        for (const UsageDecl& u : p.uses)
            if (faultyResources_[u.resource]) return;  // its declaration's error says enough
        std::vector<UsageError> problems;
        try {
            problems = type.validateUsages(p, graph_);
        } catch (const std::exception& e) {  // the application's code, as validateParams
            error(p.jsonPath + ".uses", p.name, "", "the usage validator of type '" + type.name + "' threw: " + e.what());
        } catch (...) {
            error(p.jsonPath + ".uses", p.name, "", "the usage validator of type '" + type.name +
                                                        "' threw something other than a std::exception");
        }
        for (const UsageError& e : problems) {
            if (e.usage < p.uses.size())
                error(usePath(p, e.usage), p.name, graph_.resources[p.uses[e.usage].resource].name, e.message);
            else
                error(p.jsonPath + ".uses", p.name, "", e.message);
        }
    }

    std::string alreadyFilled(const PassDesc& p, const PassTypeInfo& type, size_t slot) const {
        return "slot '" + type.slots[slot].name + "' of " + type.name + " is already filled by '" +
               graph_.resources[p.uses[filled_[slot]].resource].name + "'";
    }

    void bindSlots(PassDesc& p, const PassTypeInfo& type) {
        if (type.acceptsAnyUsage) {
            for (size_t i = 0; i < p.uses.size(); ++i)
                if (!graph_.slotName(p.uses[i].slot).empty())
                    error(usePath(p, i) + ".slot", p.name, graph_.resources[p.uses[i].resource].name,
                          type.name + " takes any usage and has no slots; remove `slot`");
            return;
        }
        // Per slot of the type (slot names are unique in a type): the first usage filling it.
        filled_.assign(type.slots.size(), kUnfilled);
        auto matches = [](const SlotDecl& s, const UsageDecl& u) { return s.accepts(u.usage.mode()); };
        auto expected = [&] {
            std::string list;
            for (const auto& s : type.slots)
                list += (list.empty() ? "" : "; ") + s.name + " (" + s.describeUsage() + ")";
            return list;
        };
        for (size_t i = 0; i < p.uses.size(); ++i) {
            UsageDecl& u = p.uses[i];
            const std::string& resName = graph_.resources[u.resource].name;
            const std::string named(graph_.slotName(u.slot));  // as the file names it, or empty
            const std::string& wanted = named.empty() ? resName : named;
            size_t slot = type.slots.size();
            for (size_t s = 0; s < type.slots.size(); ++s)
                if (type.slots[s].name == wanted) slot = s;
            if (slot == type.slots.size() && !named.empty()) {
                error(usePath(p, i) + ".slot", p.name, resName,
                      type.name + " has no slot '" + named + "'; its slots: " + expected());
                continue;
            }
            if (slot == type.slots.size()) {
                size_t candidates = 0;
                for (size_t s = 0; s < type.slots.size(); ++s)
                    if (!type.slots[s].byNameOnly && matches(type.slots[s], u) &&
                        (type.slots[s].repeated || filled_[s] == kUnfilled)) {
                        if (candidates++ == 0) slot = s;
                    }
                if (candidates > 1) {
                    error(usePath(p, i), p.name, resName, "usage " + toString(u.usage) + " fits several slots of " +
                                                              type.name + "; name one with \"slot\"");
                    continue;
                }
                if (candidates == 0) {
                    // The slots it fits may all be taken: saying so beats listing them as expected.
                    size_t taken = type.slots.size();
                    for (size_t s = 0; s < type.slots.size(); ++s)
                        if (!type.slots[s].byNameOnly && matches(type.slots[s], u)) taken = s;
                    if (taken < type.slots.size()) {
                        std::string byName;
                        for (const SlotDecl& s : type.slots)
                            if (s.byNameOnly && matches(s, u) && byName.empty())
                                byName = "; slot '" + s.name + "' takes it by name only: \"slot\": \"" + s.name + "\"";
                        error(usePath(p, i), p.name, resName, alreadyFilled(p, type, taken) + byName);
                        continue;
                    }
                    error(usePath(p, i), p.name, resName, "usage " + toString(u.usage) + " contradicts " +
                                                              type.name + "; expected " + expected());
                    continue;
                }
            }
            const SlotDecl& decl = type.slots[slot];
            if (!matches(decl, u)) {
                error(usePath(p, i), p.name, resName, "usage " + toString(u.usage) + " contradicts slot '" +
                                                          decl.name + "' of " + type.name + "; expected " +
                                                          decl.describeUsage());
                continue;
            }
            if (!decl.takes(graph_.resources[u.resource].type)) {
                error(usePath(p, i), p.name, resName, "slot '" + decl.name + "' of " + type.name + " takes " +
                                                          decl.describeTypes() + ", not '" + resName + "' of type " +
                                                          std::string(toString(graph_.resources[u.resource].type)));
                continue;
            }
            const ResourceDesc& bound = graph_.resources[u.resource];
            if (u.usage.range && !decl.takesLayers(bound, u.usage.range->baseLayer, u.usage.range->layerCount)) {
                error(usePath(p, i) + ".layers", p.name, resName,
                      "slot '" + decl.name + "' of " + type.name + " binds the whole cube: its usage must cover layers [0, " +
                          std::to_string(bound.layers) + "], not [" + std::to_string(u.usage.range->baseLayer) + ", " +
                          std::to_string(u.usage.range->layerCount) + "]");
                continue;
            }
            if (filled_[slot] != kUnfilled && !decl.repeated) {
                error(usePath(p, i), p.name, resName, alreadyFilled(p, type, slot));
                continue;
            }
            if (filled_[slot] == kUnfilled) filled_[slot] = static_cast<uint32_t>(i);
            u.slot = graph_.internSlot(decl.name);
        }
        for (size_t s = 0; s < type.slots.size(); ++s)
            if (!type.slots[s].optional && filled_[s] == kUnfilled)
                error(p.jsonPath + ".uses", p.name, "", type.name + " needs slot '" + type.slots[s].name + "' (" +
                                                            type.slots[s].describeUsage() + "); no usage fills it");
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
                    error(usePath(p, i), p.name, res.name, "overlaps " + usePath(p, j) +
                                                               "; one pass may use each subresource once");
            }
    }

    void checkAttachments(const PassDesc& p) {
        size_t colors = 0;
        std::optional<size_t> depth;
        for (size_t i = 0; i < p.uses.size(); ++i) {
            const Stage stage = p.uses[i].usage.stage;
            const std::string& name = graph_.resources[p.uses[i].resource].name;
            if (stage == Stage::ColorAttachment && ++colors == kMaxColorAttachments + 1)
                error(usePath(p, i), p.name, name, extraColorAttachmentProblem(colors));
            if (stage != Stage::DepthAttachment) continue;
            if (depth)
                error(usePath(p, i), p.name, name, secondDepthAttachmentProblem(usePath(p, *depth)));
            else
                depth = i;
        }
    }

    static constexpr size_t kPassesSampled = 256;

    /// NameIndex's view of the names it holds.
    struct ResourceName {
        const GraphDesc* graph;
        std::string_view operator()(uint32_t i) const { return graph->resources[i].name; }
    };
    struct PassName {
        const std::vector<std::string_view>* names;
        std::string_view operator()(uint32_t i) const { return (*names)[i]; }
    };

    const PassRegistry& registry_;
    const size_t textSize_;
    size_t passesStart_ = 0;
    GraphDesc graph_;
    FileProblems::Part rootDiags_, featureDiags_, resourceDiags_, passDiags_;
    FileProblems report_;
    bool featuresSeen_ = false, resourcesSeen_ = false, passesSeen_ = false;
    bool passesStreamed_ = false;
    bool unsound_ = false;
    /// JSON index -> pass name (empty: none). Names view the document, which outlives them.
    std::vector<std::string_view> passNames_;
    using ResourceIndex = NameIndex<ResourceName>;
    ResourceIndex resourceIndex_{ResourceName{&graph_}};  ///< name -> graph_.resources
    using PassIndex = NameIndex<PassName>;
    PassIndex passIndex_{PassName{&passNames_}};  ///< pass name -> JSON index of the first
    /// Loaded passes whose names are yet to be entered (checkPassNames), and how many problems
    /// the passes had before each's name.
    struct PendingName {
        uint32_t pass;
        size_t problemsBefore;
        PassIndex::Key key;
    };
    static constexpr size_t kNamesCheckedTogether = 16;
    std::vector<PendingName> namesToCheck_;
    const PassTypeInfo* lastType_ = nullptr;
    /// Of the pass being loaded, beside PassDesc::uses: each usage's index in an array of
    /// uses, for its JSON path.
    std::vector<uint32_t> useIndices_;
    std::vector<bool> faultyResources_;  ///< Per resource: its declaration had an error.
    static constexpr uint32_t kUnfilled = ~0u;
    std::vector<uint32_t> filled_;           ///< bindSlots: per slot, the first usage filling it
    struct Ahead {
        std::string_view name;
        bool named = true;  ///< Whether the entry names a resource at all.
        ResourceIndex::Key key{};
        std::optional<uint32_t> found;
    };
    std::vector<Ahead> ahead_;  ///< lookUpAhead's, per entry of the pass's `uses`
};

}  // namespace

GraphDesc parseGraph(std::string_view text, const std::string& fileName, const PassRegistry& registry) {
    GraphLoader loader(fileName, registry, text.size());
    const JsonRead read = readJson(text, &loader);
    if (!read.error.empty()) loader.refuse(read);
    if (loader.toldSoundly()) return loader.finish(read.document.root(), read.duplicateKeys);
    // Told of parts that the file repeats or gives late: load the whole document afresh.
    GraphLoader whole(fileName, registry, text.size());
    const JsonRead again = readJson(text);
    return whole.finish(again.document.root(), again.duplicateKeys);
}

GraphDesc loadGraphFile(const std::filesystem::path& path, const PassRegistry& registry) {
    const auto fail = [&](const std::string& message) {
        Diagnostics d;
        d.add({path.string(), "", "", "", message});
        throw GraphError(std::move(d));
    };
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    // The reason tells a missing file from one the user may not read.
    if (!in) fail(errno ? "cannot open the file: " + std::generic_category().message(errno) : "cannot open the file");
    // In pieces, up to the limit: a device or a pipe need not end.
    std::string text;
    std::array<char, 1 << 16> piece;
    while (in.read(piece.data(), piece.size()) || in.gcount() > 0) {
        text.append(piece.data(), size_t(in.gcount()));
        if (text.size() > kMaxGraphFileBytes)
            fail("is larger than " + std::to_string(kMaxGraphFileBytes >> 20) + " MiB, the most a graph file may be");
    }
    if (in.bad()) fail("cannot read the file (a directory?)");
    return parseGraph(text, path.string(), registry);
}

}  // namespace skygraph
