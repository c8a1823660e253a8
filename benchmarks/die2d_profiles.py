#!/usr/bin/env python3
"""How smooth the die-wall profiles are: the contact pressure along the die
(die-profile-ID.dat: "raw", the nodal normal force over the node's weight,
and "recovered", -n.sigma n of the stress averaged at the node from the
cells around it) for velocity degree 1 and 2 on the same meshes, measured by the relative second
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


COLUMNS = {"raw": 3, "recovered": 8}
# The friction stress changes sign in stick zones: its second differences
# are taken relative to the largest friction stress along the die id.
SHEAR_COLUMNS = {"raw": 4, "recovered": 9}


def second_differences(path, face_only, column, relative_to_largest=False):
    rows = [list(map(float, line.split())) for line in open(path) if line.strip() and not line.startswith("#")]
    largest = max(abs(r[column]) for r in rows)
    values = []
    for i in range(1, len(rows) - 1):
        window = rows[i - 1:i + 2]
        if any(r[7] == 0 for r in window) or (rows[i][column] == 0 and not relative_to_largest):
            continue
        if face_only and any(r[1] > X_D - 1 for r in window):
            continue
        scale = largest if relative_to_largest else abs(window[1][column])
        values.append(abs(window[0][column] - 2 * window[1][column] + window[2][column]) / scale)
    return values


def describe(values):
    if not values:
        return "-"
    values = sorted(values)
    return f"{statistics.median(values):.4f} / {values[int(0.9 * (len(values) - 1))]:.4f} ({len(values)} nodes)"


def main():
    shear_rows = []
    print("| mesh | degree | pressure | die id 3 | die id 4 | die face of id 4, x < x_D - 1 mm |")
    print("|---|---|---|---|---|---|")
    for title, mesh in MESHES.items():
        for degree in (1, 2):
            with tempfile.TemporaryDirectory() as work:
                path = os.path.join(work, "deck.prm")
                with open(path, "w") as f:
                    f.write(deck(mesh, degree, os.path.join(work, "out")))
                subprocess.run([PROGRAM, path], stdout=subprocess.DEVNULL, check=True)
                profile = lambda i: os.path.join(work, "out", f"die-profile-{i}.dat")
                for name, column in COLUMNS.items():
                    cells = [describe(second_differences(profile(3), False, column)),
                             describe(second_differences(profile(4), False, column)),
                             describe(second_differences(profile(4), True, column))]
                    print(f"| {title} | {degree} | {name} | " + " | ".join(cells) + " |")
                for name, column in SHEAR_COLUMNS.items():
                    cells = [describe(second_differences(profile(4), False, column, True)),
                             describe(second_differences(profile(4), True, column, True))]
                    shear_rows.append(f"| {title} | {degree} | {name} | " + " | ".join(cells) + " |")
    print("\n(median / 90th percentile of the relative second difference of the contact pressure)\n")
    print("| mesh | degree | friction stress | die id 4 | die face of id 4, x < x_D - 1 mm |")
    print("|---|---|---|---|---|")
    for row in shear_rows:
        print(row)
    print("\n(median / 90th percentile of the second difference of the friction stress over its largest "
          "value along die id 4)")


if __name__ == "__main__":
    main()
