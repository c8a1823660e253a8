#!/usr/bin/env python3
"""How smooth the die-wall profiles are: the contact pressure along the die
(die-profile-ID.dat, the nodal normal force over the node's weight) for
velocity degree 1 and 2 on the same meshes, measured by the relative second
difference |p[i-1] - 2 p[i] + p[i+1]| / |p[i]| over consecutive nodes in
contact (the measure of issue 9: the Q1-P0 checkerboard makes the curve
zigzag from node to node). Prints the median and the 90th percentile per
die id and mesh, and the same for the nodes of the die face before the exit
D only (x < x_D - 1 mm, away from the singular corner).

    python3 benchmarks/die2d_profiles.py

Not a test.
"""
import os, statistics, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(ROOT, "build", "dieflow")
X_D = (19 - 4.75) / 2.7474774194546216  # die exit: (h_i - h_o) / tan(70 deg)

MESHES = {
    "the old default start (blocks, 4 across, 3 Kelly cycles, fraction 0.3)":
        "  set Corner refinements = 0\n  subsection Die2d\n    set Layout = blocks\n    set Cells across = 4\n  end\n",
    "the graded start (bisected, 8 across, 5 corner levels, 3 Kelly cycles, fraction 0.3)":
        "  set Corner refinements = 5\n  subsection Die2d\n    set Cells across = 8\n  end\n",
}


def deck(mesh, degree, output):
    return f"""set Output directory = {output}
set Write VTU = false
subsection Mesh
{mesh}end
subsection Discretisation
  set Velocity degree = {degree}
end
subsection Refinement
  set Cycles = 3
  set Strategy = adaptive
  set Indicator = kelly
  set Refine fraction = 0.3
end
"""


def second_differences(path, face_only):
    rows = [list(map(float, line.split())) for line in open(path) if line.strip() and not line.startswith("#")]
    values = []
    for i in range(1, len(rows) - 1):
        window = rows[i - 1:i + 2]
        if any(r[7] == 0 for r in window) or rows[i][3] == 0:
            continue
        if face_only and any(r[1] > X_D - 1 for r in window):
            continue
        values.append(abs(window[0][3] - 2 * window[1][3] + window[2][3]) / abs(window[1][3]))
    return values


def describe(values):
    if not values:
        return "-"
    values = sorted(values)
    return f"{statistics.median(values):.4f} / {values[int(0.9 * (len(values) - 1))]:.4f} ({len(values)} nodes)"


def main():
    print("| mesh | degree | die id 3 | die id 4 | die face of id 4, x < x_D - 1 mm |")
    print("|---|---|---|---|---|")
    for title, mesh in MESHES.items():
        for degree in (1, 2):
            with tempfile.TemporaryDirectory() as work:
                path = os.path.join(work, "deck.prm")
                with open(path, "w") as f:
                    f.write(deck(mesh, degree, os.path.join(work, "out")))
                subprocess.run([PROGRAM, path], stdout=subprocess.DEVNULL, check=True)
                profile = lambda i: os.path.join(work, "out", f"die-profile-{i}.dat")
                cells = [describe(second_differences(profile(3), False)),
                         describe(second_differences(profile(4), False)),
                         describe(second_differences(profile(4), True))]
            print(f"| {title} | {degree} | " + " | ".join(cells) + " |")
    print("\n(median / 90th percentile of the relative second difference of the contact pressure)")


if __name__ == "__main__":
    main()
