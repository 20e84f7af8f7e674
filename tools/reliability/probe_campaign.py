#!/usr/bin/env python3
"""Scripted probes of clothsim's reliability contract (issue 35; docs/outputs.md).

  tools/reliability/probe_campaign.py [--binary build/clothsim] [--quick] [--family NAME]...

Families of cases, each case one or a few commands in a fresh folder checked against the
contract:
  clash     an output that is an input or another output under any spelling (the same path,
            ./, ../dir/, absolute, a symlink, a chain of them, a hard link, through a symlinked
            folder, a dangling symlink) is refused before any work: exit 2, one line, every
            input byte for byte as it was, nothing new in the folder
  distinct  outputs that only look alike (devices, other names) are written
  values    hostile values (NaN tolerances, colour ranges past single precision, sheets too
            small, names with control characters, names too long for the file system, plots
            streamed to devices) get one line and the documented exit, never an internal error
  memory    `ulimit -v` and non-regular scene inputs: refused on one line before allocating
  journal   shard items cut short are refused by merge and redone by a rerun; temporaries of
            dead writers are removed by a rerun; SIGKILL at random moments leaves none after it
  stops     SIGINT/SIGTERM while compare plans (pilots, trial runs) and while a FIFO scene
            waits for its writer: answered within 0.5 s with one line and nothing written
  pictures  same command, same bytes (compare --frames, run --frames, a still); a rerun's
            --frames holds no frame of a longer earlier run
Prints each failure, then "N passed, M failed"; exits 1 on any failure. --quick runs every
tenth case of each family (ctest's Reliability.ProbeCampaignQuick).
"""
import argparse
import hashlib
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = os.path.join(ROOT, "scenes")
SPRING = os.path.join(SCENES, "spring.yaml")
DRAPE = os.path.join(SCENES, "drape.yaml")
TINY = ["--width", "64", "--height", "48"]
GRID = ["--width", "320", "--height", "180"]  # compare's 2x2 grid and its colour bar
BINARY = None
WORK = None


class Case:
    def __init__(self, family, name, run):
        self.family, self.name, self.run = family, name, run


def clothsim(args, cwd, timeout=120, preexec=None, stdin=None, stdout_file=None):
    """Runs clothsim in `cwd`; its standard output into `stdout_file` (a file in cwd) if given."""
    out = open(os.path.join(cwd, stdout_file), "wb") if stdout_file else subprocess.PIPE
    try:
        p = subprocess.run([BINARY, *args], cwd=cwd, stdout=out, stderr=subprocess.PIPE, timeout=timeout,
                           preexec_fn=preexec, stdin=stdin if stdin is not None else subprocess.DEVNULL)
    finally:
        if stdout_file:
            out.close()
    return p.returncode, (p.stdout or b"").decode(errors="replace"), p.stderr.decode(errors="replace")


def fresh(tag):
    return tempfile.mkdtemp(prefix=tag + "-", dir=WORK)


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def snapshot(folder):
    """Every name under `folder` with its content's hash (links as their targets)."""
    out = {}
    for dirpath, dirs, names in os.walk(folder):
        for n in names + [d for d in dirs if os.path.islink(os.path.join(dirpath, d))]:
            p = os.path.join(dirpath, n)
            rel = os.path.relpath(p, folder)
            out[rel] = "link:" + os.readlink(p) if os.path.islink(p) else digest(p)
    return out


def one_line(code, err, want_code, needle=None):
    """Problems with a refusal: the exit code, one line on stderr, the words it must hold."""
    problems = []
    if code != want_code:
        problems.append(f"exit {code}, expected {want_code}")
    if err.count("\n") != 1:
        problems.append(f"{err.count(chr(10))} lines on stderr")
    if "internal error" in err or "bad_alloc" in err:
        problems.append("an internal error")
    if needle and needle not in err:
        problems.append(f"no '{needle}'")
    return problems


# ---------------------------------------------------------------- clash

