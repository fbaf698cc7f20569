#!/usr/bin/env python3
"""Checks schemas/graph.schema.json and schemas/plan.schema.json.

Usage: validate_schemas.py SOURCE_DIR SKYGRAPH_EXECUTABLE

- Both schemas are valid draft-07 schemas.
- Their enumerations match the C++ sources they mirror (formats, pass types with their slots
  and params, usage stages, Vulkan names in plans), so the schemas cannot drift silently.
- Every graphs/*.json validates, and its "$schema" resolves to schemas/graph.schema.json.
- The JSON plan of every shipped graph, under every combination of its features (and with
  --no-cull), validates against plan.schema.json, and so do those of graphs/deferred.json
  (whose transients share memory) with --no-alias, --placement first-use and another size.
- Mutated graphs: the schema and the loader (`skygraph compile`) must agree on each, so
  the schema is shown to reject what the loader rejects (unknown keys, a bad usage string,
  a bad format, ...) and to accept the extensions the loader accepts.
- Mutated plans are rejected.

Prints one line per check and "N passed, M failed" last; exits 1 if anything failed.
Uses Debian's python3-jsonschema (4.10); newer releases work too.
"""
import copy
import itertools
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

try:
    import jsonschema
except ImportError:
    print("python3-jsonschema is not installed; run tools/install-deps.sh")
    print("0 passed, 1 failed")
    sys.exit(1)

passed = 0
failed = 0


def check(ok, what, detail=""):
    global passed, failed
    if ok:
        passed += 1
        print(f"ok   - {what}")
    else:
        failed += 1
        print(f"FAIL - {what}")
        for line in str(detail).splitlines():
            print(f"       {line}")


def validator(schema):
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    return cls(schema)


def errors(v, instance):
    return sorted(v.iter_errors(instance), key=lambda e: list(e.absolute_path))


def describe(errs, limit=5):
    return "\n".join(f"{'/'.join(map(str, e.absolute_path)) or '(root)'}: {e.message[:300]}"
                     for e in errs[:limit])


def run_cli(cli, args):
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, timeout=60)


# ---------------------------------------------------------------------------------------
def check_schemas_valid(root):
    schemas = {}
    for name in ("graph", "plan"):
        path = root / "schemas" / f"{name}.schema.json"
        try:
            schema = json.loads(path.read_text())
            schemas[name] = validator(schema)
            check(schema.get("$schema") == "http://json-schema.org/draft-07/schema#",
                  f"{path.name} is a valid draft-07 schema")
        except Exception as e:  # noqa: BLE001 - report anything as a failure
            check(False, f"{path.name} is a valid schema", e)
    return schemas


