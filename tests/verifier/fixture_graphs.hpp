// Small graphs for the negative controls: each compiles to a plan with one barrier of the
// kind a control weakens, and verifies with no findings as compiled.
#pragma once

namespace skygraph::test::fixtures {

/// `a` is written, read, and then `b` takes over its memory: b's aliasing barrier waits for
/// the read (an execution dependency from COMPUTE_SHADER, no access).
inline constexpr const char* kAliasAfterRead = R"({ "version": 1, "name": "alias_after_read",
  "resources": {
    "a": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
    "b": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "write_a", "type": "Generic", "uses": [ { "resource": "a", "access": "Write", "stage": "Compute" } ] },
    { "name": "read_a", "type": "Generic", "never_cull": true, "uses": [ { "resource": "a", "access": "Read", "stage": "Compute" } ] },
    { "name": "write_b", "type": "Generic", "uses": [ { "resource": "b", "access": "Write", "stage": "Compute" } ] },
    { "name": "present", "type": "Generic", "uses": [ { "resource": "b", "access": "Read", "stage": "Fragment" },
                                                     { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";

/// `a` is written and never read, then `b` takes over its memory: b's aliasing barrier makes
/// a's write available (COMPUTE_SHADER / SHADER_STORAGE_WRITE).
inline constexpr const char* kAliasAfterWrite = R"({ "version": 1, "name": "alias_after_write",
  "resources": {
    "a": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
    "b": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "write_a", "type": "Generic", "never_cull": true, "uses": [ { "resource": "a", "access": "Write", "stage": "Compute" } ] },
    { "name": "write_b", "type": "Generic", "uses": [ { "resource": "b", "access": "Write", "stage": "Compute" } ] },
    { "name": "present", "type": "Generic", "uses": [ { "resource": "b", "access": "Read", "stage": "Fragment" },
                                                     { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";

/// Two dispatches write the same storage buffer, then a draw reads it: a write-after-write
/// between dispatches (COMPUTE_SHADER / SHADER_STORAGE_WRITE on both sides of the barrier).
inline constexpr const char* kStorageWriteAfterWrite = R"({ "version": 1, "name": "storage_waw",
  "resources": {
    "buf": { "type": "buffer", "size": 256 },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "first", "type": "Generic", "never_cull": true, "uses": [ { "resource": "buf", "access": "Write", "stage": "Compute" } ] },
    { "name": "second", "type": "Generic", "uses": [ { "resource": "buf", "access": "Write", "stage": "Compute" } ] },
    { "name": "present", "type": "Generic", "uses": [ { "resource": "buf", "access": "Read", "stage": "Fragment" },
                                                     { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";

/// An exported buffer is read by a draw and then written by a dispatch: a write-after-read
/// (FRAGMENT_SHADER / NONE -> COMPUTE_SHADER / SHADER_STORAGE_WRITE). Its copy pass is a
/// ReadWrite transfer, ordered within the pass by an in-pass barrier.
inline constexpr const char* kWriteAfterRead = R"({ "version": 1, "name": "war",
  "resources": {
    "buf": { "type": "buffer", "size": 256, "external": true, "final": "General" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "read", "type": "Generic", "never_cull": true, "uses": [ { "resource": "buf", "access": "Read", "stage": "Fragment" },
                                                                       { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] },
    { "name": "write", "type": "Generic", "uses": [ { "resource": "buf", "access": "Write", "stage": "Compute" } ] },
    { "name": "copy", "type": "Generic", "uses": [ { "resource": "buf", "access": "ReadWrite", "stage": "Transfer" } ] } ] })";

/// The smallest graph that shows the known finding: `a` has two mips; its mip 0 is written,
/// then read (the barrier between names mip 0 only), then `b` takes over its memory and its
/// aliasing barrier waits for the read with an execution dependency alone.
inline constexpr const char* kPartialAvailabilityBeforeAliasing = R"({ "version": 1, "name": "partial_availability",
  "resources": {
    "a": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "mips": 2 },
    "b": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8] },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "write_a", "type": "Generic", "uses": [ { "resource": "a", "access": "Write", "stage": "Compute", "mips": [0, 1] } ] },
    { "name": "read_a", "type": "Generic", "never_cull": true, "uses": [ { "resource": "a", "access": "Read", "stage": "Compute", "mips": [0, 1] } ] },
    { "name": "write_b", "type": "Generic", "uses": [ { "resource": "b", "access": "Write", "stage": "Compute" } ] },
    { "name": "present", "type": "Generic", "uses": [ { "resource": "b", "access": "Read", "stage": "Fragment" },
                                                     { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";


/// A resource taking over memory whose first pass uses it in two layouts: `b` (two layers)
/// takes over `a`'s bytes, and its first pass writes layer 0 as a colour attachment and layer
/// 1 in a dispatch. `a`'s dispatch wrote both layers and only layer 0 was read since, so only
/// b's aliasing barrier makes the write of layer 1 available; one barrier per layout would
/// each contain part of b.
inline constexpr const char* kMixedLayoutsTakingOverMemory = R"({ "version": 1, "name": "mixed_layouts_aliased",
  "resources": {
    "a": { "type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "layers": 2 },
    "b": { "type": "image2d_array", "format": "R16G16B16A16_SFLOAT", "extent": [64, 64], "layers": 2 },
    "c": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64], "external": true, "final": "TransferSrc" } },
  "passes": [
    { "name": "write_a", "type": "Generic", "uses": { "a": "Write@Compute" } },
    { "name": "read_a", "type": "Generic", "uses": [ { "resource": "a", "access": "Read", "stage": "Fragment", "layers": [0, 1] },
                                                   { "resource": "c", "access": "Write", "stage": "ColorAttachment" } ] },
    { "name": "write_b", "type": "Generic", "uses": [ { "resource": "b", "access": "Write", "stage": "ColorAttachment", "layers": [0, 1] },
                                                    { "resource": "b", "access": "Write", "stage": "Compute", "layers": [1, 1] } ] },
    { "name": "read_b", "type": "Generic", "uses": { "b": "Read@Fragment", "c": "ReadWrite@ColorAttachment" } } ] })";

}  // namespace skygraph::test::fixtures

namespace skygraph::test::fixtures {

/// The smallest graph that shows a known finding: an external buffer that arrives as
/// ShaderRead (whoever read it outside the frame did so in FRAGMENT_SHADER|COMPUTE_SHADER) is
/// read by a draw and then written by a dispatch, whose barrier waits for the draw alone.
inline constexpr const char* kWriteAfterOutsideReaders = R"({ "version": 1, "name": "outside_readers",
  "resources": {
    "buf": { "type": "buffer", "size": 256, "external": true, "final": "ShaderRead" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "read", "type": "Generic", "uses": [ { "resource": "buf", "access": "Read", "stage": "Fragment" },
                                                  { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] },
    { "name": "write", "type": "Generic", "uses": [ { "resource": "buf", "access": "Write", "stage": "Compute" } ] } ] })";

/// The smallest graph that shows a known finding: an exported (ShaderRead) image written by a
/// dispatch is sampled by a draw, whose barrier moves it to SHADER_READ_ONLY_OPTIMAL for
/// FRAGMENT_SHADER; the final barrier that hands it on to FRAGMENT_SHADER|COMPUTE_SHADER
/// sources from the dispatch's stage, so it does not chain after that transition.
inline constexpr const char* kExportAfterSampling = R"({ "version": 1, "name": "export_after_sampling",
  "resources": {
    "img": { "type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "final": "ShaderRead" },
    "swapchain": { "type": "image2d", "format": "B8G8R8A8_UNORM", "extent": "output", "external": true, "final": "Present" } },
  "passes": [
    { "name": "write", "type": "Generic", "uses": [ { "resource": "img", "access": "Write", "stage": "Compute" } ] },
    { "name": "present", "type": "Generic", "uses": [ { "resource": "img", "access": "Read", "stage": "Fragment" },
                                                     { "resource": "swapchain", "access": "Write", "stage": "ColorAttachment" } ] } ] })";

}  // namespace skygraph::test::fixtures
