#!/usr/bin/env python3
"""Writes the hand-made part of the fuzz seed corpus (tests/fuzz/corpus/seed_*.json): valid
graphs that exercise every resource type, subresource range and condition, and one broken
graph per loader/compiler error class. Re-run it after changing the list; the output is
committed so that CI needs no Python step. Inputs that once broke the compiler are added
as crash_*.json by hand (see docs/reliability.md)."""
import copy, json, os, sys

BASE = {
    "version": 1, "name": "seed",
    "features": {"geo": True, "sky": False},
    "resources": {
        "depth": {"type": "image2d", "format": "D32_SFLOAT", "extent": "output", "clear": {"depth": 1.0}},
        "hdr": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output",
                "clear": {"color": [0, 0, 0, 1]}},
        "cube": {"type": "cube", "format": "R16G16B16A16_SFLOAT", "extent": [16, 16], "mips": 3},
        "arr": {"type": "image2d_array", "format": "R8G8B8A8_UNORM", "extent": [8, 8], "layers": 4,
                "external": True, "initial": "ShaderRead", "final": "ShaderRead"},
        "chain": {"type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": [32, 32], "mips": "full",
                  "clear": {"color": [0, 0, 0, 0]}},
        "buf": {"type": "buffer", "size": 256, "external": True, "final": "General"},
        "swapchain": {"type": "image2d", "format": "B8G8R8A8_SRGB", "extent": "output",
                      "external": True, "final": "Present"},
    },
    "passes": [
        {"name": "faces", "type": "Generic", "never_cull": True, "uses": [
            {"resource": "cube", "access": "Write", "stage": "ColorAttachment", "mips": [0, 1], "layers": [0, 1]},
            {"resource": "cube", "access": "Write", "stage": "Compute", "mips": [0, 1], "layers": [1, 5]}]},
        {"name": "mips", "type": "Generic", "never_cull": True, "uses": [
            {"resource": "cube", "access": "Read", "stage": "Compute", "mips": [0, 1]},
            {"resource": "cube", "access": "Write", "stage": "Compute", "mips": [1, 2]},
            {"resource": "chain", "access": "Read", "stage": "Transfer", "mips": [0, 1]},
            {"resource": "chain", "access": "Write", "stage": "Transfer", "mips": [1, 5]}]},
        {"name": "forward", "type": "Generic", "if": "geo && !sky", "uses": {
            "depth": "Write@DepthAttachment", "hdr": "Write@ColorAttachment", "cube": "Read@Fragment"}},
        {"name": "sky", "type": "Generic", "if": "sky || (geo && sky)", "uses": {
            "depth": "Read@DepthAttachment", "hdr": "ReadWrite@ColorAttachment"}},
        {"name": "sim", "type": "Generic", "uses": [
            {"resource": "buf", "access": "ReadWrite", "stage": "Compute"},
            {"resource": "arr", "access": "Read", "stage": "Fragment", "layers": [2, 2]}]},
        {"name": "draw", "type": "Generic", "uses": [
            {"resource": "buf", "access": "Read", "stage": "Indirect"},
            {"resource": "hdr", "access": "Read", "stage": "Fragment", "as": "sampled"},
            {"resource": "swapchain", "access": "Write", "stage": "ColorAttachment"}]},
    ],
}


def mutate(path, value):
    g = copy.deepcopy(BASE)
    node = g
    for key in path[:-1]:
        node = node[key]
    if value is DELETE:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return g


DELETE = object()
SEEDS = {
    "valid": BASE,
    "minimal": {"version": 1, "name": "m", "resources": {"s": {"type": "image2d", "format": "B8G8R8A8_UNORM",
                "extent": "output", "external": True, "final": "Present"}},
                "passes": [{"name": "p", "type": "Generic", "uses": {"s": "Write@ColorAttachment"}}]},
    "bad_version": mutate(["version"], 2),
    "no_passes": mutate(["passes"], DELETE),
    "unknown_type": mutate(["passes", 0, "type"], "NoSuchPass"),
    "unknown_resource": mutate(["passes", 2, "uses"], {"nope": "Read@Fragment"}),
    "bad_usage": mutate(["passes", 2, "uses"], {"hdr": "Read@Nowhere"}),
    "bad_usage_syntax": mutate(["passes", 2, "uses"], {"hdr": "Read"}),
    "bad_as": mutate(["passes", 5, "uses", 1, "as"], "index"),
    "bad_condition": mutate(["passes", 2, "if"], "geo && (sky"),
    "unknown_feature": mutate(["passes", 2, "if"], "nothing"),
    "bad_format": mutate(["resources", "hdr", "format"], "R99_UNORM"),
    "bad_extent": mutate(["resources", "hdr", "extent"], "output/0"),
    "huge_extent": mutate(["resources", "cube", "extent"], [4294967295, 4294967295]),
    "zero_extent": mutate(["resources", "cube", "extent"], [0, 16]),
    "too_many_mips": mutate(["resources", "cube", "mips"], 40),
    "zero_layers": mutate(["resources", "arr", "layers"], 0),
    "huge_layers": mutate(["resources", "arr", "layers"], 4294967295),
    "range_outside": mutate(["passes", 1, "uses", 1, "mips"], [2, 4294967295]),
    "range_negative": mutate(["passes", 1, "uses", 1, "layers"], [-1, 2]),
    "range_shape": mutate(["passes", 1, "uses", 1, "mips"], [1]),
    "bad_final": mutate(["resources", "buf", "final"], "Somewhere"),
    "buffer_format": mutate(["resources", "buf", "format"], "R8_UNORM"),
    "buffer_no_size": mutate(["resources", "buf", "size"], DELETE),
    "depth_clear_color": mutate(["resources", "depth", "clear"], {"color": [1, 2, 3, 4]}),
    "read_before_write": mutate(["resources", "chain", "clear"], DELETE),
    "duplicate_pass": mutate(["passes", 1, "name"], "faces"),
    "params_not_object": mutate(["passes", 0, "params"], [1, 2]),
    "never_cull_string": mutate(["passes", 0, "never_cull"], "yes"),
    "features_not_bool": mutate(["features", "geo"], 1),
    "uses_array_of_strings": mutate(["passes", 4, "uses"], ["buf"]),
}

out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
os.makedirs(out, exist_ok=True)
for name, graph in SEEDS.items():
    with open(os.path.join(out, f"seed_{name}.json"), "w") as f:
        json.dump(graph, f, indent=1)
        f.write("\n")
# Not JSON at all, and JSON cut short: the reader's own errors.
with open(os.path.join(out, "seed_truncated.json"), "w") as f:
    f.write(json.dumps(BASE)[:300])
with open(os.path.join(out, "seed_not_json.json"), "w") as f:
    f.write("version: 1\npasses: [\n")
print(f"{len(SEEDS) + 2} seeds in {out}", file=sys.stderr)
