#!/usr/bin/env python3
"""The signal window before clothsim's launcher runs (docs/outputs.md, "Signals").

  tools/reliability/loader_window.py [BINARY] [TRIALS]

Starts `clothsim validate` TRIALS times per delay, sends SIGTERM that long after exec returned
(Popen returns once the exec has happened), and counts the runs that answered it (exit 143,
"stopped by SIGTERM") and those that met the default action (killed by the signal: the kernel
had not yet run the launcher's first instruction, which blocks the signal). Prints one line
per delay; also prints the load average, which the window follows.
"""
import os
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
BINARY = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "clothsim")
TRIALS = int(sys.argv[2]) if len(sys.argv) > 2 else 20
DELAYS = [0.0, 0.0001, 0.00025, 0.0005, 0.001, 0.002, 0.005, 0.02]


def trial(delay):
    p = subprocess.Popen([BINARY, "validate", os.path.join(ROOT, "scenes", "spring.yaml")],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    start = time.perf_counter()
    while time.perf_counter() - start < delay:
        pass
    p.send_signal(signal.SIGTERM)
    err = p.communicate()[1].decode()
    if p.returncode == 143 and "stopped by SIGTERM" in err:
        return "handled"
    if p.returncode == -signal.SIGTERM:
        return "default"
    return f"other (exit {p.returncode})"


def main():
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores, {TRIALS} trials per delay")
    for delay in DELAYS:
        outcomes = [trial(delay) for _ in range(TRIALS)]
        print(f"{delay * 1000:5.2f} ms after exec: handled {outcomes.count('handled')}/{TRIALS}, "
              f"default action {outcomes.count('default')}/{TRIALS}"
              + "".join(f", {o}" for o in sorted(set(outcomes)) if o.startswith("other")))


if __name__ == "__main__":
    main()
