#!/usr/bin/env python3
"""Sorts the failures of a random-graph run (tools/random-graphs.sh logs) by cause.

    tests/reliability/classify_failures.py build-fuzz/random-graphs/shard*.log

A failure is counted as the layer-1.3.239 false positive of docs/reliability.md (finding 2)
only if every message it carries is a WRITE_AFTER_WRITE of an image layout transition in a
vkCmdPipelineBarrier2 whose prior write had already been made available by an earlier
barrier (write_barriers not empty), and every barrier of the plan the message can name
(same image, same index within its batch, with a layout change) has a source stage among
the stages that write was made available to. That is the case the layer's fix
(KhronosGroup/Vulkan-ValidationLayers PR #6684) stops reporting: the write is in the
barrier's dependency chain, so it is available, and available memory is visible to a
layout transition. Everything else is listed as "other" with its seed, to be read by hand.
"""
import re
import sys

HAZARD = re.compile(
    r"vkCmdPipelineBarrier2: Hazard WRITE_AFTER_WRITE for image barrier (\d+) VkImage \S+\[([^\]#]+)#\d+\]\. "
    r"Access info \(usage: SYNC_IMAGE_LAYOUT_TRANSITION, prior_usage: (\w+), write_barriers: ([\w|]*),")
MESSAGE = re.compile(r"^  \[[^\]]*\] ", re.M)  # one line a message (random_graph_check.cpp)
# The layer names accesses SYNC_<STAGE>_<ACCESS>; the plan prints stages without the prefix.
SYNC_STAGES = ["COMPUTE_SHADER", "FRAGMENT_SHADER", "VERTEX_SHADER", "COLOR_ATTACHMENT_OUTPUT",
               "EARLY_FRAGMENT_TESTS", "LATE_FRAGMENT_TESTS", "DRAW_INDIRECT", "VERTEX_ATTRIBUTE_INPUT",
               "INDEX_INPUT", "COPY", "CLEAR", "BLIT", "RESOLVE", "TRANSFER"]
TRANSFER_LIKE = {"COPY", "CLEAR", "BLIT", "RESOLVE", "TRANSFER"}


def sync_stage(bit):
    name = bit[len("SYNC_"):]
    for s in SYNC_STAGES:
        if name.startswith(s + "_"):
            return "TRANSFER" if s in TRANSFER_LIKE else s
    return None


def batches(plan_text):
    """Image barriers of each batch of a text plan, in the order the executor records them."""
    out, current = [], None
    lines = plan_text.splitlines()
    for i, line in enumerate(lines):
        if re.match(r"^\[\d+\] ", line) or line.startswith("final:"):
            current = []
            out.append(current)
        elif current is not None and line.startswith("    image "):
            name = line.split()[1]
            src = lines[i + 1].split("->")[0].split("/")[0].split("|")
            layout = lines[i + 2].strip()
            current.append({"name": name, "src": {s.strip() for s in src},
                            "transition": not layout.startswith("stays")})
        elif line in ("culled:", "lifetimes:"):
            current = None
    return out


def classify(block):
    plan_at = block.find("\ngraph ")
    if plan_at < 0:
        return "other"  # a compile error or an exception, not a validation message
    messages, plan = block[:plan_at], block[plan_at:]
    count = len(MESSAGE.findall(messages))
    hazards = HAZARD.findall(messages)
    if count == 0 or len(hazards) != count:
        return "other"
    plan_batches = batches(plan)
    for index, image, prior, write_barriers in hazards:
        if prior == "SYNC_IMAGE_LAYOUT_TRANSITION" or not write_barriers:
            return "other"
        available_to = {sync_stage(b) for b in write_barriers.split("|")}
        candidates = [b[int(index)] for b in plan_batches
                      if len(b) > int(index) and b[int(index)]["name"] == image and b[int(index)]["transition"]]
        if not candidates or any(not (c["src"] & available_to) for c in candidates):
            return "other"
    return "layer-ilt-false-positive"


def main(paths):
    text = "".join(open(p, encoding="utf-8", errors="replace").read() for p in paths)
    blocks = re.split(r"^FAILED seed ", text, flags=re.M)[1:]
    counts, others = {}, []
    for b in blocks:
        head = b.split("\n", 1)[0]
        kind = classify(b)
        counts[kind] = counts.get(kind, 0) + 1
        if kind == "other":
            others.append(head)
    for kind, n in sorted(counts.items()):
        print(f"{kind}: {n}")
    for h in others:
        print(f"other: seed {h}")
    return 1 if others else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
