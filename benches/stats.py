#!/usr/bin/env python3
"""What the planner adds to a compile (issue 45): the 200,000-move plain
program of vs_rs274.py compiled (`ger compile`) and planned (`ger stats`
on a grbl and on a LinuxCNC `[machine]`), each the median of --runs runs,
with the peak memory of each.

  benches/stats.py [--ger target/release/ger] [--runs 5] [--moves 200000]
                   [--before OTHER_GER]

`ger stats` plans the moves as the back end makes them (grbl's model with
and without the machine's steps per mm, LinuxCNC's); `ger compile`
prints the program. The goal: stats within 20 % of compile. Wall clock
and CPU time (user + system, both threads): on a machine shared with
other work the CPU time is the steadier. `--before`: the same cases with
another binary too, in the same run.
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


def machine(controller):
    """The `[machine]` table of `controller`; `grbl+steps`: grbl with its
    steps per mm, as `ger machine import` writes from `$100`–`$102`."""
    if controller != "grbl+steps":
        return MACHINE.format(controller=controller)
    toml = MACHINE.format(controller="grbl")
    toml = toml.replace("max-velocity = 5000", "steps-per-mm = 250\nmax-velocity = 5000")
    return toml.replace("max-velocity = 1000", "steps-per-mm = 400\nmax-velocity = 1000")


def cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd, cwd):
    """Wall time and CPU time of one run."""
    c, t = cpu(), time.perf_counter()
    subprocess.run(cmd, cwd=cwd, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t, cpu() - c


def median(values):
    values = sorted(values)
    return values[len(values) // 2]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ger", default="target/release/ger")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--moves", type=int, default=200_000)
    ap.add_argument("--before", help="another ger binary, measured alike")
    a = ap.parse_args()
    gers = [("", os.path.abspath(a.ger))]
    if a.before:
        gers.insert(0, ("before ", os.path.abspath(a.before)))
    with tempfile.TemporaryDirectory() as d:
        with open(os.path.join(d, "plain.nc"), "w") as f:
            f.write(plain_program(a.moves))
        cases = [
            (label, ger, command, controller)
            for label, ger in gers
            for command, controller in [
                ("compile", "grbl"),
                ("stats", "grbl"),
                ("stats", "grbl+steps"),
                ("stats", "linuxcnc"),
            ]
        ]
        times = {c: [] for c in cases}
        # In turn, so a machine that slows down weighs on each alike.
        for _ in range(a.runs):
            for case in cases:
                _, ger, command, controller = case
                with open(os.path.join(d, "ger.toml"), "w") as f:
                    f.write(machine(controller))
                times[case].append(run([ger, command, "plain.nc"], d))
        # Peak memory: one run each in a fresh child (ru_maxrss of the
        # children only grows, so each is measured in its own process).
        peaks = {}
        for case in cases:
            _, ger, command, controller = case
            with open(os.path.join(d, "ger.toml"), "w") as f:
                f.write(machine(controller))
            probe = (
                "import resource,subprocess,sys;"
                "subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL,check=True);"
                "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
            )
            out = subprocess.run(
                [sys.executable, "-c", probe, ger, command, "plain.nc"],
                cwd=d, check=True, capture_output=True, text=True,
            )
            peaks[case] = int(out.stdout.strip())
    print(f"{time.strftime('%Y-%m-%d')}, {a.moves} moves, median of {a.runs} (wall, CPU;"
          " 'round': the median and quartiles of each run's wall time over the"
          " compile's of the same round, steadier where the machine's speed drifts):")
    for case in cases:
        label, _, command, controller = case
        wall = median([w for w, _ in times[case]])
        cpu_s = median([c for _, c in times[case]])
        base = [c for c in cases if c[0] == label and c[2] == "compile"][0]
        base_cpu = median([c for _, c in times[base]])
        base_wall = median([w for w, _ in times[base]])
        rounds = sorted(w / b for (w, _), (b, _) in zip(times[case], times[base]))
        quarter = lambda f: 100 * (rounds[int(f * (len(rounds) - 1))] - 1)  # noqa: E731
        print(
            f"  {label}ger {command:8} ({controller:10}) {wall:7.3f} s"
            f" {100 * (wall / base_wall - 1):+6.1f} %  CPU {cpu_s:7.3f} s"
            f" {100 * (cpu_s / base_cpu - 1):+6.1f} %  round {quarter(0.5):+6.1f} %"
            f" ({quarter(0.25):+.1f} … {quarter(0.75):+.1f})"
            f"  peak {peaks[case] / 1024:7.1f} MiB"
        )


if __name__ == "__main__":
    main()