def check_drift(root, graph_schema, plan_schema):
    """Enumerations in the schemas against the C++ sources they mirror."""
    defs = graph_schema["definitions"]
    fmt_src = (root / "framework/compiler/format_table.hpp").read_text()
    formats = re.findall(r"^\s*SG_FORMAT\((\w+),", fmt_src, re.M)
    schema_formats = defs["resource"]["properties"]["format"]["enum"]
    check(formats and schema_formats == formats, "format enum lists every format of format_table.hpp, in order",
          f"format_table.hpp: {formats}\nschema: {schema_formats}")
    depth = [f for f, d, s in re.findall(r"^\s*SG_FORMAT\((\w+), \d+, (\w+), (\w+),", fmt_src, re.M)
             if "true" in (d, s)]
    depth_rule = [r for r in defs["resource"]["allOf"]
                  if r["if"].get("properties", {}).get("format", {}).get("enum") == depth]
    check(len(depth_rule) == 1, "depth/stencil formats in the clear rule match format_table.hpp", depth)

    usage_src = (root / "framework/compiler/usage.cpp").read_text()
    stages = re.findall(r'\{"(\w+)", Stage::\w+\}', usage_src)
    check(defs["usageObject"]["properties"]["stage"]["enum"] == stages, "stage enum matches usage.cpp", stages)
    accesses = re.findall(r'\{"(\w+)", Access::\w+\}', usage_src)
    check(defs["usageObject"]["properties"]["access"]["enum"] == accesses, "access enum matches usage.cpp", accesses)

    # Pass types: names, slots (stage, accesses, as) and params, from each pass's declaration
    # (passes/<pass>/*_type.cpp, *_types.cpp), one `return {"Name", ...}` per type.
    sources = sorted((root / "passes").glob("*/*_type*.cpp"))
    check(len(sources) > 0, "pass type declarations found in passes/*/", sources)
    src = "\n".join(p.read_text() for p in sources)
    types = {}
    for block in src.split('return {"')[1:]:
        name = block.split('"', 1)[0]
        slots = {s: (st, re.findall(r"Access::(\w+)", a), None if b == "Default" else b.lower())
                 for s, st, a, b in re.findall(r'slot\("(\w+)", Stage::(\w+), (\{[^}]*\}), BindAs::(\w+)', block)}
        params = re.findall(r'\{"(\w+)", (?:oneOf|numberIn|integerIn)\(', block)
        types[name] = (slots, params, "rules(" in block)
    schema_types = defs["pass"]["properties"]["type"]["enum"]
    check(sorted(schema_types) == sorted(types), "pass type enum matches the declarations in passes/",
          f"sources: {sorted(types)}\nschema: {sorted(schema_types)}")
    rules = {r["if"]["properties"]["type"]["const"]: r["then"] for r in defs["pass"]["allOf"]}
    for name, (slots, params, has_rules) in sorted(types.items()):
        then = rules.get(name, {})
        props = then.get("properties", {})
        schema_params = sorted(props["params"]["properties"]) if "params" in props else None
        check(schema_params == (sorted(params) if has_rules else None),
              f"{name}: params match the source", f"source: {params}\nschema: {schema_params}")
        if not slots:
            check("uses" not in props, f"{name}: accepts any usage")
            continue
        schema_slots = {}
        for shape in props["uses"]["items"]["anyOf"]:
            p = shape["properties"]
            schema_slots[p["slot"]["const"]] = (p["stage"]["const"], p["access"]["enum"],
                                               p.get("as", {}).get("const"))
        check(schema_slots == slots, f"{name}: slots match the source",
              f"source: {slots}\nschema: {schema_slots}")

    graph_src = (root / "framework/compiler/graph.cpp").read_text()
    policies = re.findall(r'if \(s == "([\w-]+)"\) return LayoutPolicy::', graph_src)
    check(policies and graph_schema["properties"]["layouts"]["enum"] == policies,
          "layouts enum matches parseLayoutPolicy in graph.cpp",
          f"graph.cpp: {policies}\nschema: {graph_schema['properties']['layouts']['enum']}")
    check(plan_schema["properties"]["layouts"]["enum"] == [p for p in policies if p != "fewest-barriers"],
          "plan layouts enum lists every policy but the default, which plans leave out",
          plan_schema["properties"]["layouts"]["enum"])

    plan_src = (root / "framework/compiler/plan_format.cpp").read_text()
    pdefs = plan_schema["definitions"]
    for key, regex, prefix in (("stageBit", r"SG_BIT\(VK_PIPELINE_STAGE_2_, (\w+)\)", "VK_PIPELINE_STAGE_2_"),
                               ("accessBit", r"SG_BIT\(VK_ACCESS_2_, (\w+)\)", "VK_ACCESS_2_"),
                               ("layout", r"SG_LAYOUT\((\w+)\)\n", "VK_IMAGE_LAYOUT_")):
        names = [prefix + n for n in re.findall(regex, plan_src)]
        check(names and pdefs[key]["enum"] == names, f"plan schema {key} names match plan_format.cpp",
              f"source: {names}\nschema: {pdefs[key]['enum']}")
    model_src = (root / "framework/compiler/memory_model.cpp").read_text()
    strategies = re.findall(r'case MemoryStrategy::\w+: return "(\w+)";', model_src)
    schema_strategies = plan_schema["properties"]["memory"]["properties"]["strategy"]["enum"]
    check(strategies and schema_strategies == strategies, "plan schema memory strategies match memory_model.cpp",
          f"source: {strategies}\nschema: {schema_strategies}")


