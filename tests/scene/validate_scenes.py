#!/usr/bin/env python3
"""Checks schemas/scene.schema.json: it is a valid 2020-12 schema, every scenes/*.json meets it,
and it refuses the same kinds of mistakes as the C++ loader (a sample of them)."""
import json
import pathlib
import sys

import jsonschema

root = pathlib.Path(sys.argv[1])
schema = json.loads((root / "schemas" / "scene.schema.json").read_text())
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)

failures = []
scenes = sorted((root / "scenes").glob("*.json"))
for path in scenes:
    for err in validator.iter_errors(json.loads(path.read_text())):
        failures.append(f"{path.name}: {err.json_path}: {err.message}")

sphere = {"type": "sphere", "center": [0, 0, 0], "radius": 1}
bad = {
    "unknown key": {"camra": {}},
    "fov 180": {"camera": {"fov_y_deg": 180}},
    "fov below 0.001": {"camera": {"fov_y_deg": 0.0009}},
    "near 0": {"camera": {"near": 0}},
    "roughness 1.5": {"objects": [dict(sphere, material={"roughness": 1.5})]},
    "radius 0": {"objects": [dict(sphere, radius=0)]},
    "unknown type": {"objects": [{"type": "cube"}]},
    "bad sampling": {"environment": {"file": "procedural", "sampling": "octahedral"}},
    "png environment": {"environment": {"file": "sky.png"}},
    "unknown tonemapper": {"tonemapper": "reinhard"},
    "sequence without a number": {"environment": {"sequence": "frames/sky.exr"}},
    "sequence and file": {"environment": {"sequence": "f/%04d.exr", "file": "sky.hdr"}},
    "fps of a file": {"environment": {"file": "sky.hdr", "fps": 24}},
    "fps 0": {"environment": {"sequence": "f/%04d.exr", "fps": 0}},
}
good = {"sequence": {"environment": {"sequence": "frames/%04d.exr", "fps": 24}}}
for name, doc in good.items():
    for err in validator.iter_errors(doc):
        failures.append(f"schema refuses {name}: {err.message}")
for name, doc in bad.items():
    if validator.is_valid(doc):
        failures.append(f"schema accepts {name}: {json.dumps(doc)}")

print("\n".join(failures) or f"{len(scenes)} scenes valid; {len(bad)} bad documents refused")
sys.exit(1 if failures or len(scenes) < 4 else 0)