def spelled(folder, name, how):
    """`name` (a file in `folder`, which may not exist yet) under another spelling, made in
    `folder` (the command's working directory)."""
    base = os.path.basename(folder)
    sub, leaf = os.path.split(name)  # links are made beside the file, in its own folder
    beside = lambda made: os.path.join(sub, made)
    if how == "same":
        return name
    if how == "dot":
        return "./" + name
    if how == "parent":
        return f"../{base}/{name}"
    if how == "absolute":
        return os.path.join(folder, name)
    if how == "updown":
        os.makedirs(os.path.join(folder, "sub"), exist_ok=True)
        return f"sub/../{name}"
    if how == "symlink":
        os.symlink(leaf, os.path.join(folder, beside("link-" + leaf)))
        return beside("link-" + leaf)
    if how == "chain":
        os.symlink(leaf, os.path.join(folder, beside("l1-" + leaf)))
        os.symlink("l1-" + leaf, os.path.join(folder, beside("l2-" + leaf)))
        return beside("l2-" + leaf)
    if how == "dirlink":
        if not os.path.lexists(os.path.join(folder, "here")):
            os.symlink(".", os.path.join(folder, "here"))
        return "here/" + name
    if how == "hardlink":
        os.link(os.path.join(folder, name), os.path.join(folder, beside("hard-" + leaf)))
        return beside("hard-" + leaf)
    if how == "abslink":
        os.symlink(os.path.join(folder, name), os.path.join(folder, beside("abs-" + leaf)))
        return beside("abs-" + leaf)
    raise ValueError(how)


SPELLINGS = ["same", "dot", "parent", "absolute", "updown", "symlink", "chain", "dirlink", "hardlink", "abslink"]
# Names not made yet: a hard link needs a file.
NEW_SPELLINGS = ["same", "dot", "parent", "absolute", "updown", "symlink", "chain", "dirlink", "abslink"]


def setup_common(folder):
    shutil.copy(SPRING, os.path.join(folder, "s.yaml"))


def setup_images(folder):
    setup_common(folder)
    code, _, err = clothsim(["run", "s.yaml", "--duration", "0.1", "--still", "0.1", "-o", "a.png", *TINY], folder)
    assert code == 0, err
    shutil.copy(os.path.join(folder, "a.png"), os.path.join(folder, "b.png"))


def setup_frames(folder):
    setup_common(folder)
    code, _, err = clothsim(["run", "s.yaml", "--duration", "0.1", "--frames", "fr", *TINY], folder)
    assert code == 0, err


def setup_manifest(folder):
    setup_common(folder)
    with open(os.path.join(folder, "m.yaml"), "w") as f:
        f.write("goldens:\n  - {scene: s.yaml, times: [0.05], name: g, size: [64, 48]}\n")
    code, _, err = clothsim(["golden", "update", "m.yaml"], folder)
    assert code == 0, err


def setup_shard(folder):
    setup_common(folder)
    code, _, err = clothsim(["stability", "s.yaml", "--integrators", "rk4", "--values", "100", "--duration", "2",
                             "--min-dt", "0.01", "--max-dt", "0.1", "--csv", "p.csv", "--shard", "1/1"], folder)
    assert code == 0, err


STUDY = {
    "bench": ["bench", "s.yaml", "--duration", "0.2"],
    "stability": ["stability", "s.yaml", "--integrators", "rk4", "--values", "100", "--duration", "1"],
    "converge": ["converge", "s.yaml"],
}

# (command, setup, base argv, {output option: argv builder}, [inputs by name])
INPUT_CLASHES = [
    ("run", setup_common, ["run", "s.yaml", "--duration", "0.1"],
     {"--metrics": lambda p: ["--metrics", p], "--state": lambda p: ["--state", p],
      "--summary": lambda p: ["--summary", p], "--video": lambda p: ["--video", p],
      "-o": lambda p: ["--still", "0.1", "-o", p]}, ["s.yaml"]),
    ("compare", setup_common, ["compare", "s.yaml", "--duration", "0.1", *GRID],
     {"--video": lambda p: ["--video", p], "--summary": lambda p: ["--summary", p],
      "-o": lambda p: ["--still", "0.1", "-o", p], "--sheet": lambda p: ["--sheet", p, "--times", "0.1"]},
     ["s.yaml"]),
    *[(study, setup_common, argv, {"--csv": lambda p: ["--csv", p], "--summary": lambda p: ["--summary", p],
                                   "--plot": lambda p: ["--plot", p]}, ["s.yaml"])
      for study, argv in STUDY.items()],
    ("golden", setup_manifest, ["golden", "check", "m.yaml"],
     {"--csv": lambda p: ["--csv", p], "--summary": lambda p: ["--summary", p]},
     ["m.yaml", "s.yaml", "g_t50ms.png"]),
    ("imgdiff", setup_images, ["imgdiff", "a.png", "b.png"], {"-o": lambda p: ["-o", p], "--diff": lambda p: ["--diff", p]},
     ["a.png", "b.png"]),
    ("encode", setup_frames, ["encode", "fr"], {"-o": lambda p: ["-o", p]},
     ["fr/frame_00000.png", "fr/frame_00002.png"]),
    ("merge", setup_shard, ["merge", "p.csv.shard-1-of-1"],
     {"--csv": lambda p: ["--csv", p], "--summary": lambda p: ["--summary", p], "--plot": lambda p: ["--plot", p]},
     ["p.csv.shard-1-of-1/provenance", "p.csv.shard-1-of-1/items/0"]),
]