def check_shipped_graphs(root, cli, gv, pv):
    graphs = sorted((root / "graphs").glob("*.json"))
    check(len(graphs) > 0, "graphs/*.json exist")
    target = (root / "schemas" / "graph.schema.json").resolve()
    for g in graphs:
        rel = g.relative_to(root)
        doc = json.loads(g.read_text())
        errs = errors(gv, doc)
        check(not errs, f"{rel} validates against graph.schema.json", describe(errs))
        ref = doc.get("$schema")
        check(isinstance(ref, str) and (g.parent / ref).resolve() == target,
              f"{rel} \"$schema\" ({ref}) resolves to schemas/graph.schema.json")

        names = sorted(doc.get("features", {}))
        combos = [dict(zip(names, values)) for values in itertools.product([True, False], repeat=len(names))]
        runs = [([], "defaults, --no-cull", ["--no-cull"])]
        for combo in combos:
            flags = [a for n, on in combo.items() for a in ("--feature", f"{n}={'on' if on else 'off'}")]
            label = ", ".join(f"{n}={'on' if on else 'off'}" for n, on in combo.items()) or "defaults"
            runs.append((flags, label, []))
        for flags, label, extra in runs:
            r = run_cli(cli, ["compile", g, "--format", "json", *flags, *extra])
            if r.returncode != 0:
                check(False, f"{rel} [{label}] compiles", r.stderr)
                continue
            plan = json.loads(r.stdout)
            errs = errors(pv, plan)
            check(not errs, f"{rel} [{label}] plan validates against plan.schema.json", describe(errs))


def check_memory_plans(root, cli, pv):
    """The memory options on a graph whose transients share memory (its feature combinations are
    among the shipped graphs'): the schema holds, and the names in "memory" and in aliasing
    barriers are the plan's resources."""
    graph = root / "graphs/deferred.json"
    rel = graph.relative_to(root)
    runs = [([], "defaults"), (["--no-alias"], "--no-alias"), (["--placement", "first-use"], "--placement first-use"),
            (["--width", "640", "--height", "360"], "640x360")]
    for flags, label in runs:
        r = run_cli(cli, ["compile", graph, "--format", "json", *flags])
        if r.returncode != 0:
            check(False, f"{rel} [{label}] compiles", r.stderr)
            continue
        plan = json.loads(r.stdout)
        errs = errors(pv, plan)
        check(not errs, f"{rel} [{label}] plan validates against plan.schema.json", describe(errs))
        resources = {res["name"] for res in plan["resources"]}
        memory = plan.get("memory", {})
        named = [p["resource"] for p in memory.get("placements", [])]
        named += [a for p in memory.get("placements", []) for a in p["aliases"]]
        named += [a for p in memory.get("placements", []) for a in p.get("previousFrameAliases", [])]
        barriers = [b for p in plan["passes"] for b in p["barriers"] if "aliases" in b]
        named += [a for b in barriers for a in b["aliases"] + b.get("previousFrameAliases", [])]
        check(memory and set(named) <= resources, f"{rel} [{label}] memory names the plan's resources",
              sorted(set(named) - resources))
        # Within the frame: with --no-alias each transient keeps its bytes to itself (it still
        # takes them over from its previous frame, the frames sharing the heaps).
        in_frame = [b for b in barriers if b["aliases"]]
        sharing = label != "--no-alias"
        check(bool(in_frame) == sharing, f"{rel} [{label}] {'has' if sharing else 'has no'} aliasing barriers",
              f"{len(in_frame)} aliasing barrier(s) within the frame")


