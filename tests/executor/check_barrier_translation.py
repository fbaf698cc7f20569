#!/usr/bin/env python3
"""Every barrier the product records comes from a plan, through one translation place.

Usage: check_barrier_translation.py ROOT        check the source tree at ROOT
       check_barrier_translation.py --self-test show that a planted barrier is found

Searches framework/, passes/, tools/, examples/ and include/ for what builds or records a
barrier: Vulkan barrier structs (synchronization2 and legacy), dependency infos, pipeline
barrier and event commands, and subpass dependencies (a render pass's implicit barriers).
Only framework/executor/barrier_batch.cpp (plan barriers -> Vulkan structs) and
framework/executor/vulkan_commands.cpp (the vkCmdPipelineBarrier2 call) may. bench/ is not
searched: its hand-written Vulkan is the baseline the executor is measured against.
Prints each finding as FILE:LINE: TEXT and exits 1 if there is any.
"""
import re
import sys
import tempfile
from pathlib import Path

PATTERN = re.compile(
    r"VK_STRUCTURE_TYPE_(IMAGE_|BUFFER_)?MEMORY_BARRIER(_2)?\b|VK_STRUCTURE_TYPE_DEPENDENCY_INFO\b"
    r"|vkCmdPipelineBarrier|vkCmdWaitEvents|vkCmdSetEvent|VkSubpassDependency")
ALLOWED = {"framework/executor/barrier_batch.cpp", "framework/executor/vulkan_commands.cpp"}
DIRS = ["framework", "passes", "tools", "examples", "include"]
SUFFIXES = {".cpp", ".hpp", ".h", ".cc", ".inl"}


def findings(root: Path, scanned=None):
    out = []
    for d in DIRS:
        for path in sorted((root / d).rglob("*")):
            if path.suffix not in SUFFIXES or not path.is_file():
                continue
            if scanned is not None:
                scanned.append(path)
            rel = path.relative_to(root).as_posix()
            if rel in ALLOWED:
                continue
            for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                code = line.split("//")[0]  # comments may name what they explain
                if PATTERN.search(code):
                    out.append(f"{rel}:{n}: {line.strip()}")
    return out


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "framework/executor").mkdir(parents=True)
        (root / "framework/executor/barrier_batch.cpp").write_text("VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};\n")
        if findings(root):
            print("self-test: the translation place itself was reported")
            return 1
        (root / "framework/executor/renderer_upload.cpp").write_text(
            "void f(VkCommandBuffer c) {\n  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};\n}\n")
        (root / "passes").mkdir()
        (root / "passes/my_pass.cpp").write_text("vkCmdPipelineBarrier(cmd, 0, 0, 0, 0, nullptr, 0, nullptr, 0, nullptr);\n")
        found = findings(root)
        if len(found) != 2:
            print("self-test: expected the 2 planted barriers, found:", found)
            return 1
    print("self-test: planted barriers are found")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(sys.argv[1])
    # A wrong root would scan nothing and find nothing: the translation place must be there.
    missing = [a for a in sorted(ALLOWED) if not (root / a).is_file()]
    if missing:
        print("not a skygraph tree, or the translation place moved:", ", ".join(missing), "missing under", root)
        return 1
    scanned = []
    found = findings(root, scanned)
    if len(scanned) < 100:
        print(f"only {len(scanned)} source file(s) under {root}: not the whole tree")
        return 1
    for f in found:
        print(f)
    print(f"{len(found)} barrier(s) written outside the translation place ({len(scanned)} files scanned)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
