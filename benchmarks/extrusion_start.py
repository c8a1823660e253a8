#!/usr/bin/env python3
"""The start of the die2d extrusion (parameters/extrusion-start.prm) against
the steady run of the same scene: the ram force per step once the front
has left the 15 mm land (t >= 0.02 s: stroke 3.8 mm, the front 15.2 mm past
the die exit), its mean, spread and range, and the cost of the run (wall
time, steps, Newton iterations, new meshes, cells); then the steady ram
force of the same deck (Problem = steady, the 20 mm container, the whole
land, the die from the mesh) on growing meshes, degree 1 and 2: with the
land holding the metal (the domain as meshed) and with the free surface
(the metal leaves the land at the die exit; Free surface/Iterations).

Usage: benchmarks/extrusion_start.py [--program build/dieflow] [--edges 0.6,0.3]
                                     [--dt 0.0004] [--mu 0] [--steady 8,16,32] [--gmsh 0.6,0.3]"""
import argparse, math, os, shutil, subprocess, sys, tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from deck_variant import run_variant

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--program", default="build/dieflow")
parser.add_argument("--deck", default="parameters/extrusion-start.prm")
parser.add_argument("--edges", default="0.6", help="Incremental/Remesh boundary edge length (mm), one run each")
parser.add_argument("--dt", default="0.0004", help="Incremental/Time step (s)")
parser.add_argument("--mu", default="0", help="Coulomb coefficient on the die face and land (id 4)")
parser.add_argument("--steady", default="8,16,32", help="Cells across of the steady runs")
parser.add_argument("--gmsh", default="", help="Edge lengths (mm) of steady free-surface runs on Gmsh meshes")
args = parser.parse_args()

surface = os.path.abspath(os.path.join(os.path.dirname(args.deck), "die2d-die-face-land.msh"))
friction = "3: 0, 4: " + args.mu
print("extrusion start, Coulomb mu = %s on the die, dt = %s s (%s)" % (args.mu, args.dt, args.deck))
for edge in filter(None, args.edges.split(",")):
    status, summary = run_variant(args.program, args.deck,
                                  {"Remesh boundary edge length": edge, "Die surfaces": "4: " + surface, "Time step": args.dt,
                                   "Friction coefficients": friction, "Checkpoint interval": "0"})
    cycles = summary["cycles"]
    late = [c["boundary_force"]["1"][0] for c in cycles if c["step"]["time"] >= 0.02 - 1e-12]
    totals = summary["incremental"]
    print("edges <= %s mm, exit %d: %d steps, %d Newton iterations, %d new meshes, %d cells at the end, wall %.1f s, "
          "peak %.0f MB; volume change %.1e, largest penetration %.1e"
          % (edge, status, len(cycles) - 1, sum(c["nonlinear_iterations"] for c in cycles), totals["remeshings"],
             cycles[-1]["cells"], summary["wall_time"], summary["peak_memory_mb"], totals["volume_change"],
             totals["largest_penetration"]))
    if status != 0:
        print("  stopped at step %d (t = %.4f s): %s" % (cycles[-1]["step"]["step"], cycles[-1]["step"]["time"],
                                                       summary.get("failure", "see its log")))
    if late:
        mean = sum(late) / len(late)
        spread = math.sqrt(sum((f - mean) ** 2 for f in late) / len(late))
        print("  ram force over t >= 0.02 s (%d steps): mean %.0f N/mm, spread (sd) %.0f, range %.0f .. %.0f"
              % (len(late), mean, spread, min(late), max(late)))

print("steady run of the same scene (20 mm container, 15 mm land): the land held (as meshed), and free to leave")
for iterations in ("0", "40"):
    for degree in ("1", "2"):
        for cells in filter(None, args.steady.split(",")):
            if degree == "2" and int(cells) > 32:
                continue
            status, summary = run_variant(args.program, args.deck,
                                          {"Problem": "steady", "Container length": "20", "Land length": "15",
                                           "Cells across": cells, "Die surfaces": "", "Velocity degree": degree,
                                           "Friction coefficients": friction, "Iterations": iterations})
            c = summary["cycles"][-1]
            flux = c["flux"]
            line = ("  %s, degree %s, %s cells across: exit %d, %d dofs, ram force %.1f N/mm, die flux %.2f %% of the ram's"
                    % ("free surface" if iterations != "0" else "land held", degree, cells, status, c["dofs"],
                       c["boundary_force"]["1"][0], 100 * flux.get("4", 0) / flux["1"]))
            if "free_surface" in c:
                f = c["free_surface"]
                line += ", %d moves, %d free faces, settled %s, wall %.1f s" % (f["moves"], f["free_faces"], f["settled"],
                                                                             summary["wall_time"])
                if f.get("lines"):
                    main = max(f["lines"], key=lambda l: len(l["points"]))
                    line += "; leaves id %d at x %.3f, ends on id %d at x %.3f, y %.4f; grazing flux %.2f %%" % (
                        main["leaves"], main["from"][0], main["ends"], main["to"][0], main["to"][1],
                        100 * f["grazing_flux"] / -flux["1"])
            print(line)

if args.gmsh:
    if shutil.which("gmsh") is None:
        raise SystemExit("--gmsh needs the gmsh program: apt install gmsh")
    geo = os.path.join(os.path.dirname(os.path.abspath(__file__)), "die2d-uniform.geo")
    print("steady run with its free surface on Gmsh's quadrilaterals (%s)" % geo)
    with tempfile.TemporaryDirectory() as tmp:
        for edge in args.gmsh.split(","):
            mesh = os.path.join(tmp, "die2d-uniform-%s.msh" % edge)
            # Gmsh's subdivision halves its size h: edges about h / 2.
            subprocess.run(["gmsh", "-2", "-format", "msh22", "-setnumber", "h", str(2 * float(edge)), geo, "-o", mesh],
                           check=True, stdout=subprocess.DEVNULL)
            for degree in ("1", "2"):
                # The deck names no Gmsh file: the Source entry brings it along.
                status, summary = run_variant(args.program, args.deck,
                                              {"Problem": "steady", "Source": "gmsh\n  set Gmsh file = " + mesh,
                                               "Die surfaces": "", "Velocity degree": degree,
                                               "Friction coefficients": friction, "Iterations": "40"})
                c = summary["cycles"][-1]
                f = c["free_surface"]
                print("  edges about %s mm, degree %s: exit %d, %d dofs, ram force %.1f N/mm, %d moves, settled %s, wall %.1f s"
                      % (edge, degree, status, c["dofs"], c["boundary_force"]["1"][0], f["moves"], f["settled"],
                         summary["wall_time"]))
