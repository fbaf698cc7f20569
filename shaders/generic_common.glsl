// Shared by the GLSL that the executor generates for the built-in Generic pass.
// A fullscreen triangle that both vertex ids {0,1,2} and the index list {3,1,0} produce,
// so that non-indexed, indexed and indirect draws all cover the whole render area.
#ifndef SKYGRAPH_GENERIC_COMMON
#define SKYGRAPH_GENERIC_COMMON

const vec2 kFullscreen[4] = vec2[](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0),
                                   vec2(-1.0, 3.0));

// Buffers written by Generic passes hold a draw-indirect header (valid for
// vkCmdDrawIndirect, vkCmdDrawIndexedIndirect and as the index list {3,1,0}) followed by
// the pass's value as float bits. Readers take element kValueIndex.
const uint kValueIndex = 8u;

uint genericBufferWord(uint i, vec4 value) {
    if (i == 0u) return 3u;
    if (i == 1u) return 1u;
    if (i < kValueIndex) return 0u;
    return floatBitsToUint(value.x);
}

// What a Generic pass writes to its color attachments, given the sum of its reads and its
// params.color. Edit to post-process every Generic output (hot reload picks it up).
vec4 genericOutput(vec4 acc) { return acc; }

#endif
