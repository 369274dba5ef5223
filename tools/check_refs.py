#!/usr/bin/env python3
"""Comment reference check: every repository path and every README / docs section that a comment names
must exist. Run by ctest (CommentReferencesResolve); CommentReferencesCatchBadOnes runs it on
tests/packaging/refs_fixture, whose files name a missing path and missing sections.

Scanned: the comments of *.h, *.hpp, *.cpp, *.glsl, *.comp, *.frag, *.vert, *.mesh, *.task (// and
/* */), and of CMakeLists.txt, *.cmake, *.py, *.sh (# comments; a Python file's docstrings too), in
the whole tree except .git, build*/ and out/ (build outputs) and the fixture above.

What counts as a reference:
  - a path whose first part is a top-level folder or file of the repository, ending in a known
    extension (engine/frame_passes.cpp, shaders/shared/config.h, docs/culling.md): it must exist from
    the root. A folder path ending in / (shadows/virtual/) must be a folder.
  - a bare file name with a source extension (vsm_prepare.cpp, light_math.h, check_layers.py): some
    file of that name must exist in the tree.
  - a section of the README or of a page in docs/: README "Exit status", README, "Exit status",
    README *Status*, docs/reliability.md section "Limits ...", culling.md, "Sorted lists",
    accuracy.md section 4, docs/culling.md#sorted-lists: a heading of that page must read so (case
    aside; a cited title may be the start of a longer heading), or, for a number, start with it, or,
    for an anchor, have that GitHub slug.
Not references: globs (*), $VARIABLES, paths under out/, build/, /tmp, ../ (outside the tree),
URLs, one-letter names (n.h is a dot product). A path manylights/x (the public API as a host includes
it) must exist as include/manylights/x, but for what the build generates (see ALLOWED).

Markdown links: in README.md and every docs/ page (outside code fences), a link [text](target) whose
target is not a URL must name a file that exists (relative to the page), and an anchor (#section, on
its own or after the page's file name) must be the GitHub slug of a heading of that page.

Output: one line per problem, "file:line: names X which does not exist", and exit status 1; exit 0
when every reference resolves. --root DIR checks another tree (the fixture); --verbose also prints
the count of references checked.
"""
import os
import re
import sys

C_LIKE = (".h", ".hpp", ".cpp", ".glsl", ".comp", ".frag", ".vert", ".mesh", ".task")
HASH = (".py", ".sh", ".cmake")
PATH_EXT = ("h|hpp|cpp|c|glsl|comp|frag|vert|mesh|task|py|sh|cmake|md|txt|json|png|yaml|sbatch|gltf|glb|"
            "in|conf|csv|svg")
BARE_EXT = ("h", "hpp", "cpp", "glsl", "comp", "frag", "vert", "mesh", "task", "py", "sh", "cmake", "md")
SKIP_DIRS = {".git", "out", "node_modules", "__pycache__"}
FIXTURE = os.path.join("tests", "packaging", "refs_fixture")
# Paths that name generated files, with the reason they are not in the tree.
ALLOWED = {
    "manylights/manylights.glsl": "the host-shader include, generated at configure time (cmake/install.cmake)",
    "installed_include/": "the build tree's copy of the installed headers",
}
# The public API: a path manylights/x is include/manylights/x.
PUBLIC_PREFIX, PUBLIC_DIR = "manylights/", "include"
# Bare file names that are not in the tree, with the reason.
ALLOWED_NAMES = {
    "SOURCES.md": "the shared scenes' list of sources, in ../shared/scenes/ beside the checkout",
    "manylights.glsl": "the host-shader include, generated at configure time (cmake/install.cmake)",
}

PATH_RE = re.compile(r"(?<![\w./$*<-])((?:\.\./)*[A-Za-z0-9_][A-Za-z0-9_.+-]*(?:/[A-Za-z0-9_.+-]+)*"
                     r"(?:\.(?:" + PATH_EXT + r")(?![\w*])|/(?=[\s`'\",;:)]|$)))")
BARE_RE = re.compile(r"(?<![\w./$*<-])([A-Za-z0-9_][A-Za-z0-9_+-]+(?:\.[A-Za-z0-9_+-]+)*\.(?:" +
                     "|".join(BARE_EXT) + r"))(?![\w*/])")
QUOTE = r"(?:\"([^\"]+)\"|\*([^*]+)\*)"
README_SEC_RE = re.compile(r"\bREADME(?:\.md)?(?:'s)?,?\s+(?:section\s+)?" + QUOTE)
DOC_SEC_RE = re.compile(r"((?:docs/)?[a-z0-9-]+\.md)(?:,?\s+section\s+|,\s+|\s+)" + QUOTE)
DOC_NUM_RE = re.compile(r"((?:docs/)?[a-z0-9-]+\.md),?\s+section\s+(\d+)\b")
ANCHOR_RE = re.compile(r"((?:docs/)?[A-Za-z0-9_/-]*[A-Za-z0-9_-]+\.md)#([A-Za-z0-9_-]+)")


