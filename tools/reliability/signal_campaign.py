#!/usr/bin/env python3
"""Signals at random moments across clothsim's commands (issue 27's targets).

  tools/reliability/signal_campaign.py [--binary build/clothsim] [--trials 200] [--kills 100]

Each trial starts one command on a small scene in a fresh folder, sends SIGINT, SIGTERM or
SIGHUP at a random moment of its run, and checks the contract (docs/outputs.md): exit
128 + N, exactly one line on stderr saying it stopped, nothing it names as "not written" on
disk, no partial or hidden temporary file, every output left complete, no process left with
the folder as its working directory. Each SIGKILL trial checks the same files and processes.
Prints one line per failure and the counts; exits 1 on any failure. Not part of ctest at
these counts (minutes); tests run it with a few trials.
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENES = os.path.join(ROOT, "scenes")
SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]
SMALL = ["--width", "160", "--height", "120"]

# Each command as the campaign runs it, in a folder of its own (its outputs named there).
COMMANDS = {
    "run": ["run", f"{SCENES}/drape.yaml", "--duration", "0.5", *SMALL, "--frames", "fr", "--video", "v.mp4",
            "--metrics", "m.csv", "--state", "s.csv", "--summary", "s.json"],
    "compare": ["compare", f"{SCENES}/drape.yaml", "--duration", "0.3", *SMALL, "--video", "c.mp4",
                "--summary", "c.json"],
    "bench": ["bench", f"{SCENES}/spring.yaml", "--duration", "0.2", "--csv", "b.csv", "--summary", "b.json",
              "--plot", "b.png"],
    "stability": ["stability", f"{SCENES}/spring.yaml", "--integrators", "symplectic_euler,rk4", "--values", "1e3,1e4",
                  "--csv", "st.csv", "--plot", "st.png"],
    "encode": ["encode", "FRAMES", "-o", "e.mp4", "--preset", "slow"],
    "golden": ["golden", "update", "manifest.yaml"],
}


def prepare(name, folder):
    """What a command reads besides the shipped scenes: encode's frames, golden's manifest."""
    if name == "golden":
        with open(os.path.join(folder, "manifest.yaml"), "w") as f:
            f.write("size: [160, 120]\ngoldens:\n")
            for k, integrator in enumerate(["symplectic_euler", "rk4", "midpoint"]):
                f.write(f"  - {{scene: {SCENES}/drape.yaml, times: [0.05, 0.1], integrator: {integrator}, "
                        f"name: g{k}}}\n")


def argv_for(name, frames):
    return [frames if a == "FRAMES" else a for a in COMMANDS[name]]


def complete(path):
    """Whether a file is whole by its format: PNG to IEND, MP4 boxes to the end with moov, CSV
    ending its last line, JSON that parses."""
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".png"):
        return data.startswith(b"\x89PNG\r\n\x1a\n") and data[-8:-4] == b"IEND"
    if path.endswith(".mp4"):
        at, boxes = 0, set()
        while at + 8 <= len(data):
            size = int.from_bytes(data[at:at + 4], "big")
            boxes.add(data[at + 4:at + 8])
            if size < 8:
                return False
            at += size
        return at == len(data) and b"moov" in boxes
    if path.endswith(".csv"):
        return data.endswith(b"\n")
    if path.endswith(".json"):
        try:
            json.loads(data)
            return True
        except ValueError:
            return False
    return True


def files_under(folder):
    for dirpath, _, names in os.walk(folder):
        for n in names:
            yield os.path.join(dirpath, n)


def leftovers(folder, inputs):
    """Problems with what a command left in `folder`: partial or hidden files, incomplete outputs."""
    problems = []
    for path in files_under(folder):
        rel = os.path.relpath(path, folder)
        if rel in inputs:
            continue
        base = os.path.basename(path)
        if base.startswith(".") or "partial" in base or ".tmp" in base:
            problems.append(f"temporary left: {rel}")
        elif not complete(path):
            problems.append(f"incomplete: {rel}")
    return problems


def survivors(folder):
    """Processes whose working directory is `folder` (the command's children inherit it)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            if os.readlink(f"/proc/{pid}/cwd") == folder:
                with open(f"/proc/{pid}/stat") as f:
                    if f.read().rsplit(")", 1)[1].split()[0] != "Z":
                        found.append(pid)
        except OSError:
            pass
    return found


def no_survivors(folder, wait=2.0):
    deadline = time.monotonic() + wait
    while survivors(folder) and time.monotonic() < deadline:
        time.sleep(0.02)
    return survivors(folder)


def exiting(pid):
    """Whether the process has begun to exit (PF_EXITING in /proc/PID/stat's flags): a signal
    then has no one to answer it, and the trial has missed its moment."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return bool(int(f.read().rsplit(")", 1)[1].split()[6]) & 0x4)
    except (OSError, IndexError, ValueError):
        return True


def start(binary, name, folder, frames):
    return subprocess.Popen([binary, *argv_for(name, frames)], cwd=folder, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, start_new_session=True)


def unsignalled_seconds(binary, name, frames, work):
    """How long the command takes when left alone (the range the random moments cover)."""
    folder = tempfile.mkdtemp(prefix=f"{name}-plain-", dir=work)
    prepare(name, folder)
    began = time.monotonic()
    p = start(binary, name, folder, frames)
    err = p.communicate()[1].decode(errors="replace")
    if p.returncode != 0:
        sys.exit(f"signal_campaign: {name} fails unsignalled (exit {p.returncode}): {err.strip()[:200]}")
    return time.monotonic() - began


def check_signalled(p, sig, folder, inputs):
    err = p.communicate()[1].decode(errors="replace")
    problems = []
    if p.returncode != 128 + sig:
        problems.append(f"exit {p.returncode}, not {128 + sig}")
    # Notes before the signal (compare's colour scale, its step matching) stay; the stop is one
    # line, the last.
    stops = [line for line in err.splitlines() if re.search(r"^clothsim: .*(stopped by SIG|interrupted)", line)]
    if len(stops) != 1 or not err.endswith(stops[0] + "\n"):
        problems.append(f"stderr does not end with one line of the stop: {err.strip()[-200:]!r}")
    said = re.search(r"not written: ([^;]*)", err)
    for name in (said.group(1).split(", ") if said else []):
        if os.path.isfile(os.path.join(folder, name.strip())):
            problems.append(f"said not written, yet on disk: {name}")
    problems += leftovers(folder, inputs)
    if no_survivors(folder):
        problems.append("a child outlived the command")
    return problems


def trial(binary, name, frames, work, seconds, kill, rng):
    folder = os.path.realpath(tempfile.mkdtemp(prefix=f"{name}-", dir=work))
    prepare(name, folder)
    inputs = {os.path.relpath(p, folder) for p in files_under(folder)}
    sig = signal.SIGKILL if kill else rng.choice(SIGNALS)
    p = start(binary, name, folder, frames)
    time.sleep(rng.uniform(0.0, seconds))
    if p.poll() is not None or exiting(p.pid):  # done before the moment came: not a trial of a signal
        p.communicate()
        return None
    p.send_signal(sig)
    if kill:
        p.communicate()
        problems = leftovers(folder, inputs)
        if no_survivors(folder):
            problems.append("a child outlived the command")
    else:
        problems = check_signalled(p, sig, folder, inputs)
    if not problems:
        shutil.rmtree(folder, ignore_errors=True)
    return [f"{name} {signal.Signals(sig).name}: {problem} (in {folder})" for problem in problems]


def campaign(binary, work, count, kill, rng, seconds, frames):
    """`count` trials; returns their failures and how many moments came after the command's end."""
    done, missed, failures = 0, 0, []
    names = list(COMMANDS)
    while done < count:
        name = names[done % len(names)]
        result = trial(binary, name, frames, work, seconds[name], kill, rng)
        if result is None:
            missed += 1
            continue
        done += 1
        failures += result
        for line in result:
            print(line, flush=True)
    return failures, missed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "clothsim"))
    parser.add_argument("--trials", type=int, default=200, help="SIGINT/SIGTERM/SIGHUP trials")
    parser.add_argument("--kills", type=int, default=100, help="SIGKILL trials")
    parser.add_argument("--seed", type=int, default=27)
    parser.add_argument("--keep", action="store_true", help="keep the work folder")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    binary = os.path.realpath(args.binary)
    work = os.path.realpath(tempfile.mkdtemp(prefix="signal_campaign-"))
    frames = os.path.join(work, "frames")
    subprocess.run([binary, "run", f"{SCENES}/drape.yaml", "--duration", "0.5", *SMALL, "--frames", frames],
                   check=True, stdout=subprocess.DEVNULL)
    seconds = {name: unsignalled_seconds(binary, name, frames, work) for name in COMMANDS}
    print("unsignalled: " + ", ".join(f"{n} {s:.2f} s" for n, s in seconds.items()), flush=True)
    lost, missed = campaign(binary, work, args.trials, False, rng, seconds, frames)
    left, missed_kills = campaign(binary, work, args.kills, True, rng, seconds, frames)
    print(f"signals: {args.trials} trials, {len(lost)} failures; SIGKILL: {args.kills} trials, {len(left)} failures "
          f"({missed + missed_kills} moments after a command had ended, not counted)")
    if not args.keep and not lost and not left:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if lost or left else 0


if __name__ == "__main__":
    sys.exit(main())
