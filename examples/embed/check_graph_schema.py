#!/usr/bin/env python3
"""The example's graph against the schema its "$schema" names (vignette.schema.json, which is
skygraph's graph schema plus VignettePass), with Debian's python3-jsonschema. Mutations that
the schema must reject prove that the check can fail."""
import copy
import json
import pathlib
import sys
import warnings

import jsonschema

warnings.simplefilter("ignore", DeprecationWarning)  # RefResolver: fine on Debian 12's 4.10
here = pathlib.Path(__file__).resolve().parent
graph = json.loads((here / "vignette.json").read_text())
schema_path = here / graph["$schema"]
schema = json.loads(schema_path.read_text())
jsonschema.Draft7Validator.check_schema(schema)
resolver = jsonschema.RefResolver(base_uri=schema_path.as_uri(), referrer=schema)
validator = jsonschema.Draft7Validator(schema, resolver=resolver)

failures = [f"vignette.json: {list(e.path)}: {e.message}" for e in validator.iter_errors(graph)]
mutations = {
    "strength out of range": lambda g: g["passes"][0]["params"].update(strength=2),
    "unknown VignettePass param": lambda g: g["passes"][0]["params"].update(radius=1),
    "bad built-in param": lambda g: g["passes"][1]["params"].update(operator="nope"),
    "unknown pass type": lambda g: g["passes"][0].update(type="NoSuchPass"),
    "bad format": lambda g: g["resources"]["hdr_color"].update(format="NOPE"),
}
for name, mutate in mutations.items():
    bad = copy.deepcopy(graph)
    mutate(bad)
    if validator.is_valid(bad):
        failures.append(f"mutation '{name}' was accepted")
for f in failures:
    print("FAIL:", f)
print(f"{1 + len(mutations) - len(failures)} passed, {len(failures)} failed")
sys.exit(1 if failures else 0)