def input_clash_case(command, setup, base, build, target, how):
    def run():
        folder = fresh(f"clash-{command}")
        setup(folder)
        spelling = spelled(folder, target, how)
        before = snapshot(folder)
        code, _, err = clothsim(base + build(spelling), folder)
        problems = one_line(code, err, 2, "an output never replaces an input")
        after = snapshot(folder)
        if after != before:
            changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
            problems.append(f"the folder changed: {changed[:4]}")
        return problems, err
    return run


def output_pairs(options):
    keys = list(options)
    return [(a, b) for i, a in enumerate(keys) for b in keys[i + 1:]]


def output_clash_case(command, setup, base, options, a, b, how):
    def run():
        folder = fresh(f"pair-{command}")
        setup(folder)
        name = "out.dat"
        if how == "dangling":
            os.symlink(name, os.path.join(folder, "dl-" + name))
            second = "dl-" + name
        else:
            second = spelled(folder, name, how)
        before = snapshot(folder)
        code, _, err = clothsim(base + options[a](name) + options[b](second), folder)
        problems = one_line(code, err, 2, "give each its own path")
        if snapshot(folder) != before:
            problems.append("the folder changed")
        return problems, err
    return run


def frames_clash_case(command, how, still_first):
    """A still inside the --frames folder, under some spelling of it."""
    def run():
        folder = fresh(f"frames-{command}")
        setup_common(folder)
        os.makedirs(os.path.join(folder, "fr"))
        fr = spelled(folder, "fr", how if how != "hardlink" else "same")
        still = ["--still", "0.1", "-o", f"{fr}/frame_00001.png" if command == "run" else f"{fr}/frame_00001.png"]
        frames = ["--frames", "fr"]
        args = [command, "s.yaml", "--duration", "0.1", *GRID, *(still + frames if still_first else frames + still)]
        before = snapshot(folder)
        code, _, err = clothsim(args, folder)
        problems = one_line(code, err, 2, "frame")
        if snapshot(folder) != before:
            problems.append("the folder changed")
        return problems, err
    return run


def clash_cases():
    cases = []
    for command, setup, base, options, inputs in INPUT_CLASHES:
        for target in inputs:
            for option, build in options.items():
                # A hard link to a frame is another name, which encode does not read: writing it
                # replaces that name only, so it is no clash.
                for how in [h for h in SPELLINGS if not (command == "encode" and h == "hardlink")]:
                    cases.append(Case("clash", f"{command} {option} onto {target} ({how})",
                                      input_clash_case(command, setup, base, build, target, how)))
        for a, b in output_pairs(options) if command != "imgdiff" else []:  # -o and --diff: one option
            for how in NEW_SPELLINGS + ["dangling"]:
                cases.append(Case("clash", f"{command} {a} and {b} at one file ({how})",
                                  output_clash_case(command, setup, base, options, a, b, how)))
    for command in ["run", "compare"]:
        for how in ["same", "dot", "parent", "absolute", "updown", "symlink", "dirlink"]:
            for still_first in [False, True]:
                cases.append(Case("clash", f"{command} --still inside --frames ({how}, {'still' if still_first else 'frames'} first)",
                                  frames_clash_case(command, how, still_first)))
    return cases


# ---------------------------------------------------------------- distinct

def distinct_case(args, expect_files, stdout_file=None):
    def run():
        folder = fresh("distinct")
        setup_common(folder)
        code, _, err = clothsim(args, folder, stdout_file=stdout_file)
        problems = [] if code == 0 else [f"exit {code}"]
        for f in expect_files:
            if not os.path.isfile(os.path.join(folder, f)):
                problems.append(f"{f} not written")
        if digest(os.path.join(folder, "s.yaml")) != digest(SPRING):
            problems.append("the scene changed")
        return problems, err
    return run