def comments_c(text):
    """(line, comment text) for // and /* */ comments, skipping string and character literals."""
    out, i, n, line = [], 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1; i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i); j = n if j < 0 else j
            out.append((line, text[i + 2:j])); i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2); j = n if j < 0 else j
            for k, part in enumerate(text[i + 2:j].split("\n")): out.append((line + k, part))
            line += text.count("\n", i, j); i = j + 2
        elif c == 'R' and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m: i += 1; continue
            end = text.find(")" + m.group(1) + '"', i); end = n if end < 0 else end
            line += text.count("\n", i, end); i = end + len(m.group(1)) + 2
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1
    return out


def comments_hash(text, python):
    """(line, comment text) for # comments outside quotes (and Python docstrings)."""
    out = []
    if python:
        for m in re.finditer(r'(?s)("""|\'\'\')(.*?)\1', text):
            first = text.count("\n", 0, m.start()) + 1
            for k, part in enumerate(m.group(2).split("\n")): out.append((first + k, part))
    in_doc = None
    for no, raw in enumerate(text.split("\n"), 1):
        if no == 1 and raw.startswith("#!"): continue
        quote, i = None, 0
        while i < len(raw):
            c = raw[i]
            if python and raw.startswith(('"""', "'''"), i):
                in_doc = None if in_doc == raw[i:i + 3] else (in_doc or raw[i:i + 3]); i += 3; continue
            if in_doc: i += 1; continue
            if quote:
                if c == "\\": i += 2; continue
                if c == quote: quote = None
            elif c in "\"'":
                quote = c
            elif c == "#" and (i == 0 or raw[i - 1] in " \t(;"):
                out.append((no, raw[i + 1:])); break
            i += 1
    return out


def headings(path):
    """The headings of a markdown file (outside code fences), as written."""
    found, fence = [], False
    try:
        with open(path, errors="replace") as f:
            for line in f:
                if line.lstrip().startswith("```"): fence = not fence; continue
                if not fence and re.match(r"#{1,6} ", line): found.append(line.lstrip("#").strip())
    except OSError:
        return None
    return found


def slug(h):
    s = re.sub(r"[`*_]", "", h).strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def github_slug(h):
    """GitHub's anchor for a heading: lower case, punctuation but - and _ dropped, spaces to -."""
    s = re.sub(r"[^\w\- ]", "", h.strip().lower())
    return s.replace(" ", "-")


LINK_RE = re.compile(r"\]\(([^)\s]+)\)")


def check_markdown(tree, rel, problems, counts):
    """The links of a markdown page: files that exist, anchors that are headings' slugs."""
    here, fence = os.path.dirname(rel), False
    with open(os.path.join(tree.root, rel), errors="replace") as f: lines = f.read().split("\n")
    for no, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"): fence = not fence; continue
        if fence: continue
        for m in LINK_RE.finditer(line):
            target = m.group(1)
            if re.match(r"[a-z]+:", target): continue  # http:, https:, mailto:
            path, _, anchor = target.partition("#")
            page = os.path.normpath(os.path.join(here, path)) if path else rel
            if page.startswith(".."): continue  # outside the tree (../shared/...)
            counts[0] += 1
            if not os.path.exists(os.path.join(tree.root, page)):
                problems.append(f"{rel}:{no}: links to {target} which does not exist"); continue
            if anchor and page.endswith(".md"):
                hs = tree.heads(page) or []
                if anchor not in {github_slug(h) for h in hs} | {slug(h) for h in hs}:
                    problems.append(f"{rel}:{no}: links to {target} which does not exist")


def norm(t):
    return re.sub(r"\s+", " ", re.sub(r"[`*_]", "", t)).strip().lower().rstrip(".:")


class Tree:
    def __init__(self, root):
        self.root = root
        self.top = set(os.listdir(root)) - SKIP_DIRS
        self.names = set()
        self.files = []
        for dirpath, dirnames, filenames in os.walk(root):
            rel = os.path.relpath(dirpath, root)
            dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not d.startswith("build")
                                 and not os.path.exists(os.path.join(dirpath, d, "CMakeCache.txt")))
            for name in filenames:
                self.names.add(name)
                if name.endswith(".in"): self.names.add(name[:-3])  # configure_file's output
                self.files.append(os.path.normpath(os.path.join(rel, name)))
        self.head_cache = {}

    def heads(self, page):
        if page not in self.head_cache: self.head_cache[page] = headings(os.path.join(self.root, page))
        return self.head_cache[page]

    def doc_page(self, name, src):
        """The markdown file a citation names: from the root, beside the citing file, or in docs/."""
        for cand in (name, os.path.join(os.path.dirname(src), name), os.path.join("docs", name)):
            cand = os.path.normpath(cand)
            if os.path.isfile(os.path.join(self.root, cand)): return cand
        return None


