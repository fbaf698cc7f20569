// The recording code the executor's tests render with: the built-in library's Generic alone,
// so every pass type, built-in ones included, runs as Generic and performs exactly its
// declared accesses, which synchronization validation then checks.
#pragma once

#include <skygraph/pass.hpp>
#include <skygraph/renderer.hpp>

#include <cstdint>

namespace skygraph::test {

inline const PassLibrary& genericPasses() { return PassLibrary::genericOnly(); }

/// RendererOptions that run every pass with genericPasses().
inline RendererOptions genericOptions(uint32_t framesInFlight = 2) {
    RendererOptions o;
    o.framesInFlight = framesInFlight;
    o.passes = &genericPasses();
    return o;
}

}  // namespace skygraph::test
