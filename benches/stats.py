#!/usr/bin/env python3
"""What the planner adds to a compile (issue 45): the 200,000-move plain
program of vs_rs274.py compiled (`ger compile`) and planned (`ger stats`
on a grbl and on a LinuxCNC `[machine]`), each the median of --runs runs,
with the peak memory of each.

  benches/stats.py [--ger target/release/ger] [--runs 5] [--moves 200000]

`ger stats` builds the tool path and plans it; `ger compile` prints the
program. The goal: stats within 20 % of compile. Wall clock on this
machine; run on an idle machine.
"""
import argparse, os, resource, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from vs_rs274 import plain_program  # noqa: E402

MACHINE = """[machine]
controller = "{controller}"
units = "mm"
[machine.x]
max-velocity = 5000
max-acceleration = 250
[machine.y]
max-velocity = 5000
max-acceleration = 250
[machine.z]
max-velocity = 1000
max-acceleration = 100
"""


def run(cmd, cwd):
    """Wall time and the peak memory (KiB) of one run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t = time.perf_counter()
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, max(peak, before)


def median(values):
    values = sorted(values)
    return values[len(values) // 2]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ger", default="target/release/ger")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--moves", type=int, default=200_000)
    a = ap.parse_args()
    ger = os.path.abspath(a.ger)
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "plain.nc"), "w") as f:
            f.write(plain_program(a.moves))
        cases = [("compile", "grbl"), ("stats", "grbl"), ("stats", "linuxcnc")]
        times = {c: [] for c in cases}
        # In turn, so a machine that slows down weighs on each alike.
        for _ in range(a.runs):
            for command, controller in cases:
                with open(os.path.join(d, "ger.toml"), "w") as f:
                    f.write(MACHINE.format(controller=controller))
                times[(command, controller)].append(run([ger, command, "plain.nc"], d)[0])
        # Peak memory: one run each in a fresh child (ru_maxrss of the
        # children only grows, so each is measured in its own process).
        peaks = {}
        for command, controller in cases:
            with open(os.path.join(d, "ger.toml"), "w") as f:
                f.write(MACHINE.format(controller=controller))
            probe = (
                "import resource,subprocess,sys;"
                "subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL,check=True);"
                "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
            )
            out = subprocess.run(
                [sys.executable, "-c", probe, ger, command, "plain.nc"],
                cwd=d, check=True, capture_output=True, text=True,
            )
            peaks[(command, controller)] = int(out.stdout.strip())
    base = median(times[("compile", "grbl")])
    print(f"{time.strftime('%Y-%m-%d')}, {a.moves} moves, median of {a.runs}:")
    for case in cases:
        t = median(times[case])
        print(
            f"  ger {case[0]:8} ({case[1]:8}) {t:7.3f} s  {100 * (t / base - 1):+6.1f} %"
            f"  peak {peaks[case] / 1024:7.1f} MiB"
        )


if __name__ == "__main__":
    main()