# ---------------------------------------------------------------------------------------
# Mutations of shipped graphs. Each is (description, function(doc) -> doc, expected_valid);
# both the schema and the loader must give the expected verdict.
def raster_cases():
    # The tonemap pass, by name: passes before it may come and go.
    raster = json.loads((Path(__file__).resolve().parents[2] / "graphs" / "raster.json").read_text())
    tonemap = [p["name"] for p in raster["passes"]].index("tonemap")

    def add(d, *keys, value):
        obj = d
        for k in keys[:-1]:
            obj = obj[k]
        obj[keys[-1]] = value
        return d

    def delete(d, *keys):
        obj = d
        for k in keys[:-1]:
            obj = obj[k]
        del obj[keys[-1]]
        return d

    res = lambda d: d["resources"]  # noqa: E731
    pas = lambda d: d["passes"]  # noqa: E731
    tonemap_array = [
        {"resource": "hdr_color", "access": "Read", "stage": "Fragment", "as": "sampled", "slot": "hdr"},
        {"resource": "swapchain", "access": "Write", "stage": "ColorAttachment", "slot": "output"},
    ]
    return [
        # --- rejected --------------------------------------------------------------
        ("unknown root key", lambda d: add(d, "verison", value=1), False),
        ("unknown resource key", lambda d: add(d, "resources", "depth", "fromat", value="D32_SFLOAT"), False),
        ("unknown pass key", lambda d: add(d, "passes", 0, "enabled", value=True), False),
        ("unknown key in a usage object", lambda d: add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], stride=4), tonemap_array[1]]), False),
        ("unknown key in clear", lambda d: add(d, "resources", "depth", "clear", "value", value=0), False),
        ("usage string \"Read@Nowhere\"", lambda d: add(d, "passes", tonemap, "uses", "hdr_color", value="Read@Nowhere"), False),
        ("usage string without '@'", lambda d: add(d, "passes", tonemap, "uses", "hdr_color", value="Read"), False),
        ("usage string \"Write@VertexInput\"", lambda d: add(d, "passes", tonemap, "uses", "hdr_color", value="Write@VertexInput"), False),
        ("unknown access in a usage object", lambda d: add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], access="Sample"), tonemap_array[1]]), False),
        ("unknown format", lambda d: add(d, "resources", "hdr_color", "format", value="R16G16B16A16_FLOAT"), False),
        ("VK_FORMAT_ prefix in a format", lambda d: add(d, "resources", "hdr_color", "format", value="VK_FORMAT_R16G16B16A16_SFLOAT"), False),
        ("version 2", lambda d: add(d, "version", value=2), False),
        ("layouts \"fast\"", lambda d: add(d, "layouts", value="fast"), False),
        ("layouts true", lambda d: add(d, "layouts", value=True), False),
        ("missing version", lambda d: delete(d, "version"), False),
        ("missing name", lambda d: delete(d, "name"), False),
        ("a control character in the graph's name", lambda d: add(d, "name", value="raster\u0007"), False),
        ("a newline in a pass name", lambda d: add(d, "passes", tonemap, "name", value="tone\nmap"), False),
        ("a tab in a resource name", lambda d: add(d, "resources", "spare\tbuffer", value={"type": "buffer", "size": 64}), False),
        ("unknown resource type", lambda d: add(d, "resources", "depth", "type", value="image3d"), False),
        ("extent \"output/0\"", lambda d: add(d, "resources", "hdr_color", "extent", value="output/0"), False),
        ("extent \"output/4097\"", lambda d: add(d, "resources", "hdr_color", "extent", value="output/4097"), False),
        ("extent \"output/000002\" (six digits)", lambda d: add(d, "resources", "hdr_color", "extent",
                                                                value="output/000002"), False),
        ("`if` with a no-break space", lambda d: add(d, "passes", 2, "if", value="skybox\u00a0&& skybox"), False),
        ("extent \"half\"", lambda d: add(d, "resources", "hdr_color", "extent", value="half"), False),
        ("extent [0, 16]", lambda d: add(d, "resources", "hdr_color", "extent", value=[0, 16]), False),
        ("extent [16385, 16]", lambda d: add(d, "resources", "hdr_color", "extent", value=[16385, 16]), False),
        ("mips 16", lambda d: add(d, "resources", "hdr_color", "mips", value=16), False),
        ("mips \"all\"", lambda d: add(d, "resources", "hdr_color", "mips", value="all"), False),
        ("image2d with 2 layers", lambda d: add(d, "resources", "hdr_color", "layers", value=2), False),
        ("image with a size", lambda d: add(d, "resources", "hdr_color", "size", value=64), False),
        ("color clear on a depth format", lambda d: add(d, "resources", "depth", "clear", value={"color": [0, 0, 0, 1]}), False),
        ("depth clear on a color format", lambda d: add(d, "resources", "hdr_color", "clear", value={"depth": 1.0}), False),
        ("depth clear 1.5", lambda d: add(d, "resources", "depth", "clear", value={"depth": 1.5}), False),
        ("empty clear", lambda d: add(d, "resources", "depth", "clear", value={}), False),
        ("clear color with 3 numbers", lambda d: add(d, "resources", "hdr_color", "clear", value={"color": [0, 0, 0]}), False),
        ("clear on an external resource", lambda d: add(d, "resources", "swapchain", "clear", value={"color": [0, 0, 0, 1]}), False),
        ("initial on a non-external resource", lambda d: add(d, "resources", "hdr_color", "initial", value="ShaderRead"), False),
        ("unknown final state", lambda d: add(d, "resources", "swapchain", "final", value="PresentSrc"), False),
        ("external: \"yes\"", lambda d: add(d, "resources", "swapchain", "external", value="yes"), False),
        ("alias: \"no\"", lambda d: add(d, "resources", "hdr_color", "alias", value="no"), False),
        ("alias on an external resource", lambda d: add(d, "resources", "swapchain", "alias", value=False), False),
        ("non-boolean feature default", lambda d: add(d, "features", "skybox", value="on"), False),
        ("feature named \"true\"", lambda d: add(d, "features", "true", value=True), False),
        ("feature name with a space", lambda d: add(d, "features", "sky box", value=True), False),
        ("empty `if`", lambda d: add(d, "passes", 0, "if", value=""), False),
        ("unknown pass type", lambda d: add(d, "passes", 0, "type", value="ForwardPlusPass"), False),
        ("empty pass name", lambda d: add(d, "passes", 0, "name", value=""), False),
        ("pass without uses", lambda d: delete(d, "passes", tonemap, "uses"), False),
        ("never_cull: 1", lambda d: add(d, "passes", 0, "never_cull", value=1), False),
        ("unknown TonemappingPass param", lambda d: add(d, "passes", tonemap, "params", "gamma", value=2.2), False),
        ("unknown tone operator", lambda d: add(d, "passes", tonemap, "params", "operator", value="reinhard"), False),
        ("exposure_ev 100", lambda d: add(d, "passes", tonemap, "params", "exposure_ev", value=100), False),
        ("usage that fits no slot of the pass type", lambda d: add(d, "passes", tonemap, "uses", "hdr_color", value="Read@Compute"), False),
        ("required slot left empty", lambda d: delete(d, "passes", tonemap, "uses", "swapchain"), False),
        ("explicit slot that does not fit", lambda d: add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], slot="output"), tonemap_array[1]]), False),
        ("`as: index` on a shader stage", lambda d: add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], **{"as": "index"}), tonemap_array[1]]), False),
        ("`as` on an attachment", lambda d: add(d, "passes", tonemap, "uses", value=[
            tonemap_array[0], dict(tonemap_array[1], **{"as": "storage"})]), False),
        ("sampled write", lambda d: add(d, "passes", tonemap, "type", value="Generic") and add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], access="Write"), tonemap_array[1]]), False),
        ("attachment usage over two mips", lambda d: add(d, "resources", "swapchain", "mips", value=2) and add(
            d, "passes", tonemap, "uses", value=[tonemap_array[0], dict(tonemap_array[1], mips=[0, 2])]), False),
        ("usage range with count 0", lambda d: add(d, "passes", tonemap, "uses", value=[
            dict(tonemap_array[0], layers=[0, 0]), tonemap_array[1]]), False),
        # --- accepted --------------------------------------------------------------
        ("array-form uses with `as` and `slot`", lambda d: add(d, "passes", tonemap, "uses", value=tonemap_array), True),
        ("descriptions on resources and passes", lambda d: add(d, "resources", "depth", "description", value="z") and add(
            d, "passes", 0, "description", value="draws"), True),
        ("`if` split over lines by tab, line feed and carriage return",
            lambda d: add(d, "passes", 2, "if", value="skybox\t&&\n\r skybox"), True),
        ("`if` expression with !, && and parentheses", lambda d: add(d, "passes", 2, "if", value="(skybox && !false) || skybox"), True),
        ("never_cull", lambda d: add(d, "passes", 0, "never_cull", value=True), True),
        ("layouts \"optimal\"", lambda d: add(d, "layouts", value="optimal"), True),
        ("layouts \"fewest-barriers\"", lambda d: add(d, "layouts", value="fewest-barriers"), True),
        ("alias: false and alias: true on transients", lambda d: add(d, "resources", "hdr_color", "alias", value=False)
            and add(d, "resources", "depth", "alias", value=True), True),
        ("extent \"output/2\" and mips \"full\"", lambda d: add(d, "resources", "bloom", value={
            "type": "image2d", "format": "R16G16B16A16_SFLOAT", "extent": "output/2", "mips": "full"}), True),
        ("extent \"output/0004\"", lambda d: add(d, "resources", "hdr_color", "extent", value="output/0004") and add(
            d, "resources", "depth", "extent", value="output/4"), True),
        ("depth and stencil clear on D24_UNORM_S8_UINT", lambda d: add(d, "resources", "depth", "format", value="D24_UNORM_S8_UINT")
            and add(d, "resources", "depth", "clear", value={"depth": 1.0, "stencil": 255}), True),
        ("external swapchain with initial Present", lambda d: add(d, "resources", "swapchain", "initial", value="Present"), True),
        ("an unused extra resource", lambda d: add(d, "resources", "spare", value={
            "type": "image2d_array", "format": "R8_UNORM", "extent": [64, 64], "layers": 4, "mips": 7}), True),
    ]


