#!/usr/bin/python3
"""Docs whose numbers cannot go stale: reruns every command whose output a doc quotes.

A quoted number is marked in the markdown by an HTML comment right after it, naming its check
and value (invisible on the rendered page):

    RK4 diverges at t = 0.042<!--=clip.rk4_at--> s

and a check is an HTML comment followed by the fenced block whose command it runs, the very
command the reader sees, so the two cannot drift apart:

    <!-- check clip [full]
      rk4_at: ^rk4\\b.*?diverged at t = (\\S+) s
      mid_mm: ^midpoint\\b.*? (\\S+) m$ | x 1e3
      ahead: = expl_mm / mid_mm | tol 2%
    -->
    ```sh
    build/clothsim compare scenes/drape_smooth.yaml --still 2.5 -o drape.png
    ```

Each value line is `KEY: REGEX [| x SCALE] [| tol PCT%] [| nth N]`: the first (or Nth, from 1)
match of REGEX (Python syntax, multiline) in the command's stdout and stderr, its first group
a number, times SCALE (the doc's unit: x 1e3 for a figure printed in m and quoted in mm);
or `KEY: = EXPRESSION` over the check's other values (a ratio the prose states). A check
marked [full] runs only under --full (the default set fits in about 2 minutes on a 2-core
machine); [manual] checks are never run, only listed (timings of a whole figure).

Tolerance: a quoted value holds when the printed one rounds to it at the figures quoted
("3.3" holds for 3.25 .. 3.35), or lies within the value's `tol` (default 0 %: the figures
themselves are the tolerance; timings and ratios of timings state theirs).

The commands run in a scratch directory holding links to the repository's build/, scenes/
and tools/, so the files they write (drape.png, wp.png) land there and never in the tree.
    tools/check_docs.sh [--full] [--update] [--build DIR] [--only NAME[,NAME]] [FILE.md...]
--update rewrites every differing quoted value in place with the printed one, at the
figures it was quoted to, and says what it changed. Exit 0 when every value holds (or was
updated), 1 when one differs, 2 for a malformed mark.

Pointers. Before the numbers, a run over the repository's own docs (no FILE.md given) checks,
in about a second and with no build, that every pointer to a file or a section resolves;
`--pointers` runs that check alone. It reads every markdown file git knows of (tracked or
untracked, not ignored), outside fenced blocks and HTML comments, and the comments (`//` in
C and C++ sources, `#` in Python, shell, CMake and YAML) of the files under src/, render/,
tools/, tests/, scenes/ and the top CMakeLists.txt, lines joined so that a pointer may wrap:
  - a markdown link or image to a relative path names a file or folder that exists; a
    `#anchor`, on it or alone, names a heading of the target (GitHub's slug of it);
  - a repository path, a word beginning with src/, docs/, tools/, scenes/, tests/ or
    render/ (in markdown in or out of backticks, in comments anywhere), exists: a file, a
    folder, a file of that stem with any extension (tools/video/tiling), a glob's match; a
    trailing :LINE is dropped, {a,b} alternatives are each checked, and a word holding a
    placeholder (NAME, DIR: three capitals or more), `%`, `$`, `<`, `=` or `...` is skipped;
  - every NAME.md named (DESIGN.md) exists, looked up beside the naming file, from the
    root, then in docs/;
  - a section reference, `FILE.md, "Section"` or `FILE.md "Section"` or `"Section" (FILE.md)`
    (also `FILE.md, #37 "Section"`, `[FILE.md](FILE.md), "Section"`, `README's "Section"`, and
    a bare README or BENCHMARKS for README.md, BENCHMARKS.md), names a heading of FILE: equal
    to it, case and backticks and asterisks aside, or its start up to a colon, a comma, a
    bracket or a space before one (`"Small steps"` names "Small steps: the guess, ...").
Each pointer that does not resolve is printed as FILE:LINE: what is missing, and the run
exits 1 (after the numbers, if those ran).

Pictures. Under --full (or --pictures alone), after the numbers, tools/make_figures.sh remakes
every picture of docs/images into the scratch directory and each is compared with the tree's:
a render or an energy or stability plot by `clothsim imgdiff` at the golden tolerances (its
defaults); a plot that draws CPU time (TIMED below) by the CSV kept beside it, every column but
the timings, to 6 significant figures, since the load moves its points. A picture in docs/images
that the script does not make fails too. --update copies the differing ones into docs/images.
"""
import argparse
import bisect
import glob
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_DOCS = ["README.md", "docs/report.md", "docs/integrators.md"]
CHECK = re.compile(r"<!--\s*check\s+([\w-]+)\s*(?:\[(\w+)\])?\s*\n(.*?)-->\s*\n\s*```(?:sh|bash)?\n(.*?)```", re.S)
NUMBER = r"[-+]?(?:\d[\d,]*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
MARK = re.compile(r"(" + NUMBER + r")<!--=([\w-]+)\.([\w-]+)-->")


