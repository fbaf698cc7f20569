#!/usr/bin/env python3
"""Keeps the repository's documentation self-contained and current.

  check_docs.py SOURCE_DIR
  check_docs.py --self-test    (the check against a small tree with one case of each finding)

Fails (exit 1, one line per finding: file:line: what) when
  - a relative link in a Markdown file (README.md, docs/*.md, any other *.md) does not
    resolve to a file, or its #fragment to a heading (or <a id>) of the Markdown file it names;
  - any text file names a docs/ path, or a Markdown file names a bare *.md file, that does
    not exist, or a section ('docs/x.md, "Heading"') that the named page has no heading for;
  - any text file uses words that tell the project's history or point outside the
    repository: "session", "issue N", "../shared", the word "contract" (the graph format is
    docs/graph-format.md, not an outside specification); and, in Markdown, dates and commit
    ids (history lives in git log).
Files: those git tracks or would track (not ignored) when SOURCE_DIR is a git checkout,
otherwise every file below it except build*/ and hidden folders. Binary files are skipped.
"""
import os
import re
import subprocess
import sys

SELF = os.path.join("tests", "docs", "check_docs.py")

FORBIDDEN = [
    (re.compile(r"\b[Ss]essions?\b"), "tells the project's history ('session')"),
    (re.compile(r"\b[Ii]ssues?\s+#?\d+"), "names an issue number"),
    (re.compile(r"\.\./shared\b"), "points outside the repository ('../shared')"),
    (re.compile(r"\b[Cc]ontract(?:'s|s)?\b"),
     "refers to an outside specification ('contract'); the reference is docs/graph-format.md"),
]
FORBIDDEN_IN_MARKDOWN = [
    (re.compile(r"\b20\d\d-[01]\d-[0-3]\d\b"), "a date: history lives in git log"),
    # A word of 7-40 hex digits with at least one letter and one digit: a commit id.
    (re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}\b"),
     "a commit id: history lives in git log"),
]