def generic_cases():
    """Buffers and skygraph extensions, on a small Generic graph."""
    base = {
        "$schema": "../schemas/graph.schema.json",
        "version": 1, "name": "buffers",
        "resources": {
            "indices": {"type": "buffer", "size": 4096, "external": True, "initial": "ShaderRead"},
            "args": {"type": "buffer", "size": 64},
            "color": {"type": "image2d", "format": "R8G8B8A8_UNORM", "extent": [64, 64],
                      "external": True, "final": "TransferSrc"},
        },
        "passes": [
            {"name": "args", "type": "Generic", "uses": {"args": "Write@Compute"}},
            {"name": "draw", "type": "Generic", "uses": [
                {"resource": "indices", "access": "Read", "stage": "VertexInput", "as": "index"},
                {"resource": "args", "access": "Read", "stage": "Indirect"},
                {"resource": "color", "access": "Write", "stage": "ColorAttachment"}]},
        ],
    }

    def with_(fn):
        def mutate(_):
            d = copy.deepcopy(base)
            fn(d)
            return d
        return mutate

    def set_(d, value, *keys):
        for k in keys[:-1]:
            d = d[k]
        d[keys[-1]] = value

    return [
        ("Generic graph with an index buffer (`as: index`) and an indirect buffer", with_(lambda d: None), True),
        ("uniform buffer read", with_(lambda d: d["passes"].append(
            {"name": "u", "type": "Generic", "never_cull": True,
             "uses": [{"resource": "indices", "access": "Read", "stage": "Fragment", "as": "uniform"}]})), True),
        ("buffer with a format", with_(lambda d: set_(d, "R8_UNORM", "resources", "args", "format")), False),
        ("buffer without a size", with_(lambda d: d["resources"]["args"].pop("size")), False),
        ("buffer of 0 bytes", with_(lambda d: set_(d, 0, "resources", "args", "size")), False),
        ("buffer over 2 GiB", with_(lambda d: set_(d, 2147483649, "resources", "args", "size")), False),
        ("buffer with final TransferSrc", with_(lambda d: set_(d, "TransferSrc", "resources", "args", "final")), False),
        ("buffer with clear", with_(lambda d: set_(d, {"color": [0, 0, 0, 0]}, "resources", "args", "clear")), False),
        ("`as: index` on Fragment", with_(lambda d: set_(d, "Fragment", "passes", 1, "uses", 0, "stage")), False),
        ("Write@Indirect", with_(lambda d: set_(d, "Write", "passes", 1, "uses", 1, "access")), False),
        ("uniform write", with_(lambda d: d["passes"].append(
            {"name": "u", "type": "Generic", "never_cull": True,
             "uses": [{"resource": "args", "access": "ReadWrite", "stage": "Compute", "as": "uniform"}]})), False),
        ("params on Generic are free-form", with_(lambda d: set_(d, {"anything": [1, 2]}, "passes", 0, "params")), True),
    ]