def distinct_cases():
    run = ["run", "s.yaml", "--duration", "0.1"]
    cases = [
        Case("distinct", "run with every output at /dev/null",
             distinct_case(run + ["--metrics", "/dev/null", "--state", "/dev/null", "--summary", "/dev/null"], [])),
        Case("distinct", "run with outputs named like the scene but not it",
             distinct_case(run + ["--metrics", "s.yaml.csv", "--state", "s.csv", "--summary", "s.json"],
                           ["s.yaml.csv", "s.csv", "s.json"])),
        Case("distinct", "run --frames beside the scene", distinct_case(run + ["--frames", "."] + TINY, ["frame_00000.png"])),
        Case("distinct", "bench --plot /dev/null", distinct_case(STUDY["bench"] + ["--plot", "/dev/null"], [])),
        Case("distinct", "stability --plot /dev/null", distinct_case(STUDY["stability"] + ["--plot", "/dev/null"], [])),
        # (Into a file: a plot script cannot yet write its PNG into a pipe.)
        *[Case("distinct", f"{study} --plot /dev/stdout into a file",
               distinct_case(argv + ["--plot", "/dev/stdout"], ["out.png"], stdout_file="out.png"))
          for study, argv in STUDY.items()],
        Case("distinct", "converge --plot /dev/null --csv c.csv",
             distinct_case(STUDY["converge"] + ["--plot", "/dev/null", "--csv", "c.csv"], ["c.csv"])),
    ]
    for study, argv in STUDY.items():
        cases.append(Case("distinct", f"{study} --csv and --summary beside the scene",
                          distinct_case(argv + ["--csv", "x.csv", "--summary", "x.json"], ["x.csv", "x.json"])))
    return cases


# ---------------------------------------------------------------- values

def refusal_case(args, want_code, needle, setup=setup_common, allowed=None):
    def run():
        folder = fresh("values")
        setup(folder)
        before = snapshot(folder)
        code, _, err = clothsim(args, folder)
        problems = one_line(code, err, want_code, needle)
        after = snapshot(folder)
        extra = sorted(set(after) - set(before) - set(allowed or []))
        if extra:
            problems.append(f"written: {extra[:4]}")
        return problems, err
    return run


def values_cases():
    cases = []
    img = ["imgdiff", "a.png", "b.png"]
    for option in ["--max-rms", "--max-over"]:
        for v in ["nan", "NaN", "-nan", "inf", "-1", "1e400"]:
            cases.append(Case("values", f"imgdiff {option} {v}", refusal_case(img + [option, v], 2, option, setup_images)))
    still = ["run", "s.yaml", "--duration", "0.1", "--color", "speed", "--still", "0.1", "-o", "x.png", *TINY]
    for r in ["1e-300,1e300", "1e-10,1e300", "1,1.0000000000000002", "1e-40,1", "1,1e31", "4.9e-324,1",
              "1e-320,1e-319", "0,1", "-1,1", "2,1", "1,1", "nan,1", "1,inf", "1e-308,2e-308", "1,1.00001"]:
        cases.append(Case("values", f"--color-range {r}", refusal_case(still + ["--color-range", r], 2, "--color-range")))
    sheet = ["compare", "s.yaml", "--duration", "0.1", "--color", "checker", "--sheet", "sh.png"]
    for w, h in [(16, 16), (17, 16), (40, 16), (16, 40), (24, 24), (32, 18)]:
        for times in ["0.1", "0.02,0.04,0.06,0.08,0.1"]:
            cases.append(Case("values", f"--sheet at {w}x{h}, times {times}",
                              refusal_case(sheet + ["--times", times, "--width", str(w), "--height", str(h)], 2,
                                           "--")))
    # Control characters in a scene's name: C0, DEL and C1 refused at the key, one line.
    for c in list(range(1, 32)) + [127] + list(range(0x80, 0xa0)) + list(range(0x202A, 0x202F)) + list(range(0x2066, 0x206A)):
        ch = chr(c)
        name = "a" + ch + "b"
        cases.append(Case("values", f"a scene name holding U+{c:04X}", name_case(name)))
    for length in [250, 300, 1000]:
        cases.append(Case("values", f"a golden name of {length} bytes", long_golden_name_case(length)))
    return cases