class DocError(Exception):
    pass


class Value:
    def __init__(self, key, spec, where):
        self.key, self.where = key, where
        self.scale, self.tol, self.nth, self.expr, self.regex = 1.0, 0.0, 1, None, None
        parts = [p.strip() for p in spec.split(" | ")]
        if parts[0].startswith("="):
            self.expr = parts[0][1:].strip()
        else:
            try:
                self.regex = re.compile(parts[0], re.M)
            except re.error as e:
                raise DocError(f"{where}: {key}: bad regex: {e}")
            if self.regex.groups < 1:
                raise DocError(f"{where}: {key}: the regex has no (group) for the number")
        for p in parts[1:]:
            word, _, arg = p.partition(" ")
            try:
                if word == "x":
                    self.scale = float(arg)
                elif word == "tol":
                    self.tol = float(arg.rstrip("%")) / 100.0
                elif word == "nth":
                    self.nth = int(arg)
                else:
                    raise ValueError
            except ValueError:
                raise DocError(f"{where}: {key}: cannot read {p!r} (x SCALE, tol PCT%, nth N)")


class Check:
    def __init__(self, doc, name, tier, body, command, line):
        self.doc, self.name, self.tier, self.line = doc, name, tier or "default", line
        if self.tier not in ("default", "full", "manual"):
            raise DocError(f"{doc}:{line}: check {name}: unknown tier [{tier}] (default, full, manual)")
        self.command = command.strip()
        self.values = {}
        for i, raw in enumerate(body.splitlines()):
            if not raw.strip():
                continue
            key, colon, spec = raw.strip().partition(":")
            if not colon or not re.fullmatch(r"[\w-]+", key.strip()):
                raise DocError(f"{doc}:{line + 1 + i}: check {name}: expected KEY: REGEX, got {raw.strip()!r}")
            self.values[key.strip()] = Value(key.strip(), spec.strip(), f"{doc}:{line + 1 + i}")


def parse(doc, text):
    checks = {}
    for m in CHECK.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        c = Check(doc, m.group(1), m.group(2), m.group(3), m.group(4), line)
        if c.name in checks:
            raise DocError(f"{doc}:{line}: check {c.name} is defined twice")
        checks[c.name] = c
    marks = []
    for m in MARK.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        name, key = m.group(2), m.group(3)
        if name not in checks or key not in checks[name].values:
            raise DocError(f"{doc}:{line}: {m.group(1)}<!--={name}.{key}--> names no value of a check in {doc}")
        marks.append((m, line))
    return checks, marks


def significant(text):
    """Figures quoted: '3.3' 2, '0.042' 2, '24' 2, '1.0e-4' 2, '50 000' handled by the caller."""
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(",", "")
    digits = mantissa.replace(".", "").lstrip("0")
    return max(1, len(digits))


def as_number(text):
    return float(text.replace(",", ""))


def rounded(value, figures):
    if value == 0 or not math.isfinite(value):
        return value
    return round(value, figures - 1 - int(math.floor(math.log10(abs(value)))))


def holds(quoted_text, printed, tol):
    quoted = as_number(quoted_text)
    if not math.isfinite(printed):
        return False
    if "." in quoted_text or "e" in quoted_text.lower():
        figures = significant(quoted_text)
        if rounded(printed, figures) == rounded(quoted, figures):
            return True
    elif round(printed) == quoted:  # an integer quoted: its last digit
        return True
    return abs(printed - quoted) <= tol * abs(quoted)


def written(quoted_text, printed):
    """`printed` as `quoted_text` was written: its figures, its notation."""
    figures = significant(quoted_text)
    if "e" in quoted_text.lower():
        mantissa, _, exponent = f"{printed:.{figures - 1}e}".partition("e")
        return f"{mantissa}e{int(exponent)}"
    if "." not in quoted_text:
        return str(int(round(printed)))
    v = rounded(printed, figures)
    decimals = max(0, figures - 1 - int(math.floor(math.log10(abs(v))))) if v else figures - 1
    return f"{v:.{decimals}f}"


