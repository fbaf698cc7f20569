#!/usr/bin/env python3
"""Sorts the failures of a random-graph run (tools/random-graphs.sh logs) by cause.

    tests/reliability/classify_failures.py build-fuzz/random-graphs/shard*.log

A failure is counted as the layer-1.3.239 false positive of docs/reliability.md (finding 2)
only if every message it carries is a WRITE_AFTER_WRITE of an image layout transition in a
vkCmdPipelineBarrier2 whose prior write had already been made available by an earlier
barrier (write_barriers not empty), and every barrier of the plan the message can name
(same image, same index within its batch, with a layout change, overlapping the range of
a barrier in an earlier batch that made such a write available) has a source stage among
the stages that write was made available to. That is the case the layer's fix
(KhronosGroup/Vulkan-ValidationLayers PR #6684) stops reporting: the write is in the
barrier's dependency chain, so it is available, and available memory is visible to a
layout transition. Everything else is listed as "other" with its seed, to be read by hand.
"""
import re
import sys

HAZARD = re.compile(
    r"vkCmdPipelineBarrier2: Hazard WRITE_AFTER_WRITE for image barrier (\d+) VkImage \S+\[([^\]#]+)(?:#\d+)?\]\. "
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
            m = re.search(r"mips\[(\d+)\+(\d+)\] layers\[(\d+)\+(\d+)\]", line)
            mips, layers = ((int(m[1]), int(m[1]) + int(m[2])), (int(m[3]), int(m[3]) + int(m[4]))) if m else (None, None)
            src, dst = (side.split("/")[0].split("|") for side in lines[i + 1].split("->"))
            layout = lines[i + 2].strip()
            current.append({"name": name, "src": {s.strip() for s in src}, "dst": {s.strip() for s in dst},
                            "mips": mips, "layers": layers, "transition": not layout.startswith("stays")})
        elif line in ("culled:", "lifetimes:"):
            current = None
    return out


def overlap(a, b):
    def meet(x, y):
        return x[0] < y[1] and y[0] < x[1]
    return meet(a["mips"], b["mips"]) and meet(a["layers"], b["layers"])


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
        writer = sync_stage(prior)
        # The barrier that made the write available comes in an earlier batch than the flagged
        # one (a batch is validated before it is applied), so only later batches can be meant.
        # It must also cover part of the range that barrier made available.
        made_available = [(k, x) for k, b in enumerate(plan_batches) for x in b
                          if x["name"] == image and writer in x["src"] and x["dst"] & available_to]
        candidates = [b[int(index)] for k, b in enumerate(plan_batches)
                      if len(b) > int(index) and b[int(index)]["name"] == image and b[int(index)]["transition"]
                      and any(j < k and overlap(x, b[int(index)]) for j, x in made_available)]
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
