#!/usr/bin/env python3
"""Time `ger render` on the cases of issue 14 (wall time, parsing and
writing the PNG included; best of --runs, peak memory of the largest run).

  benches/render.py [--ger target/release/ger] [--runs 3]

1. inch:   Ger's own case: 1/4" flat end mill, 0.001" cells, a 2" x 2"
           zigzag pocket in 10 depth passes: ms per inch of tool travel
           (goal <= 0.25 ms; the seed took 250 ms).
2. pocket: a 100 x 60 mm, 6 mm deep concentric pocket, 6 mm end mill,
           0.025 mm cells (goal <= 150 ms).
3. moves:  a 200,000-move file: 0.1 mm lines over a 100 x 50 mm plate,
           each bent a little (no two in line, as CAM writes them)
           (goal <= 0.5 s).
4. ball:   a 50 x 50 mm ball-nose surface raster, 6 mm ball, 0.5 mm
           stepover and 0.5 mm segments (goal <= 1 s).
5. memory: a 6" square at 0.001" (36 million cells): peak memory
           (goal <= 200 MB).
"""
import argparse, math, os, subprocess, sys, tempfile, time


def inch_case():
    out = ["G20 G90 G17", "SetTool 1 0.25", "T1 M6", "G0 X0 Y0 Z0.1", "F40"]
    travel, pos = 0.0, (0.0, 0.0, 0.1)

    def move(code, x, y, z):
        nonlocal travel, pos
        travel += math.dist(pos, (x, y, z))
        pos = (x, y, z)
        out.append("%s X%.4f Y%.4f Z%.4f" % (code, x, y, z))

    for layer in range(1, 11):
        z = -0.02 * layer
        move("G0", 0.0, 0.0, 0.1)
        move("G1", 0.0, 0.0, z)
        y, forward = 0.0, True
        while y <= 2.0 + 1e-9:
            move("G1", 2.0 if forward else 0.0, y, z)
            y += 0.1
            forward = not forward
            if y <= 2.0 + 1e-9:
                move("G1", pos[0], y, z)
    move("G0", pos[0], pos[1], 0.5)
    out.append("M30")
    return "\n".join(out) + "\n", travel


def pocket_case():
    out = ["G21 G90 G17", "SetPart 110 70 10", "SetZero 5 5 0", "SetTool 1 6",
           "T1 M6", "G0 X50 Y30 Z2", "F600"]
    for depth in (1, 2, 3, 4, 5, 6):
        out.append("G0 X50 Y30 Z2")
        out.append("G1 Z-%d" % depth)
        k = 0
        while True:
            dx, dy = 3 + 2.5 * k, 3 + 2.5 * k
            if 50 - dx < 3:
                break
            dy = min(dy, 27)
            out.append("G1 X%.3f Y%.3f" % (50 - dx, 30 - dy))
            out.append("G1 X%.3f" % (50 + dx))
            out.append("G1 Y%.3f" % (30 + dy))
            out.append("G1 X%.3f" % (50 - dx))
            out.append("G1 Y%.3f" % (30 - dy))
            k += 1
    out.append("G0 Z5")
    out.append("M30")
    return "\n".join(out) + "\n"


def moves_case(n=200_000):
    out = ["G21 G90 G17", "SetPart 100 50 5", "G0 X0 Y0 Z1", "G1 Z-1 F1000"]
    per_row = 1000
    for i in range(n):
        row, k = divmod(i, per_row)
        x = k * 0.1 if row % 2 == 0 else 100 - k * 0.1
        wobble = 0.02 * math.sin(k * 0.7)
        out.append("G1 X%.3f Y%.3f" % (x, (row % 200) * 0.25 + wobble))
    out.append("M30")
    return "\n".join(out) + "\n"


def ball_case():
    out = ["G21 G90 G17", "SetPart 50 50 10", "SetTool 1 6 50 \"ball\"", "T1 M6",
           "G0 X0 Y0 Z2", "F1500"]
    for j in range(101):
        y = j * 0.5
        xs = [i * 0.5 for i in range(101)]
        if j % 2:
            xs.reverse()
        for x in xs:
            z = -3 + 2 * math.sin(x / 8) * math.cos(y / 11)
            out.append("G1 X%.3f Y%.3f Z%.4f" % (x, y, z))
    out.append("G0 Z5")
    out.append("M30")
    return "\n".join(out) + "\n"


def memory_case():
    out = ["G20 G90 G17", "SetPart 6 6 1", "SetTool 1 0.25", "T1 M6", "G0 X0.5 Y0.5 Z0.1",
           "G1 Z-0.1 F40", "G1 X5.5", "G1 Y5.5", "G1 X0.5", "G1 Y0.5", "G0 Z0.5", "M30"]
    return "\n".join(out) + "\n"


def best(cmd, runs):
    """Best wall time of `runs` runs, and the largest peak RSS (KiB) of
    these runs alone (wait4 gives each child's own)."""
    times, peak = [], 0
    for _ in range(runs):
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        stderr = proc.stderr.read()
        _, status, usage = os.wait4(proc.pid, 0)
        times.append(time.perf_counter() - start)
        if status != 0:
            sys.exit("failed: %s\n%s" % (" ".join(cmd), stderr.decode()))
        peak = max(peak, usage.ru_maxrss)
    return min(times), peak


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ger", default="target/release/ger")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    ger = os.path.abspath(args.ger)
    with tempfile.TemporaryDirectory() as tmp:
        def run(name, text, extra=()):
            path = os.path.join(tmp, name + ".egc")
            with open(path, "w") as f:
                f.write(text)
            return best([ger, "render", path, "-o", os.path.join(tmp, name + ".png"), *extra], args.runs)

        text, travel = inch_case()
        t, _ = run("inch", text)
        print("inch:   %.3f s for %.0f in of travel: %.3f ms per inch (goal <= 0.25)"
              % (t, travel, t * 1e3 / travel))
        t, _ = run("pocket", pocket_case())
        print("pocket: %.3f s (goal <= 0.150)" % t)
        t, _ = run("moves", moves_case())
        print("moves:  %.3f s for 200,000 moves (goal <= 0.5)" % t)
        t, _ = run("ball", ball_case())
        print("ball:   %.3f s (goal <= 1)" % t)
        t, peak = run("memory", memory_case())
        print("memory: %.3f s, peak %.0f MB for 36 million cells (goal <= 200 MB)"
              % (t, peak / 1024))


if __name__ == "__main__":
    main()