def run(check, build, scratch, timeout):
    work = os.path.join(scratch, check.name)
    os.makedirs(work, exist_ok=True)
    for link in ("scenes", "tools", "docs"):
        if not os.path.exists(os.path.join(work, link)):
            os.symlink(os.path.join(ROOT, link), os.path.join(work, link))
    if not os.path.exists(os.path.join(work, "build")):
        os.symlink(build, os.path.join(work, "build"))
    started, cpu0 = time.time(), os.times()
    try:
        p = subprocess.run(["sh", "-c", check.command], cwd=work, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, f"timed out after {timeout} s", time.time() - started, 0.0
    cpu1 = os.times()
    cpu = (cpu1.children_user - cpu0.children_user) + (cpu1.children_system - cpu0.children_system)
    return p.stdout + p.stderr, (None if p.returncode in (0, 3) else f"exit {p.returncode}"), time.time() - started, cpu


def evaluate(check, output):
    got, problems = {}, []
    for key, v in check.values.items():
        if v.regex:
            found = list(v.regex.finditer(output))
            if len(found) < v.nth:
                problems.append(f"{key}: /{v.regex.pattern}/ matched {len(found)} times, wanted match {v.nth}")
                continue
            try:
                got[key] = as_number(found[v.nth - 1].group(1)) * v.scale
            except ValueError:
                problems.append(f"{key}: matched {found[v.nth - 1].group(1)!r}, not a number")
    for key, v in check.values.items():
        if v.expr:
            try:
                got[key] = float(eval(v.expr, {"__builtins__": {}, "min": min, "max": max, "abs": abs}, dict(got))) * v.scale
            except Exception as e:  # a missing operand is reported above; say the expression's own fault
                problems.append(f"{key}: = {v.expr}: {e}")
    return got, problems


# ---- pointers ------------------------------------------------------------------------------
POINTER_FILE = r"((?:[\w.-]+/)*[\w-]+\.md|\bREADME\b|\bBENCHMARKS\b)(?:#([\w-]+))?\]?(?:\([^)\s]*\))?(?:'s)?"
REF_AFTER = re.compile(POINTER_FILE + r",?\s+(?:#\d+,?\s+)?\(?\"([^\"\n]{2,120}?)\"")
REF_BEFORE = re.compile(r"\"([^\"\n]{2,120}?)\"\s+\((?:see\s+)?" + POINTER_FILE + r"\)")
MD_NAME = re.compile(r"(?<![\w./-])((?:[\w.-]+/)*[\w-]+\.md)\b")
LINK = re.compile(r"!?\[[^\]\n]*\]\(([^)\s]+)\)")
REPO_PATH = re.compile(r"(?<![\w/.\-$])((?:src|docs|tools|scenes|tests|render)/(?:[^\s`\"'()\[\]<>,;{}]|\{[^{}\s]*\})*)")
PLACEHOLDER = re.compile(r"[A-Z]{3,}|[%$<=]|\.\.\.")
COMMENTED_DIRS = ("src/", "render/", "tools/", "tests/", "scenes/")
SLASH_COMMENTS = (".h", ".hpp", ".cpp", ".cc", ".c", ".inl")
HASH_COMMENTS = (".py", ".sh", ".cmake", ".yaml", ".yml")


def repo_files():
    try:
        out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout
        return sorted(f for f in set(out.splitlines()) if os.path.isfile(os.path.join(ROOT, f)))
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", "build"}
        return sorted(os.path.relpath(os.path.join(d, f), ROOT) for d, dirs, fs in os.walk(ROOT)
                      if not dirs.__setitem__(slice(None), [x for x in dirs if x not in skip]) for f in fs)


def title(text):
    """A heading or a quoted section, compared: case, backticks and asterisks aside."""
    t = text.replace("`", "").replace("*", "").replace("\u00d7", "x").lower()
    return re.sub(r"\s+", " ", t).strip().rstrip(".:")


def slug(text):
    """GitHub's anchor for a heading."""
    return re.sub(r"[^\w\- ]", "", text.strip().lower().replace("`", "")).replace(" ", "-")


def prose(text):
    """The markdown outside fenced blocks and HTML comments, blanked in place (lines and offsets hold)."""
    out, fenced = [], False
    for line in text.split("\n"):
        fence = line.lstrip().startswith("```")
        out.append(" " * len(line) if fenced or fence else line)
        fenced = fenced != fence
    return re.sub(r"<!--.*?-->", lambda m: re.sub(r"[^\n]", " ", m.group(0)), "\n".join(out), flags=re.S)


def comments(path, text):
    """A source file's comments, each at its place, the code (and a Python file's docstrings) blanked."""
    if path.endswith(".py"):
        text = re.sub(r'(?s)""".*?"""|\'\'\'.*?\'\'\'', lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    out = []
    for line in text.split("\n"):
        if path.endswith(SLASH_COMMENTS):
            m = re.search(r"(?<!:)//", line)
        else:
            m = re.search(r"(?:^|(?<=\s))#", line)
        out.append(" " * m.end() + line[m.end():] if m else "")
    return "\n".join(out)


class Tree:
    def __init__(self):
        self.files = repo_files()
        self.paths = set(self.files)
        for f in self.files:
            while "/" in f:
                f = f.rsplit("/", 1)[0]
                self.paths.add(f)
        self._heads = {}

    def exists(self, rel):
        rel = os.path.normpath(rel)
        return rel in self.paths or (not rel.startswith("..") and os.path.exists(os.path.join(ROOT, rel)))

    def markdown(self, name, where):
        name = {"README": "README.md", "BENCHMARKS": "BENCHMARKS.md"}.get(name, name)
        for cand in (os.path.join(os.path.dirname(where), name), name, os.path.join("docs", name)):
            if os.path.normpath(cand) in self.paths:
                return os.path.normpath(cand)
        return None

    def heads(self, md):
        if md not in self._heads:
            titles, slugs, seen = set(), set(), {}
            with open(os.path.join(ROOT, md)) as f:
                for line in prose(f.read()).split("\n"):
                    m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                    if m:
                        titles.add(title(m.group(1)))
                        n = seen.get(slug(m.group(1)), 0)
                        seen[slug(m.group(1))] = n + 1
                        slugs.add(slug(m.group(1)) + (f"-{n}" if n else ""))
            self._heads[md] = (titles, slugs)
        return self._heads[md]

    def has_section(self, md, section):
        want = title(section)
        return any(h == want or (h.startswith(want) and re.match(r"[:,(\[ ]", h[len(want)]))
                   for h in self.heads(md)[0])


def alternatives(word):
    m = re.search(r"\{([^{}]*)\}", word)
    return [word] if not m else [w for alt in m.group(1).split(",")
                                 for w in alternatives(word[:m.start()] + alt + word[m.end():])]


def check_pointers():
    """Every pointer in the docs and the sources' comments that does not resolve, as FILE:LINE: why."""
    tree, problems = Tree(), []
    for rel in tree.files:
        is_md = rel.endswith(".md")
        commented = (rel.startswith(COMMENTED_DIRS) or rel == "CMakeLists.txt") and (
            rel.endswith(SLASH_COMMENTS + HASH_COMMENTS) or os.path.basename(rel) == "CMakeLists.txt")
        if not (is_md or commented):
            continue
        try:
            with open(os.path.join(ROOT, rel)) as f:
                text = prose(f.read()) if is_md else comments(rel, f.read())
        except UnicodeDecodeError:
            continue
        starts = [0] + [m.end() for m in re.finditer("\n", text)]
        flat = re.sub(r"\s*\n\s*", lambda m: " " * len(m.group(0)), text)  # lines joined, offsets kept

        def report(pos, what):
            problems.append(f"{rel}:{bisect.bisect_right(starts, pos)}: {what}")

        named = set()
        for rx, fi, ai, si in ((REF_AFTER, 1, 2, 3), (REF_BEFORE, 2, 3, 1)):
            for m in rx.finditer(flat):
                named.add(m.start(fi))
                md = tree.markdown(m.group(fi), rel)
                section = re.sub(r"\s+", " ", m.group(si))
                if md is None:
                    report(m.start(), f"{m.group(fi)} does not exist")
                elif not tree.has_section(md, section):
                    report(m.start(), f"{md} has no section \"{section}\"")
                elif m.group(ai) and m.group(ai) not in tree.heads(md)[1]:
                    report(m.start(), f"{md} has no heading #{m.group(ai)}")
        linked = {i for m in LINK.finditer(flat) for i in range(m.start(1), m.end(1))} if is_md else set()
        for m in MD_NAME.finditer(flat):
            if m.start(1) not in named | linked and tree.markdown(m.group(1), rel) is None:
                report(m.start(), f"{m.group(1)} does not exist")
        for m in REPO_PATH.finditer(flat):
            word = re.sub(r"'s$", "", m.group(1).rstrip(".:")).split("#")[0]
            if PLACEHOLDER.search(word):
                continue
            for path in alternatives(re.sub(r":\d+$", "", word)):
                if not (glob.glob(os.path.join(ROOT, path)) if "*" in path else
                        tree.exists(path) or glob.glob(os.path.join(ROOT, glob.escape(path) + ".*"))):
                    report(m.start(), f"{path} does not exist")
        if not is_md:
            continue
        for m in LINK.finditer(flat):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue
            path, _, anchor = target.partition("#")
            full = os.path.normpath(os.path.join(os.path.dirname(rel), path)) if path else rel
            if path and not tree.exists(full):
                report(m.start(), f"link to {target}: {full} does not exist")
            elif anchor and full.endswith(".md") and anchor not in tree.heads(full)[1]:
                report(m.start(), f"link to {target}: {full} has no heading #{anchor}")
    return problems


# The figures that draw CPU time: judged by their CSV's other columns, not their pixels.
TIMED = {"bench_spring", "bench_drape", "bench_drape_smooth", "budget_drape_smooth",
         "converge_drape", "converge_drape64", "converge_stiff"}
TIMING_COLUMNS = {"wall_seconds", "cpu_seconds"}


def same_csv(a, b):
    """'' when the two CSVs agree on every column but the timings (numbers to 6 figures),
    else the first difference."""
    import csv
    with open(a) as f:
        ra = list(csv.DictReader(f))
    with open(b) as f:
        rb = list(csv.DictReader(f))
    if len(ra) != len(rb):
        return f"{len(rb)} rows, the tree's {len(ra)}"
    for i, (x, y) in enumerate(zip(ra, rb), 2):
        for k in x:
            if k in TIMING_COLUMNS or x[k] == y.get(k):
                continue
            try:
                u, v = float(x[k]), float(y.get(k, "nan"))
                if u == v or abs(u - v) <= 1e-6 * max(abs(u), abs(v)):
                    continue
            except ValueError:
                pass
            return f"line {i}, {k}: {y.get(k)!r}, the tree's {x[k]!r}"
    return ""


def check_pictures(build, scratch, update):
    """Remakes every picture of docs/images and compares each with the tree's; the number that
    differ or are not remade."""
    images = os.path.join(ROOT, "docs", "images")
    made = os.path.join(scratch, "figures")
    start = time.time()
    p = subprocess.run(["sh", os.path.join(ROOT, "tools", "make_figures.sh"), build, made],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(f"== pictures: tools/make_figures.sh in {time.time() - start:.0f} s")
    if p.returncode != 0:
        print("   FAILED: tools/make_figures.sh exited " + str(p.returncode) + "\n"
              + "\n".join("   | " + l for l in p.stdout.strip().splitlines()[-8:]))
        return 1
    failed = 0
    names = sorted(f[:-4] for f in os.listdir(images) if f.endswith(".png"))
    for name in names:
        new = os.path.join(made, name + ".png")
        if not os.path.exists(new):
            print(f"   FAILED docs/images/{name}.png: tools/make_figures.sh does not make it")
            failed += 1
            continue
        if name in TIMED:
            csvs = [os.path.join(d, name + ".csv") for d in (images, made)]
            missing = [c for c in csvs if not os.path.exists(c)]
            why = (f"{os.path.relpath(missing[0], ROOT) if missing[0].startswith(ROOT) else missing[0]} is missing: "
                   "a timed figure is judged by its CSV") if missing else same_csv(*csvs)
        else:
            d = subprocess.run([os.path.join(build, "clothsim"), "imgdiff", os.path.join(images, name + ".png"), new],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            why = "" if d.returncode == 0 else (d.stdout.strip().splitlines() or ["imgdiff failed"])[-1]
        if not why:
            continue
        if update:
            for ext in (".png", ".csv"):
                if os.path.exists(os.path.join(made, name + ext)) and (ext == ".png" or os.path.exists(os.path.join(images, name + ext))):
                    shutil.copyfile(os.path.join(made, name + ext), os.path.join(images, name + ext))
            print(f"   updated docs/images/{name}.png: {why}")
        else:
            failed += 1
            print(f"   DIFFERS docs/images/{name}.png: {why}")
    print(f"check_docs: pictures: {len(names)} compared, {failed} differ or are not remade")
    return failed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("docs", nargs="*", help="markdown files (default: README.md docs/report.md)")
    ap.add_argument("--full", action="store_true", help="also the [full] checks (several minutes)")
    ap.add_argument("--update", action="store_true", help="rewrite differing quoted values with the printed ones")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory holding clothsim")
    ap.add_argument("--only", default="", help="comma-separated check names")
    ap.add_argument("--list", action="store_true", help="list the checks and their values, run nothing")
    ap.add_argument("--pointers", action="store_true", help="check only that every pointer to a file or section resolves")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per command")
    ap.add_argument("--pictures", action="store_true", help="only remake and compare docs/images (--full does it too)")
    args = ap.parse_args()
    docs = args.docs or [os.path.join(ROOT, d) for d in DEFAULT_DOCS]
    only = set(filter(None, args.only.split(",")))
    build = os.path.abspath(args.build)
    dangling = []
    if args.pointers or not (args.docs or args.list or only):
        dangling = check_pointers()
        for p in dangling:
            print(f"   DANGLING {p}")
        print(f"check_docs: pointers: {len(dangling)} do not resolve")
        if args.pointers:
            return 1 if dangling else 0
    if not args.list and not os.access(os.path.join(build, "clothsim"), os.X_OK):
        print(f"check_docs: {build}/clothsim not found (build first, or give --build DIR)", file=sys.stderr)
        return 2
    failed = updated = checked = 0
    scratch = tempfile.mkdtemp(prefix="check_docs.")
    try:
        for doc in ([] if args.pictures else docs):
            rel = os.path.relpath(doc, ROOT) if os.path.abspath(doc).startswith(ROOT + os.sep) else doc
            with open(doc) as f:
                text = f.read()
            try:
                checks, marks = parse(rel, text)
            except DocError as e:
                print(f"check_docs: {e}", file=sys.stderr)
                return 2
            if args.list:
                for c in checks.values():
                    print(f"{rel}:{c.line}: {c.name} [{c.tier}] {len(c.values)} values: {c.command.splitlines()[0]}")
                continue
            results = {}
            for c in checks.values():
                if (only and c.name not in only) or c.tier == "manual" or (c.tier == "full" and not args.full and not only):
                    continue
                output, error, wall, cpu = run(c, build, scratch, args.timeout)
                load = open("/proc/loadavg").read().split()[0] if os.path.exists("/proc/loadavg") else "?"
                print(f"== {rel}:{c.line} {c.name}: {wall:.1f} s wall, {cpu:.1f} s CPU (load {load})")
                if error:
                    print(f"   FAILED: the command ({c.command.splitlines()[0]} ...) gave {error}\n"
                          + "\n".join("   | " + l for l in (output or "").strip().splitlines()[-8:]))
                    failed += 1
                    continue
                got, problems = evaluate(c, output)
                for p in problems:
                    print(f"   FAILED: {p}")
                failed += len(problems)
                results[c.name] = got
            out, at = [], 0
            for m, line in marks:
                name, key, quoted = m.group(2), m.group(3), m.group(1)
                if name not in results or key not in results[name]:
                    continue
                checked += 1
                printed = results[name][key]
                v = checks[name].values[key]
                if holds(quoted, printed, v.tol):
                    continue
                new = written(quoted, printed)
                tol = f", tolerance {v.tol * 100:g} %" if v.tol else ""
                if args.update:
                    out.append(text[at:m.start(1)] + new)
                    at = m.end(1)
                    updated += 1
                    print(f"   updated {rel}:{line} {name}.{key}: {quoted} -> {new}")
                else:
                    failed += 1
                    print(f"   DIFFERS {rel}:{line} {name}.{key}: quoted {quoted}, printed {printed:.6g} "
                          f"(would be written {new}{tol})")
            if args.update and updated:
                out.append(text[at:])
                with open(doc, "w") as f:
                    f.write("".join(out))
        pictures = args.pictures or (args.full and not (args.list or only or args.docs))
        if pictures:
            failed += check_pictures(build, scratch, args.update)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if args.list:
        return 0
    if args.pictures:
        return 1 if failed or dangling else 0
    print(f"check_docs: {checked} quoted values checked, {failed} differ or failed"
          + (f", {updated} updated" if args.update else "")
          + ("" if args.full or only else " ([full] checks skipped: --full runs them)"))
    return 1 if failed or dangling else 0


if __name__ == "__main__":
    sys.exit(main())
