// PassLibrary and RecordContext: the executor-side plumbing of pass implementations.
#include <skygraph/pass.hpp>

#include <stdexcept>

namespace skygraph {

void PassLibrary::add(PassTypeInfo info, PassFactory factory) {
    if (!factory) throw std::invalid_argument("pass type '" + info.name + "' has no factory");
    const std::string name = info.name;
    if (factories_.count(name) != 0 || registry_.find(name) != nullptr)
        throw std::invalid_argument("pass type '" + name + "' is already registered");
    registry_.add(std::move(info));  // validates slots; throws before anything is stored
    factories_.emplace(name, std::move(factory));
}

const PassFactory* PassLibrary::factory(std::string_view type) const noexcept {
    auto it = factories_.find(type);
    return it == factories_.end() ? nullptr : &it->second;
}

const BoundResource* RecordContext::slot(std::string_view name, size_t nth) const noexcept {
    for (const BoundResource& r : resources) {
        if (r.usage && r.usage->slot == name) {
            if (nth == 0) return &r;
            --nth;
        }
    }
    return nullptr;
}

}  // namespace skygraph