def check_mutations(root, cli, gv, tmp):
    raster = json.loads((root / "graphs/raster.json").read_text())
    cases = [(f"raster: {n}", fn, ok, raster) for n, fn, ok in raster_cases()]
    cases += [(f"generic: {n}", fn, ok, None) for n, fn, ok in generic_cases()]
    for i, (name, fn, expect_valid, base) in enumerate(cases):
        doc = fn(copy.deepcopy(base))
        errs = errors(gv, doc)
        schema_ok = not errs
        # Written to a graphs/ folder, so the "$schema" reference looks as it does in the repo.
        path = tmp / "graphs" / f"case{i}.json"
        path.write_text(json.dumps(doc, indent=1))
        r = run_cli(cli, ["compile", path])
        loader_ok = r.returncode == 0
        verdict = "accepted" if expect_valid else "rejected"
        detail = (f"schema: {'accepts' if schema_ok else 'rejects'}\n{describe(errs, 3)}\n"
                  f"loader: exit {r.returncode}\n{r.stderr.strip()[:600]}")
        check(schema_ok == expect_valid and loader_ok == expect_valid and r.returncode in (0, 1),
              f"{name}: {verdict} by schema and loader", detail)


def check_layouts_plans(root, cli, pv, tmp):
    """A graph asking for optimal layouts: its plan says so and validates; the default's does
    not name the policy."""
    doc = json.loads((root / "graphs/deferred.json").read_text())
    doc["layouts"] = "optimal"
    path = tmp / "graphs" / "deferred_optimal.json"
    path.write_text(json.dumps(doc, indent=1))
    for graph, expected in ((path, "optimal"), (root / "graphs/deferred.json", None)):
        r = run_cli(cli, ["compile", graph, "--format", "json"])
        if r.returncode != 0:
            check(False, f"{graph.name} compiles", r.stderr)
            continue
        plan = json.loads(r.stdout)
        errs = errors(pv, plan)
        check(not errs and plan.get("layouts") == expected,
              f"{graph.name}: plan layouts is {expected} and validates against plan.schema.json",
              f"layouts: {plan.get('layouts')}\n{describe(errs)}")


