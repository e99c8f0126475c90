#!/usr/bin/env python3
"""Time ger against LinuxCNC's rs274 on the same input (issues 3 and 4).

  benches/vs_rs274.py [--ger target/release/ger] [--runs 3]

1. loop:  a 200,000-iteration loop, one move with two trig calls per pass
          (ger `while` vs rs274 `o100 while`).
2. plain: a generated 200,000-move plain program (lines and arcs):
          ger compile vs rs274 -g vs `awk '{print}'`; ger's peak memory.

Prints each time (best of --runs), the ratios and the goals. Times are wall
clock on this machine; run on an idle machine.
"""
import argparse, os, resource, subprocess, sys, tempfile, time

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


def best(cmd, runs, cwd=None):
    """Best wall time of `runs` runs, and the largest peak RSS (KiB)."""
    times = []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        t = time.perf_counter()
        r = subprocess.run(cmd, cwd=cwd, stdin=subprocess.DEVNULL,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        times.append(time.perf_counter() - t)
        if r.returncode != 0:
            sys.exit("failed: %s\n%s" % (" ".join(cmd), r.stderr.decode()[-2000:]))
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return min(times), peak


def rs274_cmd(work, prog):
    var, tbl = os.path.join(work, "r.var"), os.path.join(work, "r.tbl")
    open(var, "w").close()
    with open(tbl, "w") as f:
        f.write("T1 P1 D0 Z0\n")
    return ["rs274", "-g", "-v", var, "-t", tbl, prog]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ger", default="target/release/ger")
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    ger = os.path.abspath(a.ger)
    with tempfile.TemporaryDirectory() as work:
        def write(name, text):
            p = os.path.join(work, name)
            with open(p, "w") as f:
                f.write(text)
            return p

        egc, ngc = write("loop.egc", LOOP_EGC), write("loop.ngc", LOOP_NGC)
        out = os.path.join(work, "out.nc")
        tg, _ = best([ger, "compile", egc, "-o", out], a.runs)
        tr, _ = best(rs274_cmd(work, ngc), a.runs, cwd=work)
        print("loop  200k iterations: ger %.3f s, rs274 %.3f s, ratio %.1fx (goal >= 25x)"
              % (tg, tr, tr / tg))

        plain = write("plain.ngc", plain_program(200_000))
        tg, peak = best([ger, "compile", plain, "-o", out], a.runs)
        tr, _ = best(rs274_cmd(work, plain), a.runs, cwd=work)
        ta, _ = best(["awk", "{print}", plain], a.runs)
        print("plain 200k moves: ger %.3f s, rs274 %.3f s, awk %.3f s" % (tg, tr, ta))
        print("  ger vs rs274 %.1fx faster (goal >= 25x); ger / awk %.2f (goal <= 4)"
              % (tr / tg, tg / ta))
        print("  peak memory of the largest child so far: %.1f MB (ger's run is the "
              "first measured after the loop; goal <= 200 MB)" % (peak / 1024))
        # Peak of ger alone, measured in a fresh process tree.
        r = subprocess.run([sys.executable, "-c",
                            "import resource,subprocess,sys;"
                            "subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL);"
                            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)",
                            ger, "compile", plain, "-o", out],
                           capture_output=True, text=True)
        print("  ger peak memory: %.1f MB" % (int(r.stdout.strip()) / 1024))


if __name__ == "__main__":
    main()
