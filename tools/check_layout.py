#!/usr/bin/env python3
"""The tree is the stack: checks the include graph of src/, render/ and tools/ against the floors
the tree declares, and prints every breach on one line (exit 1 if there is any).

- The libraries, bottom first, are declared in src/floors.txt: a library may include its own
  headers and those of the libraries on floors below it; never one above, and never a sibling on
  its own floor. An include names its library by its first folder ("core/state.h" is src/core's,
  "render/png_io.h" render's); a name without a folder is a file of the including file's folder.
- A library whose folders are floors of their own declares them in its own floors.txt (today
  src/core, src/clip and render): every file of it is on one floor, and no include runs up one.
- No folder-level include cycle anywhere: folder A including a file of folder B and B one of A is
  a breach, whatever the floors say (a cycle is what floors exist to prevent).
- The registry's promise: at most 3 files outside src/core/integrators name a specific
  IntegratorKind:: (a method is its row and its file).

Sizes are not checked: a file, folder or function is split where its meaning splits.
"""
import collections
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)
SOURCES = (".h", ".cpp")
breaches = []


def say(message):
    breaches.append(message)


def read_floors(path):
    """[(floor name, [entries])], bottom first, from a floors.txt."""
    floors = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].split()
            if line:
                floors.append((line[0], line[1:]))
    return floors


def sources(top):
    for folder, dirs, files in os.walk(os.path.join(ROOT, top)):
        dirs.sort()
        for name in sorted(files):
            if name.endswith(SOURCES):
                yield os.path.relpath(os.path.join(folder, name), ROOT)


def includes(path):
    with open(os.path.join(ROOT, path), errors="replace") as f:
        return INCLUDE.findall(f.read())


# The stack: library name (an include's first folder) -> (floor index, folder).
stack = {}
for index, (floor, folders) in enumerate(read_floors(os.path.join(ROOT, "src/floors.txt"))):
    for folder in folders:
        stack[os.path.basename(folder.rstrip("/"))] = (index, folder.rstrip("/"), floor)


def library_of(path):
    best = None
    for name, (_, folder, _) in stack.items():
        if path.startswith(folder + "/") and (best is None or len(folder) > len(stack[best][1])):
            best = name
    return best


def resolve(path, include):
    """The repository file an include names, or None (a system or third-party header)."""
    local = os.path.normpath(os.path.join(os.path.dirname(path), include))
    if os.path.exists(os.path.join(ROOT, local)):
        return local
    name = include.split("/", 1)[0]
    if "/" in include and name in stack:
        return os.path.normpath(os.path.join(os.path.dirname(stack[name][1]), include))
    return None


files = [f for top in ("src", "render", "tools") for f in sources(top)]
edges = collections.defaultdict(list)  # (from folder, to folder) -> ["file:line -> include"]
for path in files:
    own = library_of(path)
    for include in includes(path):
        target = resolve(path, include)
        if target is None:
            if "/" not in include:
                say(f'{path} includes "{include}", which is not in its folder: name its library')
            continue
        lib = library_of(target)
        if own is None or lib is None:
            continue
        if lib != own:
            mine, theirs = stack[own][0], stack[lib][0]
            if theirs > mine:
                say(f'{path} ({own}) includes "{include}" ({lib}, floor {stack[lib][2]}): an include runs up the stack')
            elif theirs == mine:
                say(f'{path} ({own}) includes "{include}": {lib} is its sibling on floor {stack[lib][2]}')
        if os.path.dirname(target) != os.path.dirname(path):
            edges[(os.path.dirname(path), os.path.dirname(target))].append(f"{path} -> {include}")

for path in files:
    if library_of(path) is None and not path.startswith("tools/"):
        say(f"{path} is in no library of src/floors.txt")

# The floors inside a library.
for name, (_, folder, _) in sorted(stack.items()):
    floors_txt = os.path.join(ROOT, folder, "floors.txt")
    if not os.path.exists(floors_txt):
        continue
    entries = {}
    floor_names = []
    for index, (floor, items) in enumerate(read_floors(floors_txt)):
        floor_names.append(floor)
        for item in items:
            entries[item] = index

    def floor_of(rel):
        folders = [e for e in entries if e.endswith("/") and rel.startswith(e)]
        if folders:
            return entries[max(folders, key=len)]
        stem = re.sub(r"(-inl\.h|\.h|\.cpp)$", "", rel)
        return entries.get(stem)

    for path in (f for f in files if f.startswith(folder + "/")):
        rel = os.path.relpath(path, folder)
        own = floor_of(rel)
        if own is None:
            say(f"{path} is on no floor of {folder}/floors.txt")
            continue
        for include in includes(path):
            target = resolve(path, include)
            if target is None or not target.startswith(folder + "/"):
                continue
            to = floor_of(os.path.relpath(target, folder))
            if to is not None and to > own:
                say(f'{path} (floor {floor_names[own]}) includes "{include}" (floor {floor_names[to]}): an include runs up a floor')

# Folder-level cycles: strongly connected components of the folder graph (Tarjan).
graph = collections.defaultdict(set)
for a, b in edges:
    graph[a].add(b)
index_of, low, on_stack, trail, counter = {}, {}, set(), [], [0]


def connect(v):
    index_of[v] = low[v] = counter[0]
    counter[0] += 1
    trail.append(v)
    on_stack.add(v)
    for w in sorted(graph[v]):
        if w not in index_of:
            connect(w)
            low[v] = min(low[v], low[w])
        elif w in on_stack:
            low[v] = min(low[v], index_of[w])
    if low[v] == index_of[v]:
        component = []
        while True:
            w = trail.pop()
            on_stack.discard(w)
            component.append(w)
            if w == v:
                break
        if len(component) > 1:
            links = [f"{a} -> {b} ({len(edges[(a, b)])}: {edges[(a, b)][0]})"
                     for a, b in sorted(edges) if a in component and b in component]
            say("folder-level include cycle: " + "; ".join(links))


sys.setrecursionlimit(10000)
for v in sorted(list(graph)):
    if v not in index_of:
        connect(v)

# The registry's promise.
named = sorted(f for f in files if not f.startswith("src/core/integrators/")
               and re.search(r"IntegratorKind::", open(os.path.join(ROOT, f), errors="replace").read()))
if len(named) > 3:
    say(f"{len(named)} files outside src/core/integrators name a specific IntegratorKind:: (at most 3): {' '.join(named)}")

for b in breaches:
    print("layout: " + b)
sys.exit(1 if breaches else 0)