def check_file(tree, rel, problems, counts):
    path = os.path.join(tree.root, rel)
    with open(path, errors="replace") as f: text = f.read()
    name = os.path.basename(rel)
    if name.endswith(C_LIKE): comments = comments_c(text)
    else: comments = comments_hash(text, name.endswith(".py"))
    here = os.path.dirname(rel)

    def bad(line, what): problems.append(f"{rel}:{line}: names {what} which does not exist")

    for line, c in comments:
        if "://" in c: c = re.sub(r"\w+://\S+", " ", c)
        spans = []
        for m in README_SEC_RE.finditer(c):
            title = m.group(1) or m.group(2); counts[0] += 1; spans.append(m.span())
            hs = tree.heads("README.md") or []
            if not any(norm(h).startswith(norm(title)) for h in hs): bad(line, f'README section "{title}"')
        for m in DOC_SEC_RE.finditer(c):
            page = tree.doc_page(m.group(1), rel)
            title = m.group(2) or m.group(3); counts[0] += 1; spans.append(m.span())
            if page is None: bad(line, m.group(1)); continue
            if not any(norm(h).startswith(norm(title)) for h in tree.heads(page) or []):
                bad(line, f'{m.group(1)} section "{title}"')
        for m in DOC_NUM_RE.finditer(c):
            page = tree.doc_page(m.group(1), rel); counts[0] += 1; spans.append(m.span())
            if page is None: bad(line, m.group(1)); continue
            if not any(re.match(re.escape(m.group(2)) + r"\b", h) for h in tree.heads(page) or []):
                bad(line, f"{m.group(1)} section {m.group(2)}")
        for m in ANCHOR_RE.finditer(c):
            page = tree.doc_page(m.group(1), rel); counts[0] += 1; spans.append(m.span())
            if page is None: bad(line, m.group(1)); continue
            if m.group(2).lower() not in {slug(h) for h in tree.heads(page) or []}:
                bad(line, f"{m.group(1)}#{m.group(2)}")
        for m in PATH_RE.finditer(c):
            tok = m.group(1)
            if "/" not in tok or any(a <= m.start(1) < b for a, b in spans if tok.endswith(".md")): continue
            if any(tok.startswith(p) or ("/" + p) in tok for p in ALLOWED): continue
            first = tok.split("/")[0]
            if tok.startswith(PUBLIC_PREFIX) and os.path.isdir(os.path.join(tree.root, PUBLIC_DIR)):
                counts[0] += 1
                if not os.path.exists(os.path.join(tree.root, PUBLIC_DIR, tok)): bad(line, tok)
                continue
            if tok.startswith("../"):
                continue  # outside the tree (../shared/...), as comments use it
            elif first in tree.top and first not in ("out", "build"):
                target = os.path.normpath(tok)
            else:
                continue
            counts[0] += 1
            full = os.path.join(tree.root, target)
            if not (os.path.isdir(full) if tok.endswith("/") else os.path.exists(full)): bad(line, tok)
        for m in BARE_RE.finditer(c):
            tok = m.group(1)
            if m.start(1) > 0 and c[m.start(1) - 1] == "/": continue
            counts[0] += 1
            if tok not in tree.names and tok not in ALLOWED_NAMES: bad(line, tok)


def main():
    args = sys.argv[1:]
    if any(a in ("-h", "--help") for a in args):
        print(__doc__ + "\nusage: check_refs.py [--root DIR] [--verbose]")
        return 0
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
    if "--root" in args:
        i = args.index("--root")
        if i + 1 >= len(args): print("check_refs: --root needs a folder", file=sys.stderr); return 2
        root = os.path.abspath(args[i + 1]); del args[i:i + 2]
    verbose = "--verbose" in args
    unknown = [a for a in args if a != "--verbose"]
    if unknown: print(f"check_refs: unknown argument '{unknown[0]}' (see --help)", file=sys.stderr); return 2
    tree = Tree(root)
    problems, counts, scanned = [], [0], 0
    for rel in sorted(tree.files):
        if rel.startswith(FIXTURE + os.sep): continue
        name = os.path.basename(rel)
        if not (name.endswith(C_LIKE) or name.endswith(HASH) or name == "CMakeLists.txt"): continue
        scanned += 1
        check_file(tree, rel, problems, counts)
    for rel in sorted(tree.files):
        if rel.endswith(".md") and (rel == "README.md" or rel.startswith("docs" + os.sep)):
            scanned += 1
            check_markdown(tree, rel, problems, counts)
    for p in problems: print(p)
    if verbose or problems:
        print(f"check_refs: {scanned} files, {counts[0]} references, {len(problems)} that do not resolve",
              file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