def check_plan_mutations(root, cli, pv):
    r = run_cli(cli, ["compile", root / "graphs/raster.json", "--format", "json"])
    if r.returncode != 0:
        check(False, "raster compiles for plan mutations", r.stderr)
        return
    plan = json.loads(r.stdout)

    def mutate(fn):
        p = copy.deepcopy(plan)
        fn(p)
        return p

    barrier = lambda p: p["passes"][1]["barriers"][0]  # noqa: E731
    cases = [
        ("unknown key in a barrier", lambda p: barrier(p).update(dependencyFlags=0)),
        ("short stage name in a mask", lambda p: barrier(p).update(srcStageMask=["COLOR_ATTACHMENT_OUTPUT"])),
        ("access name in a stage mask", lambda p: barrier(p).update(dstStageMask=["VK_ACCESS_2_SHADER_READ_BIT"])),
        ("unknown layout", lambda p: barrier(p).update(newLayout="VK_IMAGE_LAYOUT_SHADER_READ_OPTIMAL")),
        ("image barrier without a range", lambda p: barrier(p).pop("layerCount")),
        ("buffer barrier with layouts", lambda p: barrier(p).update(kind="buffer")),
        ("unknown barrier kind", lambda p: barrier(p).update(kind="execution")),
        ("pass without barriers", lambda p: p["passes"][0].pop("barriers")),
        ("culled entry without a reason", lambda p: p["culled"].append({"pass": "x"})),
        ("usage with a bad usage string", lambda p: p["passes"][0]["usages"][0].update(usage="Read@Nowhere")),
        ("usage with loadOp but no storeOp",
         lambda p: next(u for u in p["passes"][0]["usages"] if "storeOp" in u).pop("storeOp")),
        ("non-boolean feature value", lambda p: p["features"].update(skybox="on")),
        ("the default layouts policy spelled out", lambda p: p.update(layouts="fewest-barriers")),
        ("memory without placements", lambda p: p["memory"].pop("placements")),
        ("unknown memory strategy", lambda p: p["memory"].update(strategy="worstFit")),
        ("unknown key in memory", lambda p: p["memory"].update(wastedBytes=0)),
        ("placement with a negative offset", lambda p: p["memory"]["placements"][0].update(offset=-1)),
        ("placement without aliases", lambda p: p["memory"]["placements"][0].pop("aliases")),
        ("heap without memoryTypeBits", lambda p: p["memory"]["heaps"][0].pop("memoryTypeBits")),
        ("barrier aliases as a string", lambda p: barrier(p).update(aliases="depth")),
        ("barrier aliases naming a resource twice", lambda p: barrier(p).update(aliases=["depth", "depth"])),
    ]
    for name, fn in cases:
        errs = errors(pv, mutate(fn))
        check(bool(errs), f"plan: {name}: rejected by plan.schema.json")


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    root = Path(sys.argv[1]).resolve()
    cli = Path(sys.argv[2]).resolve()
    print(f"jsonschema {getattr(jsonschema, '__version__', '?')} on Python {sys.version.split()[0]}")
    schemas = check_schemas_valid(root)
    if len(schemas) == 2:
        gv, pv = schemas["graph"], schemas["plan"]
        check_drift(root, gv.schema, pv.schema)
        check_shipped_graphs(root, cli, gv, pv)
        with tempfile.TemporaryDirectory(prefix="skygraph_schema_") as t:
            tmp = Path(t)
            (tmp / "graphs").mkdir()
            check_mutations(root, cli, gv, tmp)
            check_layouts_plans(root, cli, pv, tmp)
        check_memory_plans(root, cli, pv)
        check_plan_mutations(root, cli, pv)
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    import warnings
    warnings.simplefilter("ignore", DeprecationWarning)  # jsonschema.__version__ on newer releases
    sys.exit(main())