DOCS_PATH = re.compile(r"(?<![\w./-])docs/[\w./-]*")
BARE_MD = re.compile(r"(?<![\w./-])[\w-]+\.md\b")
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_LINK = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)", re.M)
HEADING = re.compile(r"^\s{0,3}#{1,6}\s+(.*?)\s*#*\s*$", re.M)
ANCHOR = re.compile(r"<a\s+(?:id|name)\s*=\s*\"([^\"]+)\"", re.I)
# A section named right after a doc: docs/x.md, "Heading" or docs/x.md "Heading" (the quote may
# run over comment lines).
SECTION_AFTER_NAME = re.compile(
    r'(?:[,:]\s*(?:(?://+|#+)\s*)?| )\(?"([A-Z][^"\n]{0,79}(?:\n[^"\n]{0,80})?)"')
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def repository_files(root):
    try:
        listing = ["git", "-C", root, "ls-files", "-z", "--cached", "--others", "--exclude-standard"]
        out = subprocess.run(listing, capture_output=True, check=True).stdout.decode()
        files = [f for f in out.split("\0") if f]
        if files:
            return [f for f in files if os.path.isfile(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for dirpath, dirnames, filenames in os.walk(root):
        rel = os.path.relpath(dirpath, root)
        dirnames[:] = [d for d in dirnames
                       if not d.startswith(".") and not (rel == "." and d.startswith("build"))]
        files += [os.path.normpath(os.path.join(rel, f)) for f in filenames]
    return files


def read_text(path):
    with open(path, "rb") as f:
        data = f.read()
    if b"\0" in data:
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def blank_fences(text):
    """Markdown with its fenced code blocks blanked (line breaks kept)."""
    out, fence = [], None
    for line in text.split("\n"):
        m = re.match(r"^\s{0,3}(`{3,}|~{3,})", line)
        if fence:
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            out.append("")
        elif m:
            fence = m.group(1)
            out.append("")
        else:
            out.append(line)
    return "\n".join(out)


def prose_of(text):
    """Markdown with code blocks and inline code spans blanked: where links are links."""
    return re.sub(r"(`+)(.+?)\1", lambda s: " " * len(s.group(0)), blank_fences(text))


def slug(heading):
    """GitHub's anchor for a heading: markup dropped, lower case, punctuation removed,
    spaces to hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = re.sub(r"<[^>]+>", "", text).replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(text):
    """The #fragments a Markdown page answers to: its headings' slugs (GitHub numbers repeats
    -1, -2, ...) and its <a id> / <a name> anchors."""
    found, seen = set(), {}
    for h in HEADING.findall(blank_fences(text)):
        s = slug(h)
        n = seen.get(s, 0)
        seen[s] = n + 1
        found.add(s if n == 0 else f"{s}-{n}")
    found.update(ANCHOR.findall(text))
    return found


def line_of(text, offset):
    return text.count("\n", 0, offset) + 1


def check(root):
    """Every finding in the tree at `root`, as 'file:line: what' strings."""
    files = repository_files(root)
    texts = {}
    for f in files:
        t = read_text(os.path.join(root, f))
        if t is not None:
            texts[f] = t
    problems = []

    def problem(f, text, offset, what):
        problems.append(f"{f}:{line_of(text, offset)}: {what}")

    anchor_cache, heading_cache = {}, {}

    def headings_of(path):
        if path not in heading_cache:
            t = read_text(path) or ""
            heading_cache[path] = [" ".join(re.sub(r"[`*]", "", h).split())
                                   for h in HEADING.findall(blank_fences(t))]
        return heading_cache[path]

    def anchors_of(path):
        if path not in anchor_cache:
            t = read_text(path)
            anchor_cache[path] = anchors(t) if t is not None else set()
        return anchor_cache[path]

    for f, text in sorted(texts.items()):
        if f == SELF:
            continue
        markdown = f.endswith(".md")
        for pattern, what in FORBIDDEN + (FORBIDDEN_IN_MARKDOWN if markdown else []):
            for m in pattern.finditer(text):
                problem(f, text, m.start(), f"'{' '.join(m.group(0).split())}' {what}")

        for m in DOCS_PATH.finditer(text):
            name = m.group(0).rstrip(".,;:-/")
            following = text[m.end():m.end() + 1]
            if following in ("$", "*", "{", "<") or m.group(0).endswith("-"):
                continue  # a pattern such as docs/images/gallery-$view.png
            if not os.path.exists(os.path.join(root, name)):
                problem(f, text, m.start(), f"names {name}, which does not exist")
                continue
            section = SECTION_AFTER_NAME.match(text, m.end())
            if name.endswith(".md") and section:
                title = " ".join(re.sub(r"(?m)^\s*(?://+|#+|\*)\s?", " ", section.group(1)).split())
                if not any(h.startswith(title) for h in headings_of(os.path.join(root, name))):
                    problem(f, text, m.start(),
                            f'names section "{title}" of {name}, which has no such heading')

        if markdown:
            here = os.path.dirname(f)
            for m in BARE_MD.finditer(text):
                name = m.group(0)
                if not any(os.path.exists(os.path.join(root, d, name)) for d in (here, "docs", "")):
                    problem(f, text, m.start(),
                            f"names {name}, which is in neither {here or '.'}/, docs/ nor the root")

            prose = prose_of(text)
            targets = [(m.start(1), m.group(1)) for m in INLINE_LINK.finditer(prose)]
            targets += [(m.start(1), m.group(1)) for m in REFERENCE_LINK.finditer(prose)]
            for offset, target in targets:
                if SCHEME.match(target):
                    continue
                path, _, fragment = target.partition("#")
                resolved = os.path.normpath(os.path.join(root, here, path)) if path \
                    else os.path.join(root, f)
                if not resolved.startswith(root + os.sep) and resolved != root:
                    problem(f, text, offset, f"link {target} leaves the repository")
                    continue
                if not os.path.exists(resolved):
                    problem(f, text, offset, f"link {target} does not resolve")
                    continue
                if fragment and resolved.endswith(".md") and fragment not in anchors_of(resolved):
                    problem(f, text, offset,
                            f"link {target}: no heading '#{fragment}' in {os.path.relpath(resolved, root)}")
    return len(texts), problems


# --self-test: a small tree with one case of every kind of finding, and the same cases done
# right, so that a check that stops finding things fails too. The forbidden words are split in
# two so that a grep of the tree for them finds only real uses.
SELF_TEST_FILES = {
    "README.md": "# Top\n\nSee [format](docs/format.md#the-root), [missing](docs/missing.md),\n"
                 "[bad anchor](docs/format.md#no-such-heading), [outside](../elsewhere.md),\n"
                 "[web](https://example.org/x.md) and `[not a link](format.md#nope)` in code.\n",
    "docs/format.md": "# Format\n\n## The root\n\nBack to [top](../README.md#top); [self](#format).\n"
                      "Written in a ses" "sion, see iss" "ue 7 and ../sha" "red/spec, con" "tract §2.\n"
                      "Measured 2026-11-22 at commit 1a2b3c4; seeds 1-10000 are not a commit.\n"
                      "Names gone.md and format.md.\n",
    "include/api.hpp": "// See docs/format.md and docs/conventions.md.\n// docs/images/shot-$view.png\n"
                       "// (docs/format.md, \"The root\") and (docs/format.md, \"The\n// root\"), not\n"
                       "// (docs/format.md, \"Gone\").\n",
}
SELF_TEST_EXPECTED = [
    "README.md:3: link docs/missing.md does not resolve",
    "README.md:3: names docs/missing.md, which does not exist",
    "README.md:4: link docs/format.md#no-such-heading: no heading '#no-such-heading' in docs/format.md",
    "README.md:4: link ../elsewhere.md leaves the repository",
    "docs/format.md:6: 'ses" "sion' tells",
    "docs/format.md:6: 'iss" "ue 7' names an issue number",
    "docs/format.md:6: '../sha" "red' points outside",
    "docs/format.md:6: 'con" "tract' refers to an outside specification",
    "docs/format.md:7: '2026-11-22' a date",
    "docs/format.md:7: '1a2b3c4' a commit id",
    "docs/format.md:8: names gone.md, which is in neither docs/, docs/ nor the root",
    "include/api.hpp:1: names docs/conventions.md, which does not exist",
    'include/api.hpp:5: names section "Gone" of docs/format.md, which has no such heading',
]


def self_test():
    import tempfile
    with tempfile.TemporaryDirectory() as root:
        for name, text in SELF_TEST_FILES.items():
            os.makedirs(os.path.dirname(os.path.join(root, name)), exist_ok=True)
            with open(os.path.join(root, name), "w") as f:
                f.write(text)
        _, problems = check(root)
    missing = [e for e in SELF_TEST_EXPECTED if not any(p.startswith(e) for p in problems)]
    unexpected = [p for p in problems if not any(p.startswith(e) for e in SELF_TEST_EXPECTED)]
    for e in missing:
        print(f"self-test: not found: {e}")
    for p in unexpected:
        print(f"self-test: found, but should not be: {p}")
    print(f"check_docs self-test: {len(SELF_TEST_EXPECTED) - len(missing)} of "
          f"{len(SELF_TEST_EXPECTED)} findings, {len(unexpected)} unexpected")
    return 1 if missing or unexpected else 0


def main():
    if len(sys.argv) == 2 and sys.argv[1] == "--self-test":
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    root = os.path.abspath(sys.argv[1])
    count, problems = check(root)
    # A wrong root reads nothing and finds nothing: the tree's own docs must be among the files.
    if not os.path.isfile(os.path.join(root, "docs", "graph-format.md")) or count < 20:
        print(f"check_docs: {root} is not the skygraph tree ({count} files read)")
        return 1
    for p in problems:
        print(p)
    print(f"check_docs: {count} files, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