def name_case(name):
    def run():
        folder = fresh("name")
        with open(SPRING) as f:
            text = f.read()
        escaped = name.encode("unicode_escape").decode().replace('"', '\\"')
        escaped = escaped.replace("\\x", "\\x")
        with open(os.path.join(folder, "n.yaml"), "w", encoding="utf-8") as f:
            f.write(text.replace("name:", "# name:", 1) + f'\nname: "{escaped}"\n')
        code, _, err = clothsim(["validate", "n.yaml"], folder)
        return one_line(code, err, 2, "name"), err
    return run


def long_golden_name_case(length):
    def run():
        folder = fresh("longname")
        setup_common(folder)
        with open(os.path.join(folder, "m.yaml"), "w") as f:
            f.write(f"goldens:\n  - {{scene: s.yaml, times: [0.05], name: {'n' * length}, size: [64, 48]}}\n")
        began = time.monotonic()
        code, _, err = clothsim(["golden", "update", "m.yaml"], folder)
        problems = one_line(code, err, 2, "too long")
        if [f for f in os.listdir(folder) if f.endswith(".png")]:
            problems.append("an image was written")
        return problems, err
    return run


# ---------------------------------------------------------------- memory

def limited(kbytes):
    import resource
    def set_limit():
        resource.setrlimit(resource.RLIMIT_AS, (kbytes * 1024, kbytes * 1024))
    return set_limit


def ulimit_case(args, kbytes):
    def run():
        folder = fresh("ulimit")
        code, _, err = clothsim(args, folder, preexec=limited(kbytes))
        problems = []
        if code not in (0, 1, 2):
            problems.append(f"exit {code}")
        if code != 0 and err.count("\n") != 1:
            problems.append(f"{err.count(chr(10))} lines")
        if "internal error" in err or "std::bad_alloc" in err or "terminate" in err:
            problems.append("an internal error")
        if code == 1 and "out of memory" not in err and "ulimit -v" not in err:
            problems.append("a failure that is not the out-of-memory line")
        return problems, err
    return run


def stream_case(source, limit, command):
    def run():
        folder = fresh("stream")
        args = [command, source, "--max-memory", limit] + (["--duration", "0.01"] if command == "run" else [])
        began = time.monotonic()
        code, _, err = clothsim(args, folder, timeout=60)
        problems = one_line(code, err, 2, "read from this stream")
        return problems, err
    return run


def memory_cases():
    cases = []
    for kb in [500000, 800000, 1200000, 1600000, 2400000]:  # below ~350 MB the loader cannot map the libraries
        for n in [64, 512, 1024, 2048]:
            cases.append(Case("memory", f"validate {n}x{n} under ulimit -v {kb}",
                              ulimit_case(["validate", DRAPE, "--set", f"cloth.particles=[{n},{n}]"], kb)))
            cases.append(Case("memory", f"run {n}x{n} under ulimit -v {kb}",
                              ulimit_case(["run", DRAPE, "--set", f"cloth.particles=[{n},{n}]", "--duration", "2e-4",
                                           "--dt", "1e-4", "--metrics", "/dev/null"], kb)))
    for source in ["/dev/zero", "/dev/urandom"]:
        for limit in ["100M", "500M"]:
            for command in ["validate", "run"]:
                cases.append(Case("memory", f"{command} {source} --max-memory {limit}", stream_case(source, limit, command)))
    return cases


# ---------------------------------------------------------------- journal

def cut_item_case(cut_fraction, which):
    def run():
        folder = fresh("cut")
        setup_shard(folder)
        shard = os.path.join(folder, "p.csv.shard-1-of-1")
        item = os.path.join(shard, which, sorted(os.listdir(os.path.join(shard, which)))[0])
        size = os.path.getsize(item)
        cut = max(0, min(size - 1, int(size * cut_fraction)))
        with open(item, "r+b") as f:
            f.truncate(cut)
        code, _, err = clothsim(["merge", "p.csv.shard-1-of-1", "--csv", "m.csv"], folder)
        problems = one_line(code, err, 1, ": damaged")
        if os.path.exists(os.path.join(folder, "m.csv")):
            problems.append("m.csv written")
        return problems, err
    return run


def dead_pid():
    p = subprocess.Popen(["true"])
    p.wait()
    return p.pid


