#!/usr/bin/env python3
"""How the cell shapes decide the strength of the velocity block's
p-multigrid cycle (doc/benchmarks.md, "the die block's sheared cells").

Stokes flow (Newtonian, no contact) on structured meshes of a few shapes,
each at three sizes: every Newton system is solved with `Velocity block =
inner solve` to `Inner tolerance = 1e-6`, so each outer iteration applies
one inner CG solve of the velocity block A preconditioned by the cycle;
summary.json's inner_iterations / krylov_iterations is then the number of
cycles that take six decades off A's residual, a measure of the cycle
alone (the Schur approximation and Newton's forcing term do not enter).
A cycle whose strength does not depend on the mesh keeps it constant.

The channel meshes are written as Gmsh files (uniform squares, uniform
2:1 rectangles, a 270-degree re-entrant step, and a block tapering the
channel to half its height over 0.5 or 2 lengths, whose cells are sheared
like the die2d die block's); die2d itself runs with its dies as no-slip
walls in the two layouts of the built-in mesh.

    benchmarks/velocity_cycle_shapes.py [--program build/dieflow]
"""

import argparse, os, tempfile

from die2d_levels import machine, run_die2d


def channel_mesh(path, n, shape):
    """A channel [0, 4] x [0, 1] of n cells per unit length, its inlet x = 0
    (id 1), outlet x = 4 (id 2), wall (id 4), axis y = 0 (id 5), reshaped as
    @p shape says; written in Gmsh's 2.2 format."""
    h = 1.0 / n

    def inside(i, j):
        return not (shape == "step" and i >= 2 * n and j >= n // 2)

    def position(i, j):
        x, y = i * h, j * h
        if shape == "rectangles":
            return x, 0.5 * y
        if shape.startswith("taper"):
            length = 0.5 if shape == "taper45" else 2.0
            s = min(max((x - 2) / length, 0.0), 1.0)
            return x, y * (1 - 0.5 * s)
        return x, y

    cells = [(i, j) for i in range(4 * n) for j in range(n) if inside(i, j)]
    cell_set = set(cells)
    nodes = {}

    def node(i, j):
        return nodes.setdefault((i, j), len(nodes) + 1)

    quads = [(node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)) for i, j in cells]
    lines = []
    for i, j in cells:
        for a, b, neighbour in (((i, j), (i + 1, j), (i, j - 1)), ((i + 1, j), (i + 1, j + 1), (i + 1, j)),
                                ((i + 1, j + 1), (i, j + 1), (i, j + 1)), ((i, j + 1), (i, j), (i - 1, j))):
            if neighbour in cell_set:
                continue
            if a[0] == b[0] == 0:
                tag = 1
            elif a[0] == b[0] == 4 * n:
                tag = 2
            elif a[1] == b[1] == 0:
                tag = 5
            else:
                tag = 4
            lines.append((tag, node(*a), node(*b)))
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for (i, j), k in sorted(nodes.items(), key=lambda item: item[1]):
            f.write("%d %.12g %.12g 0\n" % ((k,) + position(i, j)))
        f.write("$EndNodes\n$Elements\n%d\n" % (len(lines) + len(quads)))
        for k, (tag, a, b) in enumerate(lines, 1):
            f.write("%d 1 2 %d %d %d %d\n" % (k, tag, tag, a, b))
        for k, q in enumerate(quads, len(lines) + 1):
            f.write("%d 3 2 0 0 %d %d %d %d\n" % ((k,) + q))
        f.write("$EndElements\n")


SOLVER = """subsection Discretisation
  set Velocity degree = 2
end
subsection Linear solver
  set Method = iterative
  set Inexact Newton = false
  set Velocity block = inner solve
  set Inner tolerance = 1e-6
end
subsection Contact
  set Die ids =
end
"""

CHANNEL = """set Dimension = 2
subsection Mesh
  set Source = gmsh
  set Gmsh file = %s
end
subsection Material
  set Law = Newtonian
  set Viscosity = 1
end
subsection Boundary conditions
  set Prescribed velocity ids = 1, 4
  set Symmetry ids = 5
  set Slip wall ids =
  set Traction free ids = 2
  subsection Prescribed velocity 1
    set Velocity = 1; 0
  end
  subsection Prescribed velocity 4
    set Velocity = 0; 0
  end
end
"""

DIE2D = """set Dimension = 2
subsection Mesh
  set Source = die2d
  subsection Die2d
    set Layout = %s
  end
end
subsection Material
  set Law = Newtonian
  set Viscosity = 0.278
end
subsection Boundary conditions
  set Symmetry ids = 5
  set Slip wall ids =
  set Traction free ids = 2
  set Prescribed velocity ids = 1, 3, 4
  subsection Prescribed velocity 1
    set Velocity = 190; 0
  end
  subsection Prescribed velocity 3
    set Velocity = 0; 0
  end
  subsection Prescribed velocity 4
    set Velocity = 0; 0
  end
end
"""


def cycles_per_solve(program, deck_text, across=1):
    """The dofs and the cycles per six decades of a run of @p deck_text
    (die2d_levels.run_die2d, which also sets the die2d mesh's Cells across:
    a deck of another mesh source does not read it), or None if it failed."""
    status, summary = run_die2d(program, deck_text + SOLVER, across)
    if status != 0:
        return None
    cycle = summary["cycles"][-1]
    counts = cycle["linear_solver"]
    return cycle["dofs"], counts["inner_iterations"] / counts["krylov_iterations"]


def print_row(label, sizes, results):
    """One table row: @p results, a (dofs, cycles) pair or None per size."""
    dofs = " / ".join("-" if r is None else str(r[0]) for r in results)
    rates = " / ".join("failed" if r is None else "%.2f" % r[1] for r in results)
    print("| %s | %s | %s | %s |" % (label, sizes, dofs, rates), flush=True)


def channel_run(program, n, shape):
    with tempfile.TemporaryDirectory() as work:
        mesh = os.path.join(work, "mesh.msh")
        channel_mesh(mesh, n, shape)
        return cycles_per_solve(program, CHANNEL % mesh)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default=os.path.join(os.path.dirname(here), "build", "dieflow"))
    args = parser.parse_args()
    print("Inner CG iterations per outer iteration (six decades of the velocity block's residual, one "
          "p-multigrid cycle per CG iteration); machine: " + machine())
    print()
    print("| mesh | sizes | dofs | cycles per six decades |")
    print("|---|---|---|---|")
    families = [("channel, squares", "squares"), ("channel, 2:1 rectangles", "rectangles"),
                ("channel with a 270-degree step", "step"), ("channel tapering over 2 (14 degrees)", "taper14"),
                ("channel tapering over 0.5 (45 degrees)", "taper45")]
    for label, shape in families:
        print_row(label, "n = 16 / 32 / 64", [channel_run(args.program, n, shape) for n in (16, 32, 64)])
    for layout in ("blocks", "bisected"):
        print_row("die2d, no-slip dies, layout " + layout, "32 / 64 / 128 across",
                  [cycles_per_solve(args.program, DIE2D % layout, across) for across in (32, 64, 128)])


if __name__ == "__main__":
    main()
