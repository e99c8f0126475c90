#!/usr/bin/env python3
"""Time ger against LinuxCNC's rs274 and awk on the same inputs (issue 15).

  benches/vs_rs274.py [--ger target/release/ger] [--runs 5]

Side by side in one run, each figure the median of --runs runs:
1. loop:  a 200,000-iteration loop, one move with two trig calls per pass
          (ger `while` vs rs274 `o100 while`, in turn);
2. plain: a generated 200,000-move plain program (lines and arcs):
          ger compile vs rs274 -g vs `awk '{print}'`, in turn (3 x --runs);
3. big:   the same kind of program with 2,000,000 moves: ger's time with
          `-o` and to standard output (is it linear in the size?) and its
          peak memory; and the same as `.egc` with a variable (not plain:
          read in parts cut outside blocks).
Prints the figures with the goals, dated, ready for README's table. Times
are wall clock on this machine; run on an idle machine.
"""
import argparse, os, subprocess, sys, tempfile, time

LOOP_EGC = """G21 G90 G17
G0 X0 Y0 Z5
G1 Z-1 F1000
Ii = 0
while (Ii < 200000) {
    G1 X<50 * cos(Ii * 0.01)> Y<50 * sin(Ii * 0.01)>
    Ii = Ii + 1
}
G0 Z5
M30
"""

LOOP_NGC = """G21 G90 G17
G0 X0 Y0 Z5
G1 Z-1 F1000
#<ii> = 0
o100 while [#<ii> LT 200000]
  G1 X[50 * COS[#<ii> * 0.01]] Y[50 * SIN[#<ii> * 0.01]]
  #<ii> = [#<ii> + 1]
o100 endwhile
G0 Z5
M30
"""


def plain_program(moves):
    out = ["G21 G90 G17", "G0 X0 Y0 Z5", "G1 Z-1 F800"]
    x, y = 0.0, 0.0
    for i in range(moves):
        if i % 5 == 4:
            # A half circle to the right, at the same Y.
            out.append("G2 X%.3f Y%.3f I2.5 J0" % (x + 5.0, y))
            x += 5.0
        else:
            x = (x + 0.731) % 400.0
            y = (i % 100) * 0.5
            out.append("G1 X%.3f Y%.3f" % (x, y))
    out.append("M30")
    return "\n".join(out) + "\n"


def median(cmd, runs, cwd=None):
    """Median wall time of `runs` runs."""
    return medians([cmd], runs, cwd)[0]


def medians(cmds, runs, cwd=None):
    """Median wall times of `runs` runs of each command, taken in turn (so
    that a machine that slows down or speeds up meanwhile weighs on each
    alike)."""
    times = [[] for _ in cmds]
    for _ in range(runs):
        for cmd, ts in zip(cmds, times):
            t = time.perf_counter()
            r = subprocess.run(cmd, cwd=cwd, stdin=subprocess.DEVNULL,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            ts.append(time.perf_counter() - t)
            if r.returncode != 0:
                sys.exit("failed: %s\n%s" % (" ".join(cmd), r.stderr.decode()[-2000:]))
    return [sorted(ts)[len(ts) // 2] for ts in times]


def peak_mb(cmd):
    """Peak resident memory of `cmd`, run alone in a fresh process tree."""
    r = subprocess.run([sys.executable, "-c",
                        "import resource,subprocess,sys;"
                        "subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL);"
                        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"]
                       + cmd, capture_output=True, text=True)
    return int(r.stdout.strip()) / 1024


def rs274_cmd(work, prog):
    var, tbl = os.path.join(work, "r.var"), os.path.join(work, "r.tbl")
    open(var, "w").close()
    with open(tbl, "w") as f:
        f.write("T1 P1 D0 Z0\n")
    return ["rs274", "-g", "-v", var, "-t", tbl, prog]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ger", default="target/release/ger")
    ap.add_argument("--runs", type=int, default=5)
    a = ap.parse_args()
    ger = os.path.abspath(a.ger)
    with tempfile.TemporaryDirectory() as work:
        def write(name, text):
            p = os.path.join(work, name)
            with open(p, "w") as f:
                f.write(text)
            return p

        out = os.path.join(work, "out.nc")
        print("%s, medians of %d runs in turn (of %d, for the plain 200k moves)"
              % (time.strftime("%Y-%m-%d"), a.runs, 3 * a.runs))

        egc, ngc = write("loop.egc", LOOP_EGC), write("loop.ngc", LOOP_NGC)
        tg, tr = medians([[ger, "compile", egc, "-o", out], rs274_cmd(work, ngc)],
                         a.runs, cwd=work)
        print("loop  200k iterations: ger %.3f s, rs274 %.3f s: %.1fx (goal >= 25x)"
              % (tg, tr, tr / tg))

        plain = write("plain.ngc", plain_program(200_000))
        # ger with `-o` (the file synced before the rename), and to
        # standard output as awk and rs274 write (held until whole, not
        # synced), in turn with awk and rs274: this machine's speed for
        # short processes changes from one minute to the next, so each
        # ratio is of runs made at the same time.
        tg, ts, ta, tr = medians([[ger, "compile", plain, "-o", out],
                                  [ger, "compile", plain],
                                  ["awk", "{print}", plain],
                                  rs274_cmd(work, plain)], 3 * a.runs, cwd=work)
        print("plain 200k moves: ger %.3f s, rs274 %.3f s: %.1fx (goal >= 25x); "
              "awk %.4f s: ger / awk %.1f (goal <= 4)" % (tg, tr, tr / tg, ta, tg / ta))
        print("  to standard output: ger %.3f s: %.1fx rs274, ger / awk %.1f"
              % (ts, tr / ts, ts / ta))
        # ger / rs274 is ger / awk over rs274 / awk: the second is the
        # machine's (how much it slows short processes against long ones).
        print("  rs274 / awk %.0f: 25x rs274 needs ger / awk <= %.1f" % (tr / ta, tr / ta / 25))
        print("  ger peak memory: %.1f MB" % peak_mb([ger, "compile", plain, "-o", out]))

        big = write("big.ngc", plain_program(2_000_000))
        # With `-o` and to standard output in turn: the first waits for
        # the disk (52 MB synced), the second shows the compile alone.
        tb, tbs = medians([[ger, "compile", big, "-o", out], [ger, "compile", big]],
                          a.runs, cwd=work)
        print("plain 2M moves: ger %.3f s (%.1fx the 200k time for 10x the moves); "
              "peak memory %.1f MB (goal <= 30 MB)"
              % (tb, tb / tg, peak_mb([ger, "compile", big, "-o", out])))
        print("  to standard output: ger %.3f s (%.1fx the 200k time); peak memory %.1f MB"
              % (tbs, tbs / ts, peak_mb([ger, "compile", big])))
        # A warning (an M code ger passes through): its line is shown, read
        # again from the file.
        warned = write("warned.ngc", plain_program(2_000_000).replace("G1 Z-1 F800", "M100\nG1 Z-1 F800", 1))
        print("  with a warning: peak memory %.1f MB" % peak_mb([ger, "compile", warned, "-o", out]))

        # Not plain: a variable (ger's own language), so read in parts cut
        # outside every block rather than line by line.
        text = plain_program(2_000_000).replace("G1 Z-1 F800", "Id = -1\nG1 Z<Id> F800", 1)
        egc_big = write("big.egc", text)
        te = median([ger, "compile", egc_big, "-o", out], a.runs)
        print("  the same as .egc with a variable: ger %.3f s; peak memory %.1f MB"
              % (te, peak_mb([ger, "compile", egc_big, "-o", out])))


if __name__ == "__main__":
    main()