def stale_temporaries_case(folder_name):
    def run():
        folder = fresh("stale")
        setup_shard(folder)
        shard = os.path.join(folder, "p.csv.shard-1-of-1")
        temp = os.path.join(shard, folder_name, f".7.tmp-{dead_pid()}-{random.randrange(1 << 24)}")
        with open(temp, "w") as f:
            f.write("half a ro")
        code, _, err = clothsim(["stability", "s.yaml", "--integrators", "rk4", "--values", "100", "--duration", "2",
                                 "--min-dt", "0.01", "--max-dt", "0.1", "--csv", "p.csv", "--shard", "1/1"], folder)
        problems = [] if code == 0 else [f"exit {code}"]
        if os.path.exists(temp):
            problems.append("the dead writer's temporary stays")
        return problems, err
    return run


def killed_shard_case(seed):
    def run():
        rng = random.Random(seed)
        folder = fresh("killed")
        setup_common(folder)
        args = [BINARY, "stability", "s.yaml", "--integrators", "symplectic_euler,rk4", "--values", "100,200,400,800",
                "--duration", "5", "--min-dt", "0.001", "--max-dt", "0.1", "--csv", "p.csv", "--shard", "1/1",
                "--jobs", "1"]
        p = subprocess.Popen(args, cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.05, 0.6))
        p.kill()
        p.wait()
        code, _, err = clothsim(args[1:], folder)
        problems = [] if code == 0 else [f"rerun exit {code}"]
        shard = os.path.join(folder, "p.csv.shard-1-of-1")
        for sub in ["", "items", "lanes"]:
            d = os.path.join(shard, sub)
            if os.path.isdir(d):
                hidden = [n for n in os.listdir(d) if n.startswith(".")]
                if hidden:
                    problems.append(f"left in {sub or '.'}: {hidden}")
        code, _, merr = clothsim(["merge", "p.csv.shard-1-of-1", "--csv", "m.csv"], folder)
        if code != 0:
            problems.append(f"merge exit {code}: {merr.strip()}")
        return problems, err
    return run


def journal_cases():
    cases = []
    for which in ["items"]:
        for k in range(80):
            cases.append(Case("journal", f"merge of an item cut at {k / 80:.4f} of its length", cut_item_case(k / 80, which)))
    for sub in ["items", "lanes", ""]:
        for _ in range(5):
            cases.append(Case("journal", f"a rerun removes a dead writer's temporary in {sub or 'the shard'}",
                              stale_temporaries_case(sub)))
    for seed in range(20):
        cases.append(Case("journal", f"SIGKILL at a random moment (seed {seed}), then a rerun", killed_shard_case(seed)))
    return cases


# ---------------------------------------------------------------- stops

