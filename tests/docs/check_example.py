#!/usr/bin/env python3
"""docs/graph-format.md's complete example: its graph, compiled by `skygraph compile`, prints
exactly the text the page shows after it. --self-test: a changed line in the shown text fails.

Usage: check_example.py SKYGRAPH ROOT [--self-test]"""
import pathlib
import subprocess
import sys
import tempfile


def example(markdown: str) -> tuple[str, str]:
    section = markdown[markdown.index("## A complete example"):]
    graph_start = section.index("```json\n") + len("```json\n")
    graph_end = section.index("```", graph_start)
    text_start = section.index("```\n", graph_end + 3) + len("```\n")
    text_end = section.index("```", text_start)
    return section[graph_start:graph_end], section[text_start:text_end]


def check(skygraph: str, graph: str, shown: str) -> str:
    """"same", "differs" (printed as a diff) or "failed" (the compile itself)."""
    with tempfile.TemporaryDirectory() as d:
        path = pathlib.Path(d) / "raster.json"
        path.write_text(graph)
        out = subprocess.run([skygraph, "compile", str(path)], capture_output=True, text=True)
    if out.returncode != 0:
        print(f"skygraph compile failed: {out.stderr}")
        return "failed"
    if out.stdout != shown:
        import difflib
        print("docs/graph-format.md's example output differs from `skygraph compile`:")
        print("".join(difflib.unified_diff(shown.splitlines(True), out.stdout.splitlines(True), "shown", "compiled")))
        return "differs"
    return "same"


def main() -> int:
    skygraph, root = sys.argv[1], pathlib.Path(sys.argv[2])
    graph, shown = example((root / "docs" / "graph-format.md").read_text())
    if "--self-test" in sys.argv:
        edited = shown.replace("UNDEFINED -> DEPTH_ATTACHMENT_OPTIMAL", "UNDEFINED -> GENERAL", 1)
        assert edited != shown, "the self-test's edit no longer applies"
        # Caught by the comparison, not by a compile that failed for another reason.
        if check(skygraph, graph, edited) != "differs":
            print("self-test: an edited example was not caught by the comparison")
            return 1
        print("self-test: the edited example is caught")
        return 0
    if check(skygraph, graph, shown) != "same":
        return 1
    print("the example's output is what skygraph compile prints")
    return 0


if __name__ == "__main__":
    sys.exit(main())