def stop_case(args, delay, sig, needle="stopped by", setup=setup_common, limit=0.5):
    def run():
        folder = fresh("stop")
        setup(folder)
        p = subprocess.Popen([BINARY, *args], cwd=folder, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        time.sleep(delay)
        sent = time.monotonic()
        p.send_signal(sig)
        err = p.communicate(timeout=60)[1].decode(errors="replace")
        took = time.monotonic() - sent
        problems = one_line(p.returncode, err, 128 + sig, needle)
        if took > limit:
            problems.append(f"answered after {took:.2f} s")
        outputs = [f for f in os.listdir(folder) if f not in ("s.yaml", "ff")]
        if outputs:
            problems.append(f"written: {outputs}")
        return problems, err + f"(after {took:.3f} s)"
    return run


def fifo_setup(folder):
    setup_common(folder)
    os.mkfifo(os.path.join(folder, "ff"))


def stops_cases():
    cases = []
    rng = random.Random(35)
    pilots = ["compare", DRAPE, "--set", "cloth.particles=[80,80]", "--still", "0.5", "-o", "x.png"]
    trials = ["compare", DRAPE, "--set", "cloth.particles=[40,40]", "--match", "error", "1e-3", "--still", "0.5",
              "-o", "x.png"]
    for sig in [signal.SIGINT, signal.SIGTERM]:
        for k in range(6):
            cases.append(Case("stops", f"compare --match cost pilots, {sig.name} ({k})",
                              stop_case(pilots, rng.uniform(0.3, 4.0), sig)))
            cases.append(Case("stops", f"compare --match error trials, {sig.name} ({k})",
                              stop_case(trials, rng.uniform(0.3, 3.0), sig)))
    for sig in [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]:
        for command in [["validate", "ff"], ["run", "ff", "--metrics", "m.csv"], ["bench", "ff", "--csv", "b.csv"]]:
            cases.append(Case("stops", f"{command[0]} of a FIFO with no writer, {sig.name}",
                              stop_case(command, 0.3, sig, "stopped by " + sig.name, fifo_setup)))
    return cases


# ---------------------------------------------------------------- pictures

def twice_case(args, outputs):
    def run():
        digests = []
        for _ in range(2):
            folder = fresh("twice")
            setup_common(folder)
            code, _, err = clothsim(args, folder)
            if code != 0:
                return [f"exit {code}"], err
            digests.append({k: v for k, v in snapshot(folder).items() if k.startswith(outputs)})
        problems = []
        if not digests[0]:
            problems.append("nothing written")
        if digests[0] != digests[1]:
            differ = [k for k in digests[0] if digests[0].get(k) != digests[1].get(k)]
            problems.append(f"{len(differ)} files differ: {differ[:3]}")
        return problems, ""
    return run


def rerun_frames_case(first, second, command):
    def run():
        folder = fresh("rerun")
        setup_common(folder)
        args = [command, "s.yaml", *(TINY if command == "run" else GRID), "--frames", "fr"]
        for duration in (first, second):
            code, _, err = clothsim(args + ["--duration", str(duration)], folder)
            if code != 0:
                return [f"exit {code}"], err
        frames = []
        for dirpath, _, names in os.walk(os.path.join(folder, "fr")):
            frames += [n for n in names if n.startswith("frame_")]
        fps = 30 if command == "run" else 30
        expected = int(round(second * fps)) + 1
        lanes = 1 if command == "run" else 4
        problems = [] if len(frames) == expected * lanes else [f"{len(frames)} frames, expected {expected * lanes}"]
        return problems, ""
    return run


def pictures_cases():
    cases = [
        Case("pictures", "compare --frames twice, same bytes",
             twice_case(["compare", "s.yaml", "--duration", "0.2", *GRID, "--frames", "f"], "f")),
        Case("pictures", "compare --frames --color error twice, same bytes",
             twice_case(["compare", DRAPE, "--set", "cloth.particles=[9,9]", "--duration", "0.2", *GRID, "--frames", "f"], "f")),
        Case("pictures", "compare --still twice, same bytes",
             twice_case(["compare", "s.yaml", "--duration", "0.2", *GRID, "--still", "0.2", "-o", "x.png"], "x.png")),
        Case("pictures", "run --frames twice, same bytes",
             twice_case(["run", "s.yaml", "--duration", "0.2", *TINY, "--frames", "f"], "f")),
    ]
    for first, second in [(0.5, 0.2), (1.0, 0.1), (0.3, 0.3), (0.1, 0.3)]:
        for command in ["run", "compare"]:
            cases.append(Case("pictures", f"{command} --frames for {first} s then {second} s holds only the second's",
                              rerun_frames_case(first, second, command)))
    return cases


FAMILIES = {
    "clash": clash_cases, "distinct": distinct_cases, "values": values_cases, "memory": memory_cases,
    "journal": journal_cases, "stops": stops_cases, "pictures": pictures_cases,
}


def main():
    global BINARY, WORK
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "clothsim"))
    parser.add_argument("--quick", action="store_true", help="every tenth case of each family")
    parser.add_argument("--family", action="append", choices=sorted(FAMILIES))
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    BINARY = os.path.abspath(args.binary)
    cases = []
    for family in args.family or list(FAMILIES):
        found = FAMILIES[family]()
        cases += found[::10] if args.quick else found
    if args.list:
        for c in cases:
            print(f"{c.family}: {c.name}")
        print(f"{len(cases)} cases")
        return 0
    WORK = tempfile.mkdtemp(prefix="clothsim-probe-")
    passed = failed = 0
    counts = {}
    try:
        for c in cases:
            try:
                problems, err = c.run()
            except Exception as e:  # a case that cannot even be set up is a failure too
                problems, err = [f"{type(e).__name__}: {e}"], ""
            ok = not problems
            passed += ok
            failed += not ok
            counts.setdefault(c.family, [0, 0])[0 if ok else 1] += 1
            if not ok:
                print(f"FAIL {c.family}: {c.name}: {'; '.join(problems)} | {err.strip()[:300]}", flush=True)
    finally:
        shutil.rmtree(WORK, ignore_errors=True)
    for family, (p, f) in counts.items():
        print(f"{family}: {p} passed, {f} failed")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
